"""Orchestration of proofs: the registry and graph of claims, the run's certificate cache, executors (in process,
process pool, Dask), the runner of proofs/*.py and the report. The mathematics never imports this package,
except theorem modules, which register their claims with `claim` and cite with `require_proven`."""
