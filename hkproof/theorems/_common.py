"""Small helpers shared by the theorem modules: reading claimed formulas in a map's ring."""
from __future__ import annotations

from typing import Sequence

import sympy

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ParseError


def parse(kmap: KahanMap, text: str) -> Frac:
    """A claimed formula as an element of Q(x, eps, params) of the map."""
    return Frac.parse(kmap.ring, text)


def parse_matrix(kmap: KahanMap, text: str) -> list[list[Frac]]:
    """A claimed matrix written as a nested list '[[a, b], [c, d]]'."""
    try:
        rows = sympy.sympify(text, locals={n: sympy.Symbol(n) for n in kmap.ring.names})
    except (sympy.SympifyError, SyntaxError) as exc:
        raise ParseError(f"cannot read the matrix {text!r}: {exc}") from None
    if not isinstance(rows, (list, tuple)) or not all(isinstance(r, (list, tuple)) for r in rows):
        raise ParseError(f"{text!r} is not a nested list of rows")
    return [[Frac.parse(kmap.ring, e) for e in r] for r in rows]


def monomial_squares(kmap: KahanMap, names: Sequence[str]) -> list[Frac]:
    """The basis functions v^2 for the given variables (and 1 for the name '1')."""
    return [Frac(kmap.ring, 1) if n == "1" else parse(kmap, f"{n}**2") for n in names]

