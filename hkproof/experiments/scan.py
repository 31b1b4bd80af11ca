"""Algorithm (N) over many random points, in parallel through any concurrent.futures.Executor."""
from __future__ import annotations

import random
from concurrent.futures import Executor, as_completed
from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache
from typing import Mapping, Sequence

from hkproof.algebra.ring import Rational
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.experiments.choice import get_arithmetic
from hkproof.algebra.sampling import random_rationals
from hkproof.experiments.points import random_values
from hkproof.experiments.profiles import (AMBIGUOUS, HK_BASIS, IRREGULAR, NO_BASIS, SINGULAR, KernelProfile,
                                          ProfileProblem, parse_basis)
from hkproof.experiments.progress import bar
from hkproof.experiments.scene import make_scene
from hkproof.proof.certificate import Certificate, Step
from hkproof.proof.status import Status

__all__ = ["PARALLEL_MIN", "scan", "ScanResult"]

PARALLEL_MIN = 16   # fewer points than this run in the calling process (a pool's workers cost ~0.3 s to start)
CHUNK = 4           # points per task handed to an executor


def parallel_tasks(points: int, chunk: int = CHUNK) -> int:
    """How many tasks (chunks of points) `scan` hands to an executor for `points` points: none below PARALLEL_MIN.

    >>> parallel_tasks(10), parallel_tasks(16), parallel_tasks(17)
    (0, 4, 5)
    """
    return -(-points // chunk) if points >= PARALLEL_MIN else 0


@dataclass
class ScanResult:
    """Profiles of Phi at many points and the dimension d they support (None: points disagree or undecided)."""

    system: str
    basis: list[str]
    arithmetic: str
    values: dict[str, str]
    profiles: list[KernelProfile] = field(default_factory=list)

    def count(self, verdict: str) -> int:
        return sum(1 for p in self.profiles if p.verdict == verdict)

    @property
    def dimension(self) -> int | None:
        """d if every decided point gives the same d and no point is irregular; else None."""
        dims = {p.dimension for p in self.profiles if p.verdict in (HK_BASIS, NO_BASIS)}
        if len(dims) != 1 or self.count(IRREGULAR):
            return None
        return dims.pop()

    @property
    def certificate(self) -> Certificate:
        """The scan in the proof kernel's terms: one step, algorithm (N) at the points, evidence only (exact over Q,
        or approximate: modular, float, mpmath), unknown when the points disagree."""
        d = self.dimension
        status = Status.UNKNOWN if d is None else (Status.EVIDENCE_EXACT if self.arithmetic == "exact" else
                                                   Status.EVIDENCE_FLOAT)
        step = Step(f"dim K of ({', '.join(self.basis)}) at {len(self.profiles)} points",
                    f"algorithm (N): kernel profiles in {self.arithmetic} arithmetic", "Q" if self.arithmetic ==
                    "exact" else self.arithmetic, status, points=len(self.profiles),
                    detail="the points disagree or are undecided" if d is None else f"d = {d}")
        return Certificate(f"scan:{self.system}", f"algorithm (N) on a basis of {self.system}", "sec. 4, algorithm (N)",
                           f"dim K_Phi = {d} for Phi = ({', '.join(self.basis)})", [step], fixed=dict(self.values))

    @property
    def status(self) -> Status:
        """Experiments give evidence only: the certificate's status."""
        return self.certificate.status

    def to_dict(self) -> dict:
        return {"system": self.system, "basis": self.basis, "arithmetic": self.arithmetic, "values": self.values,
                "dimension": self.dimension, "status": self.status.label,
                "counts": {v: self.count(v) for v in (HK_BASIS, NO_BASIS, IRREGULAR, AMBIGUOUS, SINGULAR)},
                "points": [p.to_dict() for p in self.profiles]}


def _field_spec(field: QuadraticField) -> tuple:
    return field.name, field.variables, field.parameters, field.rhs_text, field.description, field.step


@lru_cache(maxsize=8)
def _problem(field_spec: tuple, basis: tuple[str, ...], values: tuple[tuple[str, str], ...]) -> ProfileProblem:
    kmap = kahan_map(QuadraticField(*field_spec))
    return ProfileProblem(make_scene(kmap, dict(values)), parse_basis(kmap.ring, list(basis)))


def _profile_chunk(field_spec: tuple, basis: tuple[str, ...], values: tuple[tuple[str, str], ...],
                   arithmetic: tuple, points: Sequence[Sequence[str]], with_kernel: bool) -> list[dict]:
    """Worker: profiles of a chunk of points (everything passed as plain strings, so any executor can run it)."""
    problem = _problem(field_spec, basis, values)
    ar = get_arithmetic(arithmetic[0], digits=arithmetic[1], seed=arithmetic[2])
    return [problem.profile([Fraction(v) for v in pt], ar, with_kernel=with_kernel).to_dict() for pt in points]


def scan(system: str | KahanMap, basis: str | Sequence[str], *, points: int | Sequence[Sequence[Rational]] = 10,
         values: Mapping[str, Rational] | None = None, arithmetic: str = "exact", digits: int = 50, seed: int = 0,
         executor: Executor | None = None, progress: bool | None = False, with_kernel: bool = True,
         chunk: int = CHUNK) -> ScanResult:
    """Algorithm (N): the kernel profile of Phi at `points` random points (or the given ones), eps and parameters
    fixed to `values` (missing ones drawn at random once), in the chosen arithmetic; chunks of points go to
    `executor` (a process pool, Dask's executor) when it is given and there are enough of them."""
    kmap = system if isinstance(system, KahanMap) else kahan_map(system)
    rng = random.Random(seed)
    scene_values = random_values(kmap, rng, values)
    basis_texts = tuple(str(phi) for phi in parse_basis(kmap.ring, basis))
    pts = [random_rationals(rng, len(kmap.variables)) for _ in range(points)] if isinstance(points, int) else list(points)
    str_points = [[str(Fraction(str(v))) for v in pt] for pt in pts]
    args = (_field_spec(kmap.field), basis_texts, tuple((k, str(v)) for k, v in scene_values.items()),
            (arithmetic, digits, seed))
    chunks = [str_points[i:i + chunk] for i in range(0, len(str_points), chunk)]
    results: dict[int, list[dict]] = {}
    pool = executor if parallel_tasks(len(str_points), chunk) else None
    with bar(len(str_points), "points", enabled=progress, desc="scan") as shown:
        if pool is None:
            for i, c in enumerate(chunks):
                results[i] = _profile_chunk(*args, c, with_kernel)
                shown.update(len(c))
        else:
            futures = {pool.submit(_profile_chunk, *args, c, with_kernel): i for i, c in enumerate(chunks)}
            for fut in as_completed(futures):
                results[futures[fut]] = fut.result()
                shown.update(len(results[futures[fut]]))
    profiles = [KernelProfile(**d) for i in range(len(chunks)) for d in results[i]]
    return ScanResult(kmap.field.name, list(basis_texts), get_arithmetic(arithmetic, digits=digits).name,
                      {k: str(v) for k, v in scene_values.items()}, profiles)
