"""Kernel-dimension profiles of a candidate HK-basis at a point: algorithm (N) with Theorem "Lem: dim K"."""
from __future__ import annotations

import random
import time
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import flint

from hkproof.algebra.sampling import random_rational
from hkproof.algebra.formula import split_list
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational, Ring, to_fmpq
from hkproof.dynamics.kahan import KahanMap
from hkproof.algebra.linalg import rank_q
from hkproof.errors import DependentBasisError, HKProofError, ParseError, SingularPointError
from hkproof.experiments.arithmetics import Arithmetic, ExactQ
from hkproof.experiments.scene import Scene, make_scene, point_values

__all__ = ["AMBIGUOUS", "exact_profiles", "fundamental_finite", "HK_BASIS", "IRREGULAR", "kernel_vector",
           "kernel_vectors", "KernelProfile", "NO_BASIS", "parse_basis", "ProfileProblem", "SINGULAR"]

HK_BASIS = "hk-basis"          # condition "fundamental finite" holds with d >= 1
NO_BASIS = "no-hk-basis"       # X_[0,l-1](x) has full rank: K_Phi(x) = 0
IRREGULAR = "irregular"        # ranks do not follow "fundamental finite" (special point or dependent functions)
AMBIGUOUS = "ambiguous"        # the arithmetic cannot decide some rank
SINGULAR = "singular"          # the orbit meets Delta = 0: the point is skipped


def parse_basis(ring: Ring, text: str | Sequence[str]) -> list[Frac]:
    """Phi from 'phi1, phi2, ...' (commas inside parentheses do not split) or from a list of strings."""
    parts = split_list(text, "basis") if isinstance(text, str) else [p.strip() for p in text]
    if len(parts) < 2:
        raise ParseError("a candidate HK-basis needs at least two functions")
    return [Frac.parse(ring, p) for p in parts]


def fundamental_finite(ranks: Sequence[int | None]) -> tuple[str, int | None]:
    """Verdict and d from rank X_[0,s-1], s = 1..l: condition "fundamental finite" read off the ranks.

    >>> fundamental_finite([1, 2, 3, 3]), fundamental_finite([1, 2, 2, 3])[0]
    (('hk-basis', 1), 'irregular')
    """
    l = len(ranks)
    known = [r for r in ranks if r is not None]
    if len(known) != l:
        return AMBIGUOUS, None
    d = l - known[-1]
    expected = [min(s, l - d) for s in range(1, l + 1)]
    if list(ranks) != expected:
        return IRREGULAR, None
    return (HK_BASIS, d) if d >= 1 else (NO_BASIS, 0)


@dataclass
class KernelProfile:
    """dims[s-1] = dim ker X_[0,s-1](x) for s = 1..l (None: undecided), the verdict, d and K_Phi(x)."""

    point: list[str]
    verdict: str
    dimension: int | None
    dims: list[int | None] = field(default_factory=list)
    kernel: list[list] | None = None
    certainty: dict = field(default_factory=dict)
    seconds: float = 0.0
    reason: str = ""

    def to_dict(self) -> dict:
        return {"point": self.point, "verdict": self.verdict, "dimension": self.dimension, "dims": self.dims,
                "kernel": self.kernel, "certainty": self.certainty, "seconds": round(self.seconds, 6),
                "reason": self.reason}


class ProfileProblem:
    """A candidate basis Phi for the Kahan map in one scene, compiled once for many points."""

    def __init__(self, scene: Scene, basis: Sequence[Frac]):
        ring = scene.kmap.ring
        for phi in basis:
            if phi.ring != ring:
                raise ParseError(f"{phi} is not a function on {ring}")
        self.scene = scene
        self.basis = list(basis)
        self.compiled = [scene.compile(phi) for phi in basis]
        self._check_independent()

    def _check_independent(self) -> None:
        """Phi must be linearly independent (Def. "Hirota mech"): full rank at l + 2 random points proves it."""
        arithmetic = ExactQ()
        prep = arithmetic.prepare(self.scene, self.compiled)
        rng = random.Random(len(self.basis))
        rows = []
        for _ in range(len(self.basis) + 2):
            point = [random_rational(rng, 99, zero=True) for _ in self.scene.variables]
            try:
                rows.append(arithmetic.basis_row(prep, point))
            except ZeroDivisionError:
                continue
        if not rows or rank_q(rows) < len(self.basis):
            raise DependentBasisError(
                f"the functions ({', '.join(map(str, self.basis))}) are linearly dependent at {self.scene.fixed}: "
                "drop the redundant ones (an HK-basis consists of independent functions)")

    @property
    def kmap(self) -> KahanMap:
        return self.scene.kmap

    def profile(self, point: Sequence[Rational], arithmetic: Arithmetic | None = None, *,
                with_kernel: bool = True) -> KernelProfile:
        """Algorithm (N) at one point: ranks of X_[0,s-1], the verdict of Theorem "Lem: dim K", K_Phi(x)."""
        arithmetic = arithmetic or ExactQ()
        x = point_values(self.scene, point)
        label = [str(v) for v in x]
        start = time.perf_counter()
        try:
            raw = arithmetic.profile(self.scene, self.compiled, x)
        except SingularPointError as exc:
            return KernelProfile(label, SINGULAR, None, reason=str(exc), seconds=time.perf_counter() - start,
                                 certainty={"arithmetic": arithmetic.name})
        verdict, d = fundamental_finite(raw.ranks)
        l = len(self.basis)
        kernel = None
        if with_kernel and verdict == HK_BASIS and d is not None:
            kernel = [[arithmetic.to_json(v) for v in vec] for vec in arithmetic.kernel(raw, d)]
        dims = [None if r is None else l - r for r in raw.ranks]
        return KernelProfile(label, verdict, d, dims, kernel, raw.certainty, time.perf_counter() - start)


def kernel_vector(problem: ProfileProblem, point: Sequence[Rational]) -> list[flint.fmpq] | None:
    """K_Phi(x) exactly with the last coordinate -1 when dim K_Phi(x) = 1 (recipe (B)); None otherwise."""
    return kernel_vectors([problem], point)[0]


def kernel_vectors(problems: Sequence[ProfileProblem], point: Sequence[Rational]) -> list[list[flint.fmpq] | None]:
    """`kernel_vector` for several bases of one scene at one point, the exact orbit computed once for all
    (None for every basis if the longest orbit meets a singular point)."""
    scene = problems[0].scene
    if any(p.scene is not scene for p in problems):
        raise HKProofError("kernel_vectors: the bases must be profiled in one scene (the same eps and parameters)")
    arithmetic = ExactQ()
    values = point_values(scene, point)
    longest = max(problems, key=lambda p: len(p.basis))
    try:
        orbit = arithmetic.orbit(arithmetic.prepare(scene, longest.compiled), values, len(longest.basis) - 1)
    except SingularPointError:
        return [None] * len(problems)
    out: list[list[flint.fmpq] | None] = []
    for problem in problems:
        raw = arithmetic.profile_on(scene, problem.compiled, orbit[:len(problem.basis)])
        verdict, d = fundamental_finite(raw.ranks)
        out.append(arithmetic.kernel(raw, 1)[0] if verdict == HK_BASIS and d == 1 else None)
    return out


def exact_profiles(kmap: KahanMap, basis: Sequence[Frac],
                   points: Sequence[tuple[Mapping[str, Rational], Sequence[Rational]]]) -> list[KernelProfile]:
    """Algorithm (N) over Q (Theorem "Lem: dim K") for `basis` at points given as (eps and parameters, x)."""
    out = []
    for values, x in points:
        problem = ProfileProblem(make_scene(kmap, dict(values)), basis)
        out.append(problem.profile([to_fmpq(str(v)) for v in x]))
    return out
