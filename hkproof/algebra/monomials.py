"""Monomials as exponent vectors: enumeration, counts, values at points and text (one home for every search).

>>> exponents_upto(2, 2)
[(2, 0), (1, 1), (0, 2), (1, 0), (0, 1), (0, 0)]
>>> count_upto(2, 2), text(("x", "y"), (2, 1))
(6, 'x**2*y')
>>> value((2, 1), [3, 5]), value_mod_p((2, 1), [3, 5], 7)
(45, 3)
"""
from __future__ import annotations

import math
from typing import Any, Sequence

__all__ = ["Exponents", "columns_mod_p", "count_upto", "exponents_of_degree", "exponents_upto", "text", "value",
           "value_mod_p"]

Exponents = tuple[int, ...]


def exponents_of_degree(n: int, degree: int) -> list[Exponents]:
    """The monomials of total degree exactly `degree` in n variables, the first variable's exponent descending."""
    if n == 0:
        return [()] if degree == 0 else []
    out: list[Exponents] = []

    def rec(prefix: Exponents, left: int) -> None:
        if len(prefix) == n - 1:
            out.append(prefix + (left,))
            return
        for e in range(left, -1, -1):
            rec(prefix + (e,), left - e)
    rec((), degree)
    return out


def exponents_upto(n: int, degree: int, *, highest_first: bool = True) -> list[Exponents]:
    """All monomials of total degree <= `degree` in n variables, by total degree (highest first by default, so that
    the constant 1 comes last: the free column of a kernel, the last element of a basis as the paper writes them)."""
    degrees = range(degree, -1, -1) if highest_first else range(degree + 1)
    return [e for d in degrees for e in exponents_of_degree(n, d)]


def count_upto(n: int, degree: int) -> int:
    """How many monomials of degree <= `degree` there are in n variables: C(n + degree, n)."""
    return math.comb(n + degree, n)


def value(e: Exponents, point: Sequence[Any]) -> Any:
    """x^e at a point (any ring: ints, fmpq, Frac); the empty product is the point's own 1."""
    out: Any = point[0] ** 0 if len(point) else 1
    for x, k in zip(point, e, strict=True):
        if k:
            out = out * x ** k
    return out


def value_mod_p(e: Exponents, point: Sequence[int], p: int) -> int:
    """x^e mod p at a point of residues."""
    v = 1
    for x, k in zip(point, e, strict=True):
        if k:
            v = v * pow(x, k, p) % p
    return v


def columns_mod_p(monomials: Sequence[Exponents], points: Sequence[Sequence[int]], p: int) -> list[list[int]]:
    """For each monomial, its values mod p at all the points: each column a smaller monomial's column times one
    coordinate's, elementwise (one product per monomial and point).

    >>> columns_mod_p([(2, 1), (0, 0)], [[3, 5], [2, 2]], 7)
    [[3, 1], [1, 1]]
    """
    coordinates = [[x[i] for x in points] for i in range(len(points[0]) if points else 0)]
    known: dict[Exponents, list[int]] = {}

    def column(e: Exponents) -> list[int]:
        out = known.get(e)
        if out is None:
            i = next((k for k, d in enumerate(e) if d), None)
            if i is None:
                out = [1 % p] * len(points)
            else:
                parent = column(e[:i] + (e[i] - 1,) + e[i + 1:])
                out = [a * b % p for a, b in zip(parent, coordinates[i], strict=True)]
            known[e] = out
        return out
    return [column(tuple(e)) for e in monomials]


def text(names: Sequence[str], e: Exponents) -> str:
    """x^e as hkproof's parser reads it ('x**2*y'; '1' for the constant)."""
    parts = [v if k == 1 else f"{v}**{k}" for v, k in zip(names, e, strict=True) if k]
    return "*".join(parts) or "1"
