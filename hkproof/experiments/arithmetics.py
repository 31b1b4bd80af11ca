"""Arithmetics for algorithm (N): orbits by solving M x~ = b, ranks of X_[0,s-1] (eq. "balance"), kernels.

This module holds the common interface and exact rational arithmetic (the reference answer); modular.py and
approximate.py hold the arithmetics that are faster and say how sure they are.
"""
from __future__ import annotations

import math
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import flint

from hkproof import budget
from hkproof.dynamics.heights import HeightGuard
from hkproof.errors import SingularPointError
from hkproof.experiments.scene import AffineEntry, CompiledPoly, Scene

__all__ = ["Arithmetic", "ExactQ", "FieldArithmetic", "free_kernel", "integer_rows", "Number", "pivot_columns",
           "Prepared", "ranks_from_pivots", "RawProfile"]

Number = Any

@dataclass
class RawProfile:
    """ranks[s-1] = rank X_[0,s-1] (None: the arithmetic cannot tell), the rows used, and how sure we are."""

    ranks: list[int | None]
    rows: list[list[Number]]
    certainty: dict = field(default_factory=dict)


class Arithmetic(ABC):
    """An arithmetic for algorithm (N): the profile of ranks at one point, and kernels of its rows."""

    name: str = ""

    @abstractmethod
    def profile(self, scene: Scene, basis: Sequence[tuple[CompiledPoly, CompiledPoly]],
                point: Sequence[flint.fmpq]) -> RawProfile:
        """Orbit x, f(x), ..., f^(l-1)(x), the matrix X_[0,l-1](x) (eq. "balance") and the ranks of its top rows."""

    @abstractmethod
    def kernel(self, raw: RawProfile, d: int) -> list[list[Number]]:
        """A basis of ker X_[0,l-d-1] normalized as the paper does: chosen last coordinates -1 (recipe (B))."""

    def to_json(self, value: Number) -> str | float:
        return str(value)


@dataclass
class Prepared:
    """A scene's matrix pieces and a compiled basis with every constant converted to one arithmetic."""

    matrix: list[list[tuple[Number, tuple[tuple[int, Number], ...]]]]
    rhs: list[tuple[Number, tuple[tuple[int, Number], ...]]]
    basis: list[tuple[tuple, tuple]]
    matrices: Any = None  # arithmetic-specific form of M0, M_k, b0, B (see ModP)
    integer_basis: Any = None  # ExactQ: the basis with integer coefficients over one denominator (IntegerPoly)


class FieldArithmetic(Arithmetic):
    """Numbers of one field, with linear solves and ranks: the orbit and X_[0,l-1] computed directly."""

    def __init__(self) -> None:
        self._prepared: dict[tuple[int, int], tuple[Scene, Sequence, Prepared]] = {}

    def prepare(self, scene: Scene, basis: Sequence[tuple[CompiledPoly, CompiledPoly]]) -> Prepared:
        """Constants converted once per scene and basis (the hot loop then only multiplies and adds)."""
        key = (id(scene), id(basis))
        hit = self._prepared.get(key)
        if hit is None or hit[0] is not scene or hit[1] is not basis:
            def affine(e: AffineEntry):
                return self.number(e[0]), tuple((k, self.number(c)) for k, c in e[1])

            def poly(p: CompiledPoly):
                return tuple((self.number(c), tuple((i, e) for i, e in enumerate(exps) if e)) for c, exps in p)

            prep = Prepared([[affine(e) for e in row] for row in scene.matrix], [affine(e) for e in scene.rhs],
                            [(poly(n), poly(d)) for n, d in basis])
            if len(self._prepared) > 16:
                self._prepared.clear()
            self._prepared[key] = hit = (scene, basis, prep)
        return hit[2]

    def profile(self, scene: Scene, basis: Sequence[tuple[CompiledPoly, CompiledPoly]],
                point: Sequence[flint.fmpq]) -> RawProfile:
        prep = self.prepare(scene, basis)
        return self.profile_on(scene, basis, self.orbit(prep, point, len(basis) - 1))

    def profile_on(self, scene: Scene, basis: Sequence[tuple[CompiledPoly, CompiledPoly]],
                   orbit: Sequence[Sequence[Number]]) -> RawProfile:
        """`profile` on a given orbit of this scene (its first l points), so that several bases share one orbit."""
        prep = self.prepare(scene, basis)
        return self.profile_rows([self.basis_row(prep, x) for x in orbit])

    def profile_rows(self, rows: list[list[Number]]) -> RawProfile:
        """The profile of given rows of X_[0,l-1] (eq. "balance"): the ranks of their top rows."""
        ranks, certainty = self.prefix_ranks(rows)
        return RawProfile(ranks, rows, {"arithmetic": self.name, **certainty})

    def orbit(self, prep: Prepared, point: Sequence[flint.fmpq], steps: int) -> list[list[Number]]:
        """The orbit in this arithmetic; SingularPointError where det M(x, eps) vanishes."""
        x = [self.number(v) for v in point]
        orbit = [x]
        watch = self.watch(steps)
        for i in range(steps):
            watch(i, x)
            try:
                x = self.step(prep, x)
            except SingularPointError as exc:
                raise type(exc)(f"step {i + 1} of the orbit: {exc}") from None
            orbit.append(x)
        return orbit

    def watch(self, steps: int) -> Callable[[int, Sequence[Number]], None]:
        """What the orbit loop checks before each step: the active budget (ExactQ also watches the heights)."""
        return lambda i, x: budget.check(f"step {i + 1} of an orbit")

    def step(self, prep: Prepared, x: Sequence[Number]) -> list[Number]:
        """x~ from M(x) x~ = b(x) (eq. "Kahan gen" in matrix form)."""
        m = [[self.affine(e, x) for e in row] for row in prep.matrix]
        return self.solve(m, [self.affine(e, x) for e in prep.rhs])

    def basis_row(self, prep: Prepared, x: Sequence[Number]) -> list[Number]:
        """(phi_1(x), ..., phi_l(x)): one row of X (eq. "balance")."""
        return [self.evaluate(num, x) / self.evaluate(den, x) for num, den in prep.basis]

    def affine(self, entry, x: Sequence[Number]) -> Number:
        value, lin = entry
        for k, c in lin:
            value = value + c * x[k]
        return value

    def evaluate(self, poly, x: Sequence[Number]) -> Number:
        total = 0
        for c, exps in poly:
            for i, e in exps:
                c = c * x[i] ** e
            total = total + c
        return total

    @abstractmethod
    def number(self, q: flint.fmpq) -> Number:
        """An exact rational in this arithmetic."""

    @abstractmethod
    def solve(self, m: list[list[Number]], b: list[Number]) -> list[Number]:
        """The solution of M x~ = b; SingularPointError if M is singular."""

    @abstractmethod
    def prefix_ranks(self, rows: list[list[Number]]) -> tuple[list[int | None], dict]:
        """rank X_[0,s-1] for s = 1..len(rows), with a statement of certainty."""


# ---- exact rationals ------------------------------------------------------------------------------
def pivot_columns(rref: Any, rank: int) -> list[int]:
    """Columns holding the pivots of a reduced row echelon form."""
    pivots, j = [], 0
    for i in range(rank):
        while rref[i, j] == 0:
            j += 1
        pivots.append(j)
    return pivots


def ranks_from_pivots(pivots: Sequence[int], nrows: int) -> list[int | None]:
    """rank of the top s rows of X = number of pivot columns < s in rref(X^T)."""
    return [sum(1 for p in pivots if p < s) for s in range(1, nrows + 1)]


def free_kernel(rref: Any, rank: int, ncols: int, entry, minus_one) -> list[list]:
    """Kernel basis from a reduced row echelon form: free columns set to -1, pivots solved (recipe (B))."""
    pivots = pivot_columns(rref, rank)
    basis = []
    for free in (j for j in range(ncols) if j not in pivots):
        v = [entry(None, None)] * ncols
        v[free] = minus_one
        for i, pj in enumerate(pivots):
            v[pj] = entry(i, free)
        basis.append(v)
    return basis


def integer_rows(rows: Sequence[Sequence[flint.fmpq]]) -> flint.fmpz_mat:
    """Each row times the lcm of its denominators: same prefix ranks and kernels, fraction-free."""
    out = []
    for row in rows:
        den = flint.fmpz(1)
        for v in row:
            den = den.lcm(v.q)
        out.append([int(v.p * (den // v.q)) for v in row])
    return flint.fmpz_mat(out)


@dataclass(frozen=True)
class IntegerPoly:
    """A compiled polynomial sum_t c_t x^e_t as (sum_t n_t x^e_t) / den with integers n_t: evaluated at x = a / D
    (integers a over one D) as sum_t n_t a^e_t D^(top - |e_t|) / (den D^top), in integers until one last quotient."""

    den: int
    top: int
    terms: tuple[tuple[flint.fmpz, tuple[tuple[int, int], ...], int], ...]  # (n_t, ((variable, exponent), ...), |e_t|)

    @classmethod
    def of(cls, poly: tuple) -> IntegerPoly:
        den = math.lcm(1, *(int(c.q) for c, _ in poly))
        terms = tuple((flint.fmpz(c.p * (den // int(c.q))), exps, sum(e for _, e in exps)) for c, exps in poly)
        return cls(den, max((k for *_, k in terms), default=0), terms)

    def numerator_at(self, a: Sequence[flint.fmpz], scale: flint.fmpz, powers: dict[tuple[int, int], flint.fmpz]
                     ) -> flint.fmpz:
        """sum_t n_t a^e_t scale^(top - |e_t|); `powers` caches a_i^e and scale^j (key (-1, j)) across calls."""
        def power(i: int, e: int) -> flint.fmpz:
            if (i, e) not in powers:
                powers[(i, e)] = (a[i] if i >= 0 else scale) ** e
            return powers[(i, e)]
        total = flint.fmpz(0)
        for n, exps, k in self.terms:
            term = n
            for i, e in exps:
                term *= power(i, e)
            total += term * power(-1, self.top - k) if k < self.top else term
        return total


class ExactQ(FieldArithmetic):
    """Exact rational arithmetic (fmpq_mat solves; ranks and kernels on fmpz_mat): the reference answer."""

    name = "exact"

    def number(self, q: flint.fmpq) -> flint.fmpq:
        return q

    def basis_row(self, prep: Prepared, x: Sequence[flint.fmpq]) -> list[flint.fmpq]:
        """(phi_1(x), ..., phi_l(x)) in integers over the common denominator of x (`IntegerPoly`): one rational
        quotient per function instead of a rational product per term."""
        if prep.integer_basis is None:
            prep.integer_basis = [(IntegerPoly.of(num), IntegerPoly.of(den)) for num, den in prep.basis]
        scale = flint.fmpz(math.lcm(*(int(v.q) for v in x)))
        a = [v.p * (scale // v.q) for v in x]
        powers: dict[tuple[int, int], flint.fmpz] = {}
        row = []
        for num, den in prep.integer_basis:
            bottom = den.numerator_at(a, scale, powers) * num.den * scale ** num.top
            if bottom == 0:
                raise ZeroDivisionError("a basis function's denominator vanishes on the orbit")
            row.append(flint.fmpq(num.numerator_at(a, scale, powers) * den.den * scale ** den.top, bottom))
        return row

    def watch(self, steps: int) -> Callable[[int, Sequence[Number]], None]:
        """Exact orbits whose heights grow exponentially are stopped before the costly steps (HeightGuard)."""
        return HeightGuard(steps).observe

    def solve(self, m: list[list[flint.fmpq]], b: list[flint.fmpq]) -> list[flint.fmpq]:
        try:
            sol = flint.fmpq_mat(m).solve(flint.fmpq_mat([[v] for v in b]))
        except ZeroDivisionError:
            raise SingularPointError("det M(x, eps) = 0 (exactly)") from None
        return [sol[i, 0] for i in range(len(b))]

    def prefix_ranks(self, rows: list[list[flint.fmpq]]) -> tuple[list[int | None], dict]:
        r, _, rank = integer_rows(rows).transpose().rref()
        return ranks_from_pivots(pivot_columns(r, rank), len(rows)), {"method": "exact rank over Q"}

    def kernel(self, raw: RawProfile, d: int) -> list[list[flint.fmpq]]:
        rows = raw.rows[:len(raw.rows[0]) - d]
        r, den, rank = integer_rows(rows).rref()
        zero = flint.fmpq(0)
        return free_kernel(r, rank, len(rows[0]),
                            lambda i, j: zero if i is None else flint.fmpq(r[i, j], den), flint.fmpq(-1))
