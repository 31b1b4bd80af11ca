"""User-facing pipelines between the provers (hkproof.hk) and the commands: `discover` and the Darboux search of
`measure`. Each runs searches (experiments), hands every candidate to a prover, and reports what it covered."""
