"""What a shift does to a homogeneous piece along a line (Cuyt–Lee): the t-coefficients of P_k(t z + s).

Along x = t z + s the coefficient of t^r of a rational function's numerator is sum_{k >= r} [t^r] P_k(t z + s): the
homogeneous piece P_r itself plus contributions of the higher pieces. Once those are known, their contributions are
subtracted and P_r is interpolated on its own sparse support. A sparse shift (few non-zero s_i) keeps the
contributions sparse: a term x^e gives one term for each way to lower the exponents of the shifted variables.

>>> sorted(shifted_coefficients({(2, 1): 1}, 3, [0, 5], 101).items())
[(2, {(2, 0): 5}), (3, {(2, 1): 1})]
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence

import flint

__all__ = ["shifted_coefficients"]


def shifted_coefficients(piece: Mapping[tuple[int, ...], int], degree: int, shift: Sequence[int], p: int
                         ) -> dict[int, dict[tuple[int, ...], int]]:
    """[t^r] P(t z + s) mod p for each r <= degree, as polynomials in z (homogeneous of degree r), for a homogeneous
    P of that degree given as {exponents: coefficient} (Cuyt–Lee's shift contributions): the homogeneous parts of
    P(z + s), by one FLINT composition mod p."""
    if not piece:
        return {}
    n = len(shift)
    ctx = flint.nmod_mpoly_ctx.get(tuple(f"z{i}" for i in range(n)), p, "degrevlex")  # type: ignore[call-arg, arg-type]  # flint's stubs lag the API
    poly = ctx.from_dict({e: c % p for e, c in piece.items() if c % p})
    moved = poly.compose(*[g + (s % p) if s % p else g for g, s in zip(ctx.gens(), shift, strict=True)])
    out: dict[int, dict[tuple[int, ...], int]] = {}
    for m, c in moved.to_dict().items():
        if int(c):
            out.setdefault(sum(m), {})[tuple(m)] = int(c)
    return out
