"""A polynomial identity R = sum_mu T_mu prod_j F_j^mu_j = 0 decided without expanding R in every variable.

Two exact reductions, each checked on the polynomials themselves:

1. **Weighted dehomogenization.** The gradings under which every T_mu and F_j is homogeneous and every summand has
   one weight are found from their exponents (and verified on every monomial). If the weights of names O form an
   invertible block, the exponents of O in a monomial of R are determined by its other exponents, so setting the
   names of O to 1 maps the monomials of R injectively: R = 0 iff R(O = 1) = 0.
2. **A unisolvent lattice.** If the total degree of R in names S is at most D and its degree in s_i at most d_i,
   the lower set A = {c in N^|S| : |c| <= D, c_i <= d_i} is unisolvent for the span of the monomials s^a, a in A
   (induction on |A|: P(0, .) lies in the span of the lower set {a in A : a_1 = 0} and vanishes on it, so it is 0
   by induction on |S|; then P = s_1 Q with Q in the span of the lower set {a - e_1 : a in A, a_1 >= 1}, vanishing
   on those points shifted by 1 in s_1, where s_1 != 0 -- the same statement with the nodes 1, 2, ... in s_1, so
   the induction runs over any distinct nodes). R = 0 iff R(S = c) = 0 in Z[rest] for every c in A. D and the d_i
   are bounded by the exponents of the T_mu and F_j; with d_i = D this is the principal lattice.

Each lattice point is a Horner evaluation in the remaining variables only (small polynomials); the specializations
are nested (one name at a time), so the big T_mu are specialized D + 1 times, not once per point. Used for the rows
with an iterate of Prop. "prop: even" (`hk.row_check`), where the expansion in every variable is the bottleneck.
"""
from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from math import comb, lcm
from typing import Mapping, Sequence, TypeVar

import flint
import numpy as np

from hkproof.algebra.linalg import nullspace_q
from hkproof.algebra.monomials import Exponents
from hkproof import budget

__all__ = ["horner", "horner_work", "LatticePlan", "plan_lattice", "vanishes_on_lattice"]

PARALLEL_POINTS = 64      # fewer lattice points are checked in this process (a fork costs more than they do)
EXACT_INT64 = 2 ** 62     # exponent sums and weighted sums below this are exact in int64 (Python integers above)
Terms = Mapping[Exponents, flint.fmpz_mpoly]
Poly = TypeVar("Poly", flint.fmpz_mpoly, flint.nmod_mpoly)


def horner(terms: Mapping[Exponents, Poly], factors: Sequence[Poly]) -> Poly:
    """sum_mu terms[mu] prod_j factors[j]^mu_j: factor out the first factor that occurs, recursively (over Z or
    modulo a prime)."""
    constant = terms.get(tuple(0 for _ in factors))
    rest = {mu: p for mu, p in terms.items() if any(mu)}
    out = constant if constant is not None else factors[0] - factors[0]
    while rest:
        j = min(k for mu in rest for k, e in enumerate(mu) if e)
        inner = {mu[:j] + (mu[j] - 1,) + mu[j + 1:]: p for mu, p in rest.items() if mu[j]}
        rest = {mu: p for mu, p in rest.items() if not mu[j]}
        out = out + factors[j] * horner(inner, factors)
    return out


def _work(mus: Sequence[Exponents], term_sizes: Sequence[int], factor_sizes: Sequence[int]) -> int:
    """Term products of Horner's scheme: each T_mu (its size) times the sizes of the factors it meets."""
    return int(sum(t * max(1, sum(int(m) * factor_sizes[j] for j, m in enumerate(mu)))
                   for mu, t in zip(mus, term_sizes, strict=True)))


def horner_work(terms: Terms, factors: Sequence[flint.fmpz_mpoly]) -> int:
    """The cost model's estimate of `horner` expanded in every variable (term products)."""
    mus = [mu for mu, p in terms.items() if not p.is_zero()]
    return _work(mus, [len(terms[mu]) for mu in mus], [len(f) for f in factors])


class _Exponents:
    """The exponent matrices of the T_mu and F_j (numpy, one row per monomial), read once. Every sum, difference and
    weighted sum of exponents below is exact: the arrays are int64 only when a bound computed with Python integers
    (the degrees of the T_mu and F_j) shows that no such value can pass 2^62, and Python integers (dtype object)
    otherwise -- int64 arithmetic wraps silently, and a grading that holds only mod 2^64 would set names to 1
    unsoundly."""

    def __init__(self, terms: Terms, factors: Sequence[flint.fmpz_mpoly]):
        self.mus = [mu for mu, p in terms.items()
                    if not p.is_zero() and not any(m and factors[j].is_zero() for j, m in enumerate(mu))]
        sizes = [sum(int(d) for d in f.degrees()) if not f.is_zero() else 0 for f in factors]
        self.bound = max((sum(int(d) for d in terms[mu].degrees()) + sum(m * sizes[j] for j, m in enumerate(mu))
                          for mu in self.mus), default=0)     # >= every exponent sum of a summand and of a T or F
        self.dtype: type = np.int64 if self.bound < EXACT_INT64 else object
        self.terms = [self._array(terms[mu]) for mu in self.mus]
        self.factors = [self._array(f) for f in factors]
        self._distinct: dict[tuple[int, ...], tuple[list[int], list[int]]] = {}

    def _array(self, p: flint.fmpz_mpoly) -> np.ndarray:
        monoms = [tuple(int(x) for x in m) for m in p.monoms()] if self.dtype is object else p.monoms()
        return np.array(monoms, dtype=self.dtype).reshape(-1, p.context().nvars())

    def top(self) -> int:
        """The largest sum of exponents of a monomial of a T_mu or F_j, plus 1 (a bound for weight arithmetic)."""
        return max((int(e.sum(axis=1).max()) for e in self.all()), default=0) + 1

    def all(self) -> list[np.ndarray]:
        return self.terms + [f for f in self.factors if len(f)]

    def summand_rows(self) -> list[np.ndarray]:
        """The exponents of the first monomial of each summand T_mu prod F_j^mu_j, minus the first summand's."""
        firsts = [t[0] + sum(m * self.factors[j][0] for j, m in enumerate(mu) if m)
                  for mu, t in zip(self.mus, self.terms, strict=True)]
        return [f - firsts[0] for f in firsts[1:]]

    def degree(self, columns: Sequence[int]) -> int:
        """A bound on the total degree of R in the names of `columns`."""
        cols = list(columns)
        if not cols:
            return 0
        t = [int(e[:, cols].sum(axis=1).max()) for e in self.terms]
        f = [int(e[:, cols].sum(axis=1).max()) if len(e) else 0 for e in self.factors]
        return max(d + sum(m * f[j] for j, m in enumerate(mu)) for mu, d in zip(self.mus, t, strict=True))

    def distinct(self, columns: Sequence[int]) -> tuple[list[int], list[int]]:
        """How many monomials each T_mu and F_j keeps when only `columns` are kept (the others specialized)."""
        key = tuple(columns)
        if key not in self._distinct:
            def count(e: np.ndarray) -> int:
                if not len(e) or not key:
                    return min(len(e), 1)
                if e.dtype == object:                        # numpy's unique has no axis for Python integers
                    return len({tuple(row) for row in e[:, key]})
                return int(np.unique(e[:, key], axis=0).shape[0])
            self._distinct[key] = ([count(e) for e in self.terms], [count(e) for e in self.factors])
        return self._distinct[key]

    def work(self, term_sizes: Sequence[int], factor_sizes: Sequence[int]) -> int:
        """A cost model of Horner's scheme: each term times the factors it meets (`horner_work`)."""
        return _work(self.mus, term_sizes, factor_sizes)


def _integer(v: Sequence[flint.fmpq]) -> list[int]:
    den = lcm(*(int(c.q) for c in v))
    return [int(c.p) * (den // int(c.q)) for c in v]


def _rank(weights: np.ndarray, columns: Sequence[int]) -> int:
    """The exact rank of the weights of some names."""
    if not len(weights) or not columns:
        return 0
    return flint.fmpz_mat([[int(x) for x in row] for row in weights[:, list(columns)]]).rank()


def _failing_row(e: np.ndarray, weights: np.ndarray) -> np.ndarray | None:
    """A difference of exponents of one polynomial that some weight vector does not annihilate, or None."""
    if len(e) < 2 or not len(weights):
        return None
    values = e @ weights.T
    bad = np.nonzero((values != values[0]).any(axis=1))[0]
    return None if not len(bad) else e[bad[0]] - e[0]


def _gradings(exponents: _Exponents, nvars: int, seed_rows: int = 32) -> np.ndarray:
    """Integer weight vectors (rows) spanning every grading under which each T_mu and F_j is homogeneous and the
    summands have one weight; found on a few exponent differences, then verified on every monomial (a difference
    that fails joins the equations)."""
    rows: list[np.ndarray] = exponents.summand_rows()
    for e in exponents.all():
        rows += list(e[1:seed_rows] - e[0])
    while True:
        basis = nullspace_q([[int(x) for x in r] for r in rows]) if rows else \
            [[flint.fmpq(int(i == j)) for i in range(nvars)] for j in range(nvars)]
        weights = np.array([_integer(v) for v in basis], dtype=object).reshape(-1, nvars)
        if exponents.dtype is not object and (
                not len(weights) or max(abs(int(w)) for w in weights.flat) * exponents.top() < EXACT_INT64):
            weights = weights.astype(np.int64)      # every e . w fits: int64 is exact (else Python integers)
        failing = [r for r in (_failing_row(e, weights) for e in exponents.all()) if r is not None]
        if not failing:
            return weights
        rows += failing


def _lower_set_size(degrees: Sequence[int], total: int) -> int:
    """The number of c in N^k with c_i <= degrees[i] and |c| <= total (inclusion-exclusion over the bounds that
    fail: c_i >= degrees[i] + 1 for i in J leaves comb(total - sum_J (degrees[i] + 1) + k, k) points)."""
    k = len(degrees)
    return sum((-1) ** len(over) * comb(total - sum(degrees[i] + 1 for i in over) + k, k)
               for size in range(k + 1) for over in combinations(range(k), size)
               if sum(degrees[i] + 1 for i in over) <= total)


@dataclass(frozen=True)
class LatticePlan:
    """Names set to 1 (justified by the gradings), names put on the lower set of total degree `degree` and degree
    `degrees[i]` in the i-th name, and the cost model's estimates for this route and for the plain expansion."""

    ones: tuple[str, ...]
    lattice: tuple[str, ...]
    degree: int
    degrees: tuple[int, ...]
    points: int
    work: int
    plain_work: int

    @property
    def cheaper(self) -> bool:
        return self.work < self.plain_work

    def describe(self) -> str:
        ones = f"{', '.join(self.ones)} = 1 by the weighted homogeneity (checked on every monomial); " if self.ones \
            else ""
        each = ", ".join(f"{d} in {n}" for n, d in zip(self.lattice, self.degrees, strict=True))
        return (f"{ones}total degree <= {self.degree} in {', '.join(self.lattice) or 'no parameter'}"
                f"{f' (degree <= {each})' if each else ''}, zero at the {self.points} points of the principal "
                "lattice cut by these degrees (a unisolvent lower set), each by Horner's scheme in the other variables")


def plan_lattice(terms: Terms, factors: Sequence[flint.fmpz_mpoly], names: Sequence[str], free: Sequence[str],
                 lattice: Sequence[str]) -> LatticePlan:
    """The cheapest choice of names of `free` to set to 1 (an invertible block of the gradings' weights) with the
    rest of `lattice` on the principal lattice; costs by `_Exponents.work`."""
    exps = _Exponents(terms, factors)
    weights = _gradings(exps, len(names))
    free_cols = [names.index(n) for n in free]
    rank = _rank(weights, free_cols)
    plain = exps.work([len(e) for e in exps.terms], [len(e) for e in exps.factors])
    best: LatticePlan | None = None
    for ones in combinations(free, rank):
        cols = [names.index(n) for n in ones]
        if _rank(weights, cols) < rank:
            continue
        on = tuple(n for n in lattice if n not in ones)
        degree = exps.degree([names.index(n) for n in on])
        degrees = tuple(min(degree, exps.degree([names.index(n)])) for n in on)
        points = _lower_set_size(degrees, degree)
        kept = [k for k, n in enumerate(names) if n not in ones and n not in on]
        work = points * exps.work(*exps.distinct(kept))
        if best is None or work < best.work:
            best = LatticePlan(tuple(ones), on, int(degree), degrees, int(points), int(work), int(plain))
    assert best is not None      # combinations(free, rank) with rank = rank of the block yields a valid choice
    return best


def vanishes_on_lattice(terms: Terms, factors: Sequence[flint.fmpz_mpoly], plan: LatticePlan, jobs: int = 1
                        ) -> tuple[bool, dict[str, int] | None]:
    """Whether R = 0, by `plan`: (True, None), or (False, a lattice point where R(point) != 0). The active budget
    is checked at every point; with jobs > 1 the values of the first lattice name are shared among `jobs` parts, forked
    children or the tasks of a spread (`Budget.call_each`, under the same deadline)."""
    ones: dict[str | int, int | flint.fmpz] = {n: 1 for n in plan.ones}
    start = {mu: p.subs(ones) if ones else p for mu, p in terms.items() if not p.is_zero()}
    moved = [f.subs(ones) if ones else f for f in factors]

    def walk(level: int, left: int, t: dict[Exponents, flint.fmpz_mpoly], f: list[flint.fmpz_mpoly],
             point: dict[str, int], values: Sequence[int]) -> dict[str, int] | None:
        if level == len(plan.lattice):
            budget.check("checking a row identity at the points of a lattice")
            return None if horner(t, f).is_zero() else point
        name = plan.lattice[level]
        for c in values:
            value: dict[str | int, int | flint.fmpz] = {name: c}
            bad = walk(level + 1, left - c, {mu: p.subs(value) for mu, p in t.items()}, [g.subs(value) for g in f],
                       {**point, name: c}, range(min([left - c, *plan.degrees[level + 1:level + 2]]) + 1))
            if bad is not None:
                return bad
        return None

    first = min([plan.degree, *plan.degrees[:1]]) + 1            # the values of the first lattice name
    jobs = min(jobs, first) if plan.lattice and plan.points >= PARALLEL_POINTS else 1

    def part(k: int) -> dict[str, int] | None:
        return walk(0, plan.degree, start, moved, {}, range(k, first, jobs))

    found = budget.current().call_each("checking a row identity on a lattice", part, jobs)
    bad = next((b for b in found if b is not None), None)
    return bad is None, bad
