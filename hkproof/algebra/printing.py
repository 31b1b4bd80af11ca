"""Printing for people and notebooks, in one place: exact values as sympy objects, LaTeX through sympy (eps printed as
varepsilon), and Markdown tables for the `_repr_markdown_` of result objects.

>>> import sympy
>>> latex(sympy.Symbol("eps") ** 2 / 2)
'\\\\frac{\\\\varepsilon^{2}}{2}'
>>> print(markdown_table(["name", "status"], [["I1", "verified"], ["a|b", "x"]]))
| name | status |
| --- | --- |
| I1 | verified |
| a\\|b | x |
"""
from __future__ import annotations

import json
from typing import TYPE_CHECKING, Any, Sequence

import flint

if TYPE_CHECKING:
    import sympy

__all__ = ["latex", "markdown_table", "math", "poly_to_sympy", "SHOWN_TERMS", "sympy_rational", "to_json"]

SHOWN_TERMS = 400
"""Terms (numerator and denominator) above which the text and LaTeX reports summarize a formula instead of printing
it (a formula of the commuting so(4) flow is 29 million characters long); the JSON output prints every formula whole."""


def latex(expr: sympy.Expr) -> str:
    """LaTeX of a sympy expression, eps written as \\varepsilon (hkproof's eps is half the time step)."""
    import sympy
    return sympy.latex(expr, symbol_names={sympy.Symbol("eps"): r"\varepsilon"})


def math(expr: sympy.Expr) -> str:
    """Inline LaTeX math for Markdown, `$...$`."""
    return f"${latex(expr)}$"


def sympy_rational(q: flint.fmpq | int) -> sympy.Rational:
    """An exact rational as a sympy Rational."""
    import sympy
    q = flint.fmpq(q)
    return sympy.Rational(int(q.p), int(q.q))


def poly_to_sympy(p: flint.fmpz_mpoly) -> sympy.Expr:
    """A FLINT polynomial as a sympy expression in its context's variable names."""
    import sympy
    symbols = [sympy.Symbol(n) for n in p.context().names()]
    return sympy.Add(*[sympy.Integer(int(c)) * sympy.Mul(*[s**e for s, e in zip(symbols, m, strict=True)])
                       for m, c in p.to_dict().items()])


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """A Markdown table; a `|` inside a cell is escaped."""
    def cell(value: Any) -> str:
        return str(value).replace("|", "\\|").replace("\n", " ")
    lines = ["| " + " | ".join(map(cell, header)) + " |", "| " + " | ".join("---" for _ in header) + " |"]
    lines += ["| " + " | ".join(map(cell, row)) + " |" for row in rows]
    return "\n".join(lines)


def to_json(payload: Any, indent: int | None = None) -> str:
    """The one JSON encoder of results (commands, certificates, JSON lines): exact values (FLINT numbers and
    polynomials, fractions) as their exact text, enums by their label or value.

    >>> to_json({"c": flint.fmpq(3, 7)})
    '{"c": "3/7"}'
    """
    def exact(value: Any) -> Any:
        label = getattr(value, "label", None)
        if isinstance(label, str):
            return label
        return str(value)
    return json.dumps(payload, indent=indent, default=exact)
