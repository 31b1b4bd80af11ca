"""Functional independence: the exact rank of a Jacobian at a rational point (full rank proves independence)."""
from __future__ import annotations

from typing import Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational
from hkproof.errors import SingularPointError

__all__ = ["derivative_at", "gradient_at", "jacobian_rank_at", "max_jacobian_rank", "sample_point"]


def jacobian_rank_at(functions: Sequence[Frac], variables: Sequence[str], point: Mapping[str, Rational]) -> int:
    """Rank over Q of (d h_i / d x_j) at a point fixing every variable of the ring."""
    rows = [gradient_at(h, variables, point) for h in functions]
    return flint.fmpq_mat(rows).rank()


def max_jacobian_rank(functions: Sequence[Frac], variables: Sequence[str],
                      points: Sequence[Mapping[str, Rational]]) -> int:
    """The largest exact Jacobian rank at the points, a proven lower bound of the generic rank (sec. 6.5,
    independence by a non-zero minor); points on a pole of some function are skipped, no functions give 0."""
    best = 0
    for point in points:
        try:
            best = max(best, jacobian_rank_at(functions, variables, point)) if functions else 0
        except SingularPointError:
            continue
    return best


def gradient_at(h: Frac, variables: Sequence[str], point: Mapping[str, Rational]) -> list[flint.fmpq]:
    """(d h / d x for x in variables) at a point, by the quotient rule on values (no symbolic gcd; fast for big
    fractions): num and den are converted to Q once and evaluated once, then their derivatives."""
    ring = h.ring
    at = ring.point(point)
    num_q, den_q = ring.to_q(h.num), ring.to_q(h.den)
    num, den = num_q(*at), den_q(*at)
    if den == 0:
        raise SingularPointError(f"the denominator of {h} vanishes at {dict(point)}")
    out = []
    for name in variables:
        i = ring.index(name)
        out.append((num_q.derivative(i)(*at) * den - num * den_q.derivative(i)(*at)) / (den * den))
    return out


def derivative_at(h: Frac, name: str, point: Mapping[str, Rational]) -> flint.fmpq:
    """d h / d name at a point (`gradient_at` for one variable)."""
    return gradient_at(h, [name], point)[0]


def sample_point(names: Sequence[str], seed: int = 1) -> dict[str, flint.fmpq]:
    """A deterministic point with small distinct rational coordinates (a 'random' point that is reproducible)."""
    primes = [3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53, 59, 61, 67]
    return {n: flint.fmpq(primes[(k + seed) % len(primes)], primes[(3 * k + 2 * seed + 1) % len(primes)] + k)
            for k, n in enumerate(names)}
