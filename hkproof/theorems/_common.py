"""Small helpers shared by the theorem modules: reading claimed formulas in a map's ring."""
from __future__ import annotations

from hkproof.algebra import formula
from hkproof.algebra.fraction import Frac
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.matrix_form import require_matrix_form

__all__ = ["parse", "parse_matrix", "require_matrix_form"]  # require_matrix_form: for s2 and s6c


def parse(kmap: KahanMap, text: str) -> Frac:
    """A claimed formula as an element of Q(x, eps, params) of the map."""
    return Frac.parse(kmap.ring, text)


def parse_matrix(kmap: KahanMap, text: str) -> list[list[Frac]]:
    """A claimed matrix written as a nested list '[[a, b], [c, d]]'."""
    return formula.parse_matrix(kmap.ring, text)
