"""The candidate denominators D of `poisson` (issue 38): 1, the irreducible factors (in the phase variables) of the
given polynomials, of the proven integrals' denominators and of the Darboux polynomials of `measure`, and the products
of two of them (squares included).

An exclusion "no invariant Q/D with deg Q <= d" is a theorem for any polynomial D (the invariance rows hold for every
D). Darboux polynomials (D o f = K D) are the natural candidates, and every integral's denominator is one. Their
factors are taken rather than the polynomials `measure` lists (which include powers and products: m3, m3^2, ..., or
the denominators of densities), so that the list stays small; a factor free of the phase variables is a unit of
Q(eps, params) and is dropped.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Sequence

import flint

from hkproof.algebra.fraction import poly_str

__all__ = ["Denominator", "candidate_denominators"]


@dataclass(frozen=True)
class Denominator:
    """A candidate D with the name the reports use (`1`, `F1`, `F1*F2`, `F1^2`), where its factors come from, and
    its factors with their exponents (D is evaluated and written as their product, never expanded there)."""
    name: str
    poly: flint.fmpz_mpoly
    origin: str = ""
    factors: tuple[tuple[flint.fmpz_mpoly, int], ...] = ()

    def formula(self, limit: int = 80) -> str:
        """D as text, or its degree and size when it is longer than `limit` characters."""
        text = poly_str(self.poly) if len(self.poly) <= limit // 2 else ""
        return text if text and len(text) <= limit else f"degree {self.poly.total_degree()}, {len(self.poly)} terms"

    def parts(self) -> tuple[tuple[flint.fmpz_mpoly, int], ...]:
        """The factors with exponents; D itself when none were given (a constant D has none)."""
        return self.factors or (() if self.poly.is_constant() else ((self.poly, 1),))

    def text(self) -> str:
        """D as a product of its factors, (F1)**2*(F2), which hkproof's parser reads exactly."""
        parts = self.parts()
        if len(parts) != 1 or parts[0][1] != 1:
            return "*".join(f"({poly_str(f)})" + (f"**{e}" if e > 1 else "") for f, e in parts) or "1"
        return poly_str(self.poly)


def candidate_denominators(one: flint.fmpz_mpoly, phase: Sequence[str],
                           sources: Sequence[tuple[str, flint.fmpz_mpoly]]) -> list[Denominator]:
    """1, the distinct irreducible factors F1, F2, ... of the `sources` (name, polynomial) that involve the `phase`
    variables, then their products of two; equal up to a rational factor counts once."""
    ring_names = list(one.context().names())
    indices = [ring_names.index(v) for v in phase]
    factors: list[flint.fmpz_mpoly] = []
    origins: list[list[str]] = []
    for name, poly in sources:
        if poly.is_zero():
            continue
        for factor, _ in poly.factor()[1]:
            if not any(factor.degrees()[i] for i in indices):
                continue
            key = _normal(factor)
            if key not in factors:
                factors.append(key)
                origins.append([])
            if name not in origins[factors.index(key)]:
                origins[factors.index(key)].append(name)
    singles = [Denominator(f"F{k + 1}", f, "a factor of " + ", ".join(o), ((f, 1),)) for k, (f, o) in
               enumerate(zip(factors, origins, strict=True))]
    pairs = [Denominator(f"{a.name}^2", a.poly ** 2, factors=((a.poly, 2),)) if a is b else
             Denominator(f"{a.name}*{b.name}", a.poly * b.poly, factors=((a.poly, 1), (b.poly, 1)))
             for a, b in itertools.combinations_with_replacement(singles, 2)]
    return [Denominator("1", one)] + singles + pairs


def _normal(poly: flint.fmpz_mpoly) -> flint.fmpz_mpoly:
    """The primitive part with a positive leading coefficient: D and c*D define the same class Q/D."""
    part = poly.primitive()[1]
    return -part if part.leading_coefficient() < 0 else part
