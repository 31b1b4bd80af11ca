"""Phase points given by a user: exact rationals, one per variable, or a clear ParseError (never a float)."""
from __future__ import annotations

from typing import Sequence

import flint

from hkproof.algebra.formula import split_list
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.field import QuadraticField
from hkproof.errors import ParseError

__all__ = ["parse_point"]


def parse_point(field: QuadraticField, text: str | Sequence[Rational | str]) -> dict[str, flint.fmpq]:
    """A phase point 'x1, x2, ...' (comma-separated exact rationals, one per variable) as {variable: value}."""
    items: list = split_list(text, "point") if isinstance(text, str) else list(text)
    if len(items) != len(field.variables):
        raise ParseError(f"the point {text!r} has {len(items)} coordinates; {field.name} has "
                         f"{len(field.variables)} variables {list(field.variables)}")
    return {v: to_fmpq(t) for v, t in zip(field.variables, items, strict=True)}
