"""What a shift does to a homogeneous piece along a line (Cuyt–Lee): the t-coefficients of P_k(t z + s).

Along x = t z + s the coefficient of t^r of a rational function's numerator is sum_{k >= r} [t^r] P_k(t z + s): the
homogeneous piece P_r itself plus contributions of the higher pieces. Once those are known, their contributions are
subtracted and P_r is interpolated on its own sparse support. A sparse shift (few non-zero s_i) keeps the
contributions sparse: a term x^e gives one term for each way to lower the exponents of the shifted variables.

>>> sorted(shifted_coefficients({(2, 1): 1}, 3, [0, 5], 101).items())
[(2, {(2, 0): 5}), (3, {(2, 1): 1})]
"""
from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence

__all__ = ["shifted_coefficients"]


def shifted_coefficients(piece: Mapping[tuple[int, ...], int], degree: int, shift: Sequence[int], p: int
                         ) -> dict[int, dict[tuple[int, ...], int]]:
    """[t^r] P(t z + s) mod p for each r <= degree, as polynomials in z (homogeneous of degree r), for a homogeneous
    P of that degree given as {exponents: coefficient} (Cuyt–Lee's shift contributions; binomial expansion in the
    shifted variables only)."""
    shifted = [i for i, s in enumerate(shift) if s % p]
    out: dict[int, dict[tuple[int, ...], int]] = {}
    for e, a in piece.items():
        ranges = [range(e[i] + 1) for i in shifted]
        for lowered in itertools.product(*ranges):
            c = a
            m = list(e)
            for i, li in zip(shifted, lowered):
                if li:
                    c = c * math.comb(e[i], li) * pow(shift[i], li, p) % p
                    m[i] -= li
            if c:
                r = degree - sum(lowered)
                terms = out.setdefault(r, {})
                key = tuple(m)
                terms[key] = (terms.get(key, 0) + c) % p
    return {r: {m: c for m, c in terms.items() if c} for r, terms in out.items()}
