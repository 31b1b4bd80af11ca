"""Linear relations among kernel coordinates written as text ('w1*e1 - w2*w3*e4 = 0'), as rows of recipe (E)."""
from __future__ import annotations

from itertools import pairwise
from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import rank_over_fraction_field
from hkproof.algebra.ring import Ring
from hkproof.errors import ParseError
from hkproof.hk.reduced import Relation

__all__ = ["parse_relation", "parse_relation_chain", "relation_rank", "same_relation"]


def parse_relation(ring: Ring, text: str, unknowns: Sequence[str]) -> Relation:
    """'lhs = rhs', linear in the unknowns with coefficients in Q(ring), as sum coef_k a_k = rhs."""
    if text.count("=") != 1:
        raise ParseError(f"a relation needs exactly one '=': {text!r}")
    lhs, rhs = text.split("=")
    big = ring.extend(unknowns)
    expr = Frac.parse(big, f"({lhs}) - ({rhs})")
    if expr.den_variables_in(unknowns):
        raise ParseError(f"the relation {text!r} is not linear in {list(unknowns)}: an unknown in a denominator")
    zero = {u: 0 for u in unknowns}
    degrees = expr.num.degrees()
    coefficients = []
    for u in unknowns:      # the numerator's derivative along u over the denominator (free of the unknowns)
        i = big.index(u)
        if degrees[i] == 0:
            coefficients.append(Frac(ring, 0))
            continue
        d = Frac(big, expr.num.derivative(i), expr.den)
        if not set(unknowns).isdisjoint(d.variables()):
            raise ParseError(f"the relation {text!r} is not linear in {list(unknowns)}")
        coefficients.append(d.specialize(zero, ring))
    constant = expr.specialize(zero, ring)
    return Relation(coefficients, -constant)


def parse_relation_chain(ring: Ring, text: str, unknowns: Sequence[str],
                         known: Mapping[str, Frac] | None = None) -> list[Relation]:
    """A printed chain 'X = Y = Z' (as in sec. 6.7, eqs. "rel18_4" ... "rel18_8") as the relations X = Y, Y = Z
    among `unknowns`; `known` functions (integrals d7, g4, ...) may appear linearly and move to the right-hand side."""
    known = dict(known or {})
    k = len(unknowns)
    out = []
    for lhs, rhs in pairwise(text.split("=")):
        rel = parse_relation(ring, f"{lhs} = {rhs}", [*unknowns, *known])
        moved = sum((c * v for c, v in zip(rel.coefficients[k:], known.values(), strict=True)), Frac(ring, 0))
        out.append(Relation(rel.coefficients[:k], rel.rhs - moved))
    return out


def same_relation(a: Relation, b: Relation) -> bool:
    """The two relations are proportional over the fraction field (rank 1 of their augmented rows)."""
    return relation_rank([a, b]) == 1


def relation_rank(relations: Sequence[Relation]) -> int:
    """Rank over the fraction field of the augmented rows (coefficients | rhs)."""
    return rank_over_fraction_field([list(r.coefficients) + [r.rhs] for r in relations])
