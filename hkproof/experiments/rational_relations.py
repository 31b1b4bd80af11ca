"""Finding rational relations h = Q(u)/P(u) among integrals, exactly at fixed parameters (evidence, not proof).

The ansatz h P(u) - Q(u) = 0, with P, Q polynomials of given degrees in named functions u_1, ..., u_k, is linear
in the coefficients of P and Q. Exact values of h and u at random rational phase points (eps and the parameters
fixed) give one row each; the null space of enough rows is the space of such relations at those parameter
values. This is how hkproof found F, J and g1 as functions of A, B, C, D (Th. "dC bases 345"); the formula, once
guessed in the parameters, is proven by an exact identity elsewhere.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import TYPE_CHECKING, Mapping, Sequence

import flint

from hkproof import budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.monomials import Exponents, exponents_upto
from hkproof.algebra.linalg import nullspace_q
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.errors import DependenceSearchError, HKProofError, SingularPointError
from hkproof.algebra.sampling import random_rational

if TYPE_CHECKING:
    import sympy

__all__ = ["DependenceSearch", "find_rational_relations", "monomials",
           "RationalRelation"]




@dataclass
class RationalRelation:
    """target * P(u) = Q(u) at the parameter values `values` (coefficients exact rationals)."""

    target: str
    names: list[str]
    denominator: dict[Exponents, flint.fmpq]
    numerator: dict[Exponents, flint.fmpq]
    values: dict[str, flint.fmpq]

    def _poly(self, coefficients: Mapping[Exponents, flint.fmpq]) -> sympy.Expr:
        import sympy
        syms = sympy.symbols(self.names)
        return sympy.Add(*[sympy.Rational(int(c.p), int(c.q)) * sympy.Mul(*[s ** e for s, e in zip(syms, m, strict=True)])
                           for m, c in coefficients.items() if c != 0])

    def text(self) -> str:
        if not any(self.denominator.values()):
            return f"{self._poly(self.numerator)} = 0"
        return f"{self.target} = ({self._poly(self.numerator)})/({self._poly(self.denominator)})"

    def to_dict(self) -> dict:
        return {"relation": self.text(), "at": {k: str(v) for k, v in self.values.items()}}


@dataclass
class DependenceSearch:
    """The relations found (modulo those among the knowns alone), and how many samples and unknowns they came
    from."""

    relations: list[RationalRelation]
    among_knowns: list[RationalRelation]   # Q(u) = 0 with P = 0: relations of the knowns alone
    unknowns: int
    samples: int

    @property
    def dimension(self) -> int:
        return len(self.relations)


def monomials(names: Sequence[str], degree: int, max_degree: Mapping[str, int] | None = None) -> list[Exponents]:
    """Exponent vectors of total degree <= degree, with optional caps per name (e.g. D <= 1 modulo a quadric)."""
    caps = [min(degree, (max_degree or {}).get(n, degree)) for n in names]
    return sorted(m for m in exponents_upto(len(names), degree) if all(e <= c for e, c in zip(m, caps, strict=True)))


def find_rational_relations(target: Frac, knowns: Mapping[str, Frac], values: Mapping[str, Rational],
                            phase: Sequence[str], *, degrees: tuple[int, int] = (1, 1),
                            max_degree: Mapping[str, int] | None = None, target_name: str = "h", extra: int = 8,
                            seed: int = 0) -> DependenceSearch:
    """Relations target * P(knowns) = Q(knowns), deg P <= degrees[0], deg Q <= degrees[1], at fixed `values` of
    eps and the parameters, from exact values at random rational points in the `phase` variables."""
    if min(degrees) < 0 or not knowns:
        raise DependenceSearchError(f"degrees {degrees} must be >= 0 and at least one known function is needed")
    names = list(knowns)
    p_mons, q_mons = monomials(names, degrees[0], max_degree), monomials(names, degrees[1], max_degree)
    unknowns = len(p_mons) + len(q_mons)
    fixed = {k: to_fmpq(v) for k, v in values.items()}
    small = target.ring.drop(fixed)
    if set(small.names) != set(phase):
        raise DependenceSearchError(f"fix eps and every parameter: {sorted(set(small.names) - set(phase))} "
                                    "have no value")
    funcs = [h.specialize(fixed, small) for h in (target, *knowns.values())]
    rng = random.Random(seed)
    rows: list[list[flint.fmpq]] = []
    tries = 0
    while len(rows) < unknowns + extra:
        budget.check("sampling values for a dependence search")
        tries += 1
        if tries > 4 * (unknowns + extra) + 20:
            raise DependenceSearchError(f"only {len(rows)} of {unknowns + extra} exact samples: the functions have "
                                        "poles at almost every random point; check the parameter values")
        point = {v: random_rational(rng) for v in phase}
        try:
            t, *u = (h.evaluate(point) for h in funcs)
        except SingularPointError:
            continue

        def value(m: Exponents) -> flint.fmpq:
            out = flint.fmpq(1)
            for x, e in zip(u, m, strict=True):
                out *= x ** e
            return out
        rows.append([t * value(m) for m in p_mons] + [-value(m) for m in q_mons])
    kernel = nullspace_q(rows)
    found: list[RationalRelation] = []
    among: list[RationalRelation] = []
    if kernel:
        # echelon form with the P coordinates first: rows with a pivot in P involve the target; the others (P = 0)
        # are relations among the knowns alone, which say nothing about the target
        echelon, rank = flint.fmpq_mat(kernel).rref()
        for i in range(rank):
            v = [echelon[i, j] for j in range(unknowns)]
            rel = RationalRelation(target_name, names, dict(zip(p_mons, v[:len(p_mons)], strict=True)),
                                   dict(zip(q_mons, v[len(p_mons):], strict=True)), fixed)
            (found if any(v[:len(p_mons)]) else among).append(rel)
    return DependenceSearch(found, among, unknowns, len(rows))
