"""Recipe (E) the paper's way: PSLQ (mpmath) on kernel coordinates at fixed rational eps and parameters,
keeping only integer relations that recur unchanged at several initial points (section 6, Remark on PSLQ)."""
from __future__ import annotations

import itertools
import random
import time
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import flint
import mpmath

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import primitive_vector, rank_q
from hkproof.algebra.ring import Rational
from hkproof.dynamics.kahan import KahanMap
from hkproof.experiments.profiles import ProfileProblem, kernel_vectors, parse_basis
from hkproof.experiments.relations import FoundRelation
from hkproof.experiments.scene import make_scene

__all__ = ["agreement", "pslq_relations", "PSLQSearch"]


@dataclass
class PSLQSearch:
    """Integer relations confirmed at every point, the ones rejected as inconsistent, and the cost.

    PSLQ runs on kernel coordinates rounded to `digits` digits (computed exactly first), so a failure at
    low precision is the precision's and not that of an inaccurate kernel."""

    names: list[str]
    digits: int
    relations: list[list[int]] = field(default_factory=list)
    rejected: int = 0
    undecided_points: int = 0
    seconds: float = 0.0

    def to_dict(self) -> dict:
        return {"columns": self.names + ["1"], "digits": self.digits, "relations": self.relations,
                "rejected": self.rejected, "undecided_points": self.undecided_points,
                "seconds": round(self.seconds, 4)}


def _real_point(kmap: KahanMap, rng: random.Random, digits: int) -> list[flint.fmpq]:
    """A random point in [-1, 1]^n with every working digit random: at a point of small height the kernel
    coordinates are rationals of small height, which satisfy many spurious integer relations."""
    bits = int(3.33 * digits) + 8
    return [flint.fmpq(rng.getrandbits(bits) - (1 << (bits - 1)), 1 << (bits - 1)) for _ in kmap.variables]


def _coordinates(problems: Sequence[ProfileProblem], point) -> list | None:
    """Kernel coordinates (last coordinate -1 dropped) of every basis at one point, exactly, then rounded to
    the working precision: the data PSLQ sees is known to exactly that many digits."""
    out = []
    for c in kernel_vectors(problems, point):
        if c is None:
            return None
        out += [mpmath.mpf(int(v.p)) / int(v.q) for v in c[:-1]]
    return out + [mpmath.mpf(1)]


def pslq_relations(kmap: KahanMap, bases: Sequence[str | Sequence[Frac]], values: Mapping[str, Rational], *,
                   names: Sequence[str] | None = None, digits: int = 50, points: int = 3, max_size: int = 4,
                   maxcoeff: int = 10**8, maxsteps: int = 10**4, seed: int = 0) -> PSLQSearch:
    """PSLQ on every subset of at most `max_size` columns (the constant 1 always included) at each point."""
    start = time.perf_counter()
    parsed = [parse_basis(kmap.ring, b) if isinstance(b, str) else list(b) for b in bases]
    scene = make_scene(kmap, values)
    problems = [ProfileProblem(scene, b) for b in parsed]
    width = sum(len(b) - 1 for b in parsed) + 1
    names = list(names) if names else [f"c{k + 1}" for k in range(width - 1)]
    search = PSLQSearch(names, digits)
    rng = random.Random(seed)
    samples: list[list] = []
    with mpmath.workdps(digits):
        while len(samples) < points and search.undecided_points < 4 * points:
            c = _coordinates(problems, _real_point(kmap, rng, digits))
            if c is None:
                search.undecided_points += 1
            else:
                samples.append(c)
    found: list[list[int]] = []
    if len(samples) < 2:
        samples = []   # one point cannot show that a relation recurs: report none
    # PSLQ itself needs >= 53 bits; the tolerance reflects the digits the coordinates were computed with
    with mpmath.workdps(max(digits, 16)):
        tol = mpmath.mpf(10) ** (-(3 * digits) // 4)
        for size in range(1, max_size if samples else 0):
            for cols in itertools.combinations(range(width - 1), size):
                cols = cols + (width - 1,)
                rels = [mpmath.pslq([s[k] for k in cols], tol=tol, maxcoeff=maxcoeff, maxsteps=maxsteps)
                        for s in samples]
                if rels[0] is None or any(r is None for r in rels):
                    continue
                vecs = {tuple(int(a) for a in primitive_vector(r)) for r in rels}
                if len(vecs) != 1:
                    search.rejected += 1
                    continue
                full = [0] * width
                for k, v in zip(cols, vecs.pop(), strict=True):
                    full[k] = v
                if rank_q(found + [full]) > len(found):
                    found.append(full)
    search.relations = found
    search.seconds = time.perf_counter() - start
    return search


def agreement(pslq: PSLQSearch, exact: Sequence[FoundRelation], values: Mapping[str, Rational]) -> tuple[int, int]:
    """(PSLQ relations lying in the exact relation space at these values, exact relations PSLQ recovers)."""
    rows = [r.row_at(values) for r in exact]
    base = rank_q(rows) if rows else 0
    right = [r for r in pslq.relations if rank_q(rows + [r]) == base]
    recovered = rank_q(right) if right else 0
    return len(right), recovered
