"""Small helpers shared by the theorem modules: reading claimed formulas in a map's ring."""
from __future__ import annotations

from hkproof.algebra import formula
from hkproof.algebra.fraction import Frac
from hkproof.dynamics.kahan import KahanMap


def parse(kmap: KahanMap, text: str) -> Frac:
    """A claimed formula as an element of Q(x, eps, params) of the map."""
    return Frac.parse(kmap.ring, text)


def parse_matrix(kmap: KahanMap, text: str) -> list[list[Frac]]:
    """A claimed matrix written as a nested list '[[a, b], [c, d]]'."""
    return formula.parse_matrix(kmap.ring, text)
