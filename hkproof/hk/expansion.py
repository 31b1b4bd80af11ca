"""Exact Taylor expansions of rational functions in one variable (the step size eps), and weighted degrees."""
from __future__ import annotations

from typing import Any, Sequence

import flint

from hkproof import budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring
from hkproof.proof.certificate import Refuted

__all__ = ["coefficients_in", "even_pieces", "homogeneous_eps_pieces", "support_degrees", "support_stats", "taylor",
           "weighted_degrees"]


def coefficients_in(ring: Ring, p: flint.fmpz_mpoly, name: str) -> list[flint.fmpz_mpoly]:
    """[p_0, p_1, ...] with p = sum_k p_k name^k, each p_k free of `name` (same ring)."""
    i = ring.index(name)
    parts: dict[int, dict] = {}
    for m, c in p.to_dict().items():
        k = m[i]
        parts.setdefault(k, {})[m[:i] + (0,) + m[i + 1:]] = c
    top = max(parts, default=-1)
    return [ring.ctx.from_dict(parts.get(k, {})) for k in range(top + 1)]


def taylor(h: Frac, name: str, order: int) -> list[Frac]:
    """[c_0, ..., c_order] with h = sum c_k name^k + O(name^(order+1)); c_k exact, free of `name`.

    The denominator of h must not vanish at name = 0 (power series division by its constant term).
    """
    ring = h.ring
    a = coefficients_in(ring, h.num, name)
    b = coefficients_in(ring, h.den, name)
    if not b or b[0].is_zero():
        raise ZeroDivisionError(f"the denominator of h vanishes at {name} = 0: no Taylor expansion there")
    b0 = Frac(ring, b[0])
    out: list[Frac] = []
    for k in range(order + 1):
        acc = Frac(ring, a[k]) if k < len(a) else Frac(ring, 0)
        for j in range(1, min(k, len(b) - 1) + 1):
            if not b[j].is_zero():
                acc = acc - Frac(ring, b[j]) * out[k - j]
        out.append(acc / b0)
    return out


def weighted_degrees(ring: Ring, p: flint.fmpz_mpoly, weights: dict[str, int]) -> set[int]:
    """The set of weighted degrees sum_v weights[v] * deg_v of the terms of p (one value: weighted homogeneous)."""
    idx = [(ring.index(n), w) for n, w in weights.items()]
    return {sum(m[i] * w for i, w in idx) for m in p.monoms()}


def support_degrees(ring: Ring, p: flint.fmpz_mpoly, names: Sequence[str]) -> dict[str, Any]:
    """Degrees of p as a polynomial in `names` (coefficients in the other variables) and its number of terms, read
    without a loop over the terms: the degree in each name is FLINT's, the total degree is the degree in a new
    variable t of p(names -> t * names) (one compose with monomial images, injective on monomials, so nothing
    cancels)."""
    if p.is_zero():
        return {"degree": 0, "degrees": dict.fromkeys(names, 0), "terms": 0}
    degrees = p.degrees()
    t = "t"
    while t in ring.names:
        t += "_"
    ctx = flint.fmpz_mpoly_ctx.get((*ring.names, t), ring.ctx.ordering().name)
    gens = ctx.gens()
    images = [gens[k] * gens[-1] if n in names else gens[k] for k, n in enumerate(ring.names)]
    return {"degree": int(p.compose(*images, ctx=ctx).degrees()[-1]),
            "degrees": {n: int(degrees[ring.index(n)]) for n in names}, "terms": len(p)}


def support_stats(ring: Ring, p: flint.fmpz_mpoly, names: Sequence[str]) -> dict[str, Any]:
    """`support_degrees` and the number of distinct monomials in `names`.

    Those are read one term at a time (`monomial(i)`, about 3 microseconds a term): only the distinct monomials in
    `names` are kept, never a list of every term's exponents (for the 6.3 million terms of the Clebsch f o f's
    m1-numerator that list took 2 GB)."""
    idx = [ring.index(n) for n in names]
    first, last = min(idx), max(idx) + 1
    window = idx == list(range(first, last))
    monomial, monomials = p.monomial, set()
    for i in range(len(p)):
        if not i & 0xFFFFF:
            budget.check("reading the monomials of a large polynomial")
        m = monomial(i)
        monomials.add(m[first:last] if window else tuple(m[k] for k in idx))
    return {**support_degrees(ring, p, names), "monomials": len(monomials)}


def even_pieces(ring: Ring, p: flint.fmpz_mpoly, name: str, max_degree: int) -> list[flint.fmpz_mpoly] | None:
    """[p_0, p_2, ..., p_max] with p = sum p_2k name^2k (Prop. "prop: even"), or None if p has an odd power of
    `name` or a power above `max_degree`."""
    coeffs = coefficients_in(ring, p, name)
    if len(coeffs) > max_degree + 1 or any(not c.is_zero() for c in coeffs[1::2]):
        return None
    return [coeffs[k] if k < len(coeffs) else ring.ctx.from_dict({}) for k in range(0, max_degree + 1, 2)]


def homogeneous_eps_pieces(h: Frac, eps: str, names: Sequence[str], count: int, first_degree: int,
                           what: str) -> list[Frac]:
    """[h_0, ..., h_(count-1)] with h = sum_q eps^(2q) h_q, h_q homogeneous of degree first_degree + 2q in `names`
    and free of eps (the form of sec. 6.7, eqs. "dC A" ... "dC D", "bigint_form"); Refuted naming `what` if not."""
    r = h.ring
    if Frac(r, h.den).variables() & {eps, *names}:
        raise Refuted(f"{what} is not a polynomial in ({', '.join(names)}, {eps})")
    coeffs = coefficients_in(r, h.num, eps)
    if len(coeffs) > 2 * count - 1 or any(not c.is_zero() for c in coeffs[1::2]):
        raise Refuted(f"{what}: not a polynomial in {eps}^2 of degree {count - 1}")
    pieces = [Frac(r, coeffs[2 * q], h.den) if 2 * q < len(coeffs) else Frac(r, 0) for q in range(count)]
    for q, piece in enumerate(pieces):
        if not weighted_degrees(r, piece.num, {n: 1 for n in names}) <= {first_degree + 2 * q}:
            raise Refuted(f"{what}: the {eps}^{2 * q} piece is not homogeneous of degree {first_degree + 2 * q}")
    return pieces
