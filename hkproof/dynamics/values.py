"""Exact values given by a user (eps, parameters, points): rationals or a clear ParseError, never a float."""
from __future__ import annotations

from typing import Mapping, Sequence

import flint

from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.field import EPS, QuadraticField
from hkproof.errors import ParseError


def exact(value: Rational | str, what: str = "value") -> flint.fmpq:
    """An exact rational from an int, fraction or a string such as '-3/7' or '0.25'; anything else is refused."""
    try:
        return to_fmpq(value.strip() if isinstance(value, str) else value)
    except (ValueError, ZeroDivisionError):
        raise ParseError(f"the {what} {value!r} is not an exact rational number (write e.g. 3, -1/2 or 0.25)") from None


def exact_values(field: QuadraticField, values: Mapping[str, Rational | str]) -> dict[str, flint.fmpq]:
    """eps and parameter values, each checked to be a name of the system and an exact rational."""
    names = (EPS,) + field.parameters
    unknown = sorted(set(values) - set(names))
    if unknown:
        raise ParseError(f"{unknown} are not eps or parameters of {field.name} ({list(names)})")
    return {k: exact(v, f"value of {k}") for k, v in values.items()}


def parse_point(field: QuadraticField, text: str | Sequence[Rational | str]) -> dict[str, flint.fmpq]:
    """A phase point 'x1, x2, ...' (comma-separated exact rationals, one per variable) as {variable: value}."""
    items = [t for t in text.split(",")] if isinstance(text, str) else list(text)
    if len(items) != len(field.variables):
        raise ParseError(f"the point {text!r} has {len(items)} coordinates; {field.name} has "
                         f"{len(field.variables)} variables {list(field.variables)}")
    return {v: exact(t, f"coordinate {v}") for v, t in zip(field.variables, items)}
