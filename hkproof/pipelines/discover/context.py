"""What every stage of `discover` reads: the maps, the scaling weights, the names sampled, the budget, the clock."""
from __future__ import annotations

import random
from dataclasses import dataclass, field

import flint

from hkproof.budget import Budget
from hkproof.dynamics.kahan import KahanMap
from hkproof.experiments.weights import Weights
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
    caches: dict = field(default_factory=dict)

    @property
    def inner(self) -> list[str]:
        """The phase variables of the searched map."""
        return list(self.kmap.variables)
