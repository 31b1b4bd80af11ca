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
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.algebra.linalg import rank_q
from hkproof.errors import DependentBasisError, HKProofError, ParseError, SingularPointError
from hkproof.experiments.arithmetics import Arithmetic, ExactQ
from hkproof.experiments.scene import Scene, make_scene, point_values

__all__ = ["AMBIGUOUS", "BasisFamily", "exact_profiles", "fundamental_finite", "HK_BASIS", "IRREGULAR", "kernel_vector",
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
    """K_Phi exactly with the last coordinate -1 when its dimension is 1 (recipe (B)), on the orbit through x
    (`BasisFamily.kernel_vectors`); None otherwise."""
    return kernel_vectors([problem], point)[0]


def kernel_vectors(problems: Sequence[ProfileProblem], point: Sequence[Rational]) -> list[list[flint.fmpq] | None]:
    """`kernel_vector` for several bases of one scene at one point, the exact orbit computed once for all
    (None for every basis if the longest orbit meets a singular point)."""
    return BasisFamily(problems).kernel_vectors(point)


class BasisFamily:
    """Several bases of one scene profiled on one exact orbit (recipe (B) for each), every function they share
    evaluated once per orbit point: build it once and call `kernel_vectors` at many points."""

    def __init__(self, problems: Sequence[ProfileProblem]):
        self.scene = problems[0].scene
        if any(p.scene is not self.scene for p in problems):
            raise HKProofError("kernel_vectors: the bases must be profiled in one scene (the same eps and parameters)")
        self.problems = list(problems)
        index: dict[tuple, int] = {}
        self.columns = [[index.setdefault(fn, len(index)) for fn in p.compiled] for p in problems]
        self.functions = sorted(index, key=index.__getitem__)
        self.arithmetic = ExactQ()
        steps = max(len(cols) for cols in self.columns) - 1
        kmap = self.scene.kmap
        self.back = steps // 2 if kmap.equations_reversible() else 0
        self.forward = steps - self.back
        backward_scene = make_scene(kmap, {**self.scene.fixed, EPS: -self.scene.fixed[EPS]}) if self.back \
            else self.scene
        self.prep = self.arithmetic.prepare(self.scene, self.functions)
        self.backward_prep = self.arithmetic.prepare(backward_scene, self.functions)

    def kernel_vectors(self, point: Sequence[Rational]) -> list[list[flint.fmpq] | None]:
        """K_Phi of each basis with last coordinate -1 where dim K_Phi = 1, else None, on the window
        f^-m(x), ..., f^(l-1-m)(x) of the orbit through x, m = (l - 1) // 2 (f^-1(x, eps) = f(x, -eps)): an
        HK-basis with d = 1 has the same kernel at every point of an orbit, and the heights of the window's
        points (growing with |i|) are about those of half as many steps."""
        x = point_values(self.scene, point)
        try:
            behind = self.arithmetic.orbit(self.backward_prep, x, self.back)
            orbit = behind[:0:-1] + self.arithmetic.orbit(self.prep, x, self.forward)
        except SingularPointError:
            return [None] * len(self.columns)
        values = [self.arithmetic.basis_row(self.prep, y) for y in orbit]
        out: list[list[flint.fmpq] | None] = []
        for cols in self.columns:
            raw = self.arithmetic.profile_rows([[row[c] for c in cols] for row in values[:len(cols)]])
            verdict, d = fundamental_finite(raw.ranks)
            out.append(self.arithmetic.kernel(raw, 1)[0] if verdict == HK_BASIS and d == 1 else None)
        return out


def exact_profiles(kmap: KahanMap, basis: Sequence[Frac],
                   points: Sequence[tuple[Mapping[str, Rational], Sequence[Rational]]]) -> list[KernelProfile]:
    """Algorithm (N) over Q (Theorem "Lem: dim K") for `basis` at points given as (eps and parameters, x)."""
    out = []
    for values, x in points:
        problem = ProfileProblem(make_scene(kmap, dict(values)), basis)
        out.append(problem.profile([to_fmpq(str(v)) for v in x]))
    return out
