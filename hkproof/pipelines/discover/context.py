"""What every stage of `discover` reads: the maps, the scaling weights, the names sampled, the budget, the clock."""
from __future__ import annotations

import random
from dataclasses import dataclass

import flint

from hkproof.algebra.reconstruction import Mapper
from hkproof.budget import Budget
from hkproof.dynamics.kahan import KahanMap
from hkproof.dynamics.field import EPS
from hkproof.experiments.weights import Weights, scaling_weights
from hkproof.pipelines.stages import Stages

__all__ = ["SearchContext"]


@dataclass
class SearchContext:
    """One search: `kmap` is the map searched (conserved coordinates made parameters), `full_map` the system's own
    map (where integrals are proven); `free` are eps and the parameters that weighted homogeneity does not
    normalize; `fixed` the values the user fixed (results then verified(specialized))."""

    kmap: KahanMap
    full_map: KahanMap
    weights: Weights
    free: list[str]
    fixed: dict[str, flint.fmpq]
    rng: random.Random
    budget: Budget
    stages: Stages
    max_degree: int = 16
    max_unknowns: int = 2500
    mapper: Mapper | None = None        # where batches of probes run (a process pool, Dask); None: in this process
    symmetries: bool = True             # step 5d carries members of a group by symmetries of the field
    hamiltonian: bool = True            # the modified Hamiltonian of F = J grad H is seeded before the search

    @classmethod
    def for_maps(cls, kmap: KahanMap, full_map: KahanMap | None = None, *, fixed: dict[str, flint.fmpq] | None = None,
                 seed: int = 0, budget: Budget | None = None, stages: Stages | None = None, max_degree: int = 16,
                 max_unknowns: int = 2500, mapper: Mapper | None = None, symmetries: bool = True,
                 hamiltonian: bool = True) -> "SearchContext":
        """A search of `kmap` (the weights from its scaling symmetry; eps and the parameters they leave free)."""
        weights = scaling_weights(kmap)
        free = [m for m in (EPS,) + tuple(kmap.field.parameters) if m not in weights.normalized]
        return cls(kmap, full_map or kmap, weights, free, dict(fixed or {}), random.Random(seed),
                   budget or Budget(None), stages or Stages("discover"), max_degree, max_unknowns, mapper=mapper,
                   symmetries=symmetries, hamiltonian=hamiltonian)

    @property
    def inner(self) -> list[str]:
        """The phase variables of the searched map."""
        return list(self.kmap.variables)
