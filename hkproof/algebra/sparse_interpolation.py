"""Sparse interpolation mod p along a geometric sequence of points (Ben-Or–Tiwari with Kronecker substitution).

A polynomial F(z) = sum_m a_m z^m sampled at z_j = (c_i w_i^j)_i is the exponential sum
F(z_j) = sum_m (a_m c^m) b_m^j with bases b_m = w^m. Berlekamp–Massey finds the minimal polynomial of the sequence,
its roots are the bases, discrete logarithms of the bases read the exponents back when w_i = w^(D^i) (Kronecker
substitution, D above every partial degree) and p - 1 is smooth (Pohlig–Hellman), and a transposed Vandermonde
solve gives the coefficients. With the support known, only the last step is needed, with any prime and any w_i.

>>> rng = random.Random(1)
>>> p = smooth_prime(rng)
>>> grid = GeometricPoints.kronecker(p, 2, 4, rng)
>>> poly = {(3, 0): 5, (1, 2): p - 7, (0, 0): 2}
>>> values = [sum(a * grid.monomial_value(m, j) for m, a in poly.items()) % p for j in range(8)]
>>> sorted(ben_or_tiwari(values, grid, 3).items()) == sorted(poly.items())
True
"""
from __future__ import annotations

import itertools
import random
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import flint

from hkproof import budget
from hkproof.errors import ResourceLimitError, UnluckyPrimeError

__all__ = ["EARLY_TERMINATION", "SPLIT_ATTEMPTS", "ExponentialSum", "GeometricPoints", "ben_or_tiwari",
           "distinct_roots", "is_smooth_prime", "smooth_prime", "transposed_vandermonde"]

EARLY_TERMINATION = 2
"""Ben-Or–Tiwari stops when 2L + EARLY_TERMINATION terms of the sequence fit a recurrence of order L."""

SPLIT_ATTEMPTS = 40
"""Random splittings tried on a factor before it is declared not to split into distinct linear factors."""

SMOOTH_BOUND = 1 << 22
"""A prime suits Ben-Or–Tiwari when every prime factor of p - 1 is below this (Pohlig–Hellman stays cheap)."""


def smooth_prime(rng: random.Random, bits: int = 62) -> int:
    """A random prime of `bits` bits with p - 1 a product of primes below 2^12 (Ben-Or–Tiwari's discrete logs by
    Pohlig–Hellman then cost a few square roots of 2^12 each)."""
    while True:
        m = 2
        while m.bit_length() < bits - 12:
            q = rng.getrandbits(11) | (1 << 10) | 1
            if flint.fmpz(q).is_prime():
                m *= q
        lo, hi = ((1 << (bits - 1)) - 1) // m + 1, ((1 << bits) - 2) // m
        for _ in range(200 if lo <= hi else 0):
            k = rng.randint(lo, hi)
            if flint.fmpz(m * k + 1).is_prime():
                return m * k + 1


def is_smooth_prime(p: int) -> bool:
    """Whether p is a prime with every prime factor of p - 1 below SMOOTH_BOUND (Pohlig–Hellman is cheap)."""
    return p > 2 and bool(flint.fmpz(p).is_prime()) and all(q < SMOOTH_BOUND for q, _ in flint.fmpz(p - 1).factor())


def _primitive_root(p: int, rng: random.Random) -> int:
    """A random generator of the multiplicative group mod p."""
    factors = [int(q) for q, _ in flint.fmpz(p - 1).factor()]
    while True:
        g = rng.randrange(2, p - 1)
        if all(pow(g, (p - 1) // q, p) != 1 for q in factors):
            return g


@dataclass(frozen=True)
class GeometricPoints:
    """The points z_j = (c_i w_i^j)_i mod p: random scales c_i (a random start) and ratios w_i.

    With `kronecker`, w_i = w^(D^i) for a generator w, so the base w^m of a monomial m with partial degrees below D
    is w^K(m) with K(m) = sum m_i D^i, and a discrete logarithm gives m back."""
    p: int
    ratios: tuple[int, ...]
    scales: tuple[int, ...]
    generator: int = 0
    base: int = 0

    @classmethod
    def kronecker(cls, p: int, nvars: int, base: int, rng: random.Random) -> GeometricPoints:
        """Kronecker points for monomials of partial degrees < `base`: needs base^nvars < p - 1 and smooth p - 1."""
        if base ** nvars >= p - 1:
            raise ResourceLimitError(
                f"Kronecker substitution needs (degree + 1)^(variables - 1) = {base}^{nvars} below p - 1 = {p - 1}:"
                f" too many variables for this degree in one {p.bit_length()}-bit prime (lower max_degree or the"
                f" number of variables)")
        g = _primitive_root(p, rng)
        return cls(p, tuple(pow(g, base ** i, p) for i in range(nvars)),
                   tuple(rng.randrange(1, p) for _ in range(nvars)), g, base)

    @classmethod
    def random(cls, p: int, nvars: int, rng: random.Random) -> GeometricPoints:
        """Points with random ratios, for a known support (bases need only be distinct)."""
        return cls(p, tuple(rng.randrange(2, p - 1) for _ in range(nvars)),
                   tuple(rng.randrange(1, p) for _ in range(nvars)))

    def points(self, start: int, stop: int) -> list[list[int]]:
        """z_j for start <= j < stop."""
        p = self.p
        z = [c * pow(w, start, p) % p for c, w in zip(self.scales, self.ratios)]
        out = []
        for _ in range(start, stop):
            out.append(z)
            z = [a * w % p for a, w in zip(z, self.ratios)]
        return out

    def base_of(self, m: Sequence[int]) -> int:
        """w^m, the base of monomial m in the exponential sum."""
        v = 1
        for w, e in zip(self.ratios, m):
            if e:
                v = v * pow(w, e, self.p) % self.p
        return v

    def scale_of(self, m: Sequence[int]) -> int:
        """c^m, the factor the random start puts on the coefficient of m."""
        v = 1
        for c, e in zip(self.scales, m):
            if e:
                v = v * pow(c, e, self.p) % self.p
        return v

    def exponential_terms(self, terms: Iterable[tuple[Sequence[int], int]], top: int) -> Iterator[tuple[int, int]]:
        """(c * scale_of(m), base_of(m)) for each term (m, c) of a polynomial of partial degrees <= top, from tables
        of powers (the polynomial's values at the points z_j are the exponential sum of these pairs)."""
        p = self.p
        powers = [[pow(w, e, p) for e in range(top + 1)] for w in self.ratios]
        scales = [[pow(c, e, p) for e in range(top + 1)] for c in self.scales]
        for m, c in terms:
            base, weight = 1, c
            for e, pw, sc in zip(m, powers, scales):
                if e:
                    base, weight = base * pw[e] % p, weight * sc[e] % p
            yield weight, base

    def monomial_value(self, m: Sequence[int], j: int) -> int:
        """z_j^m."""
        return self.scale_of(m) * pow(self.base_of(m), j, self.p) % self.p

    def exponents_of(self, bases: Sequence[int], nvars: int) -> list[tuple[int, ...]] | None:
        """The monomials whose bases these are (discrete logs to the Kronecker generator); None if one is no
        monomial of partial degrees < base."""
        ctx = flint.fmpz_mod_ctx(self.p)
        g = ctx(self.generator)
        out = []
        for b in bases:
            k = int(g.discrete_log(ctx(b)))
            if k >= self.base ** nvars:
                return None
            digits = []
            for _ in range(nvars):
                k, d = divmod(k, self.base)
                digits.append(d)
            out.append(tuple(digits))
        return out


LEAVES = 4096
"""Terms of an exponential sum turned into Python polynomials at a time (the product tree works chunk by chunk)."""


def _merged(pairs: list[tuple[flint.nmod_poly, flint.nmod_poly]]) -> tuple[flint.nmod_poly, flint.nmod_poly]:
    """u/v = the sum of the fractions u_i/v_i, by pairing neighbours (a balanced tree)."""
    while len(pairs) > 1:
        nxt = [(u1 * v2 + u2 * v1, v1 * v2) for (u1, v1), (u2, v2) in zip(pairs[0::2], pairs[1::2])]
        if len(pairs) % 2:
            nxt.append(pairs[-1])
        pairs = nxt
    return pairs[0]


def _product_tree_fraction(terms: Iterable[tuple[int, int]], p: int
                           ) -> tuple[flint.nmod_poly, flint.nmod_poly, int]:
    """U/V = sum_m w_m / (1 - b_m x) for (w_m, b_m) in terms, and their number: a product tree over chunks of LEAVES
    terms, the chunks' fractions merged like a binary counter (at most one chunk of Python leaves alive at a time);
    the active budget is checked between chunks."""
    stack: list[tuple[int, flint.nmod_poly, flint.nmod_poly]] = []
    count = 0
    it = iter(terms)
    while chunk := list(itertools.islice(it, LEAVES)):
        if count:
            budget.check("summing the known pieces' values along the lines")
        count += len(chunk)
        u, v = _merged([(flint.nmod_poly([w % p], p), flint.nmod_poly([1, (-b) % p], p)) for w, b in chunk])
        level = 0
        while stack and stack[-1][0] == level:
            _, u2, v2 = stack.pop()
            (u, v), level = _merged([(u2, v2), (u, v)]), level + 1
        stack.append((level, u, v))
    if not stack:
        return flint.nmod_poly([], p), flint.nmod_poly([1], p), 0
    return (*_merged([(u, v) for _, u, v in stack]), count)


class ExponentialSum:
    """The sequence s_j = sum_m w_m b_m^j mod p, evaluated for a range of j as a power series U/V (product tree)."""

    def __init__(self, terms: Iterable[tuple[int, int]], p: int):
        """From the pairs (weight w_m, base b_m), read once (a generator keeps memory to one chunk of leaves);
        the active budget is checked between chunks."""
        self.p = p
        self._u, self._v, self.terms = _product_tree_fraction(terms, p)
        self._cache: list[int] = []

    def values(self, start: int, stop: int) -> list[int]:
        """s_j for start <= j < stop."""
        if stop > len(self._cache):
            n = max(stop, 2 * len(self._cache), 16)
            series = self._u.mul_low(self._v.inverse_series_trunc(n), n)
            coeffs = [int(c) for c in series.coeffs()]
            self._cache = coeffs + [0] * (n - len(coeffs))
        return self._cache[start:stop]


def distinct_roots(poly: flint.fmpz_mod_poly, p: int, rng: random.Random) -> list[int] | None:
    """The roots of a polynomial that splits into distinct non-zero linear factors mod p (equal-degree splitting,
    Cantor–Zassenhaus: gcd with (x + a)^((p-1)/2) - 1 for random a), None when it does not (a factor that resists
    SPLIT_ATTEMPTS random splittings is taken to be irreducible or repeated); the active budget is checked between splits."""
    f = flint.nmod_poly([int(c) for c in poly.coeffs()], p)
    if f.degree() <= 0:
        return []
    if int(f.coeffs()[0]) == 0:
        return None
    out: list[int] = []
    stack = [f]
    while stack:
        g = stack.pop()
        if g.degree() == 1:
            c0, c1 = (int(c) for c in g.coeffs())
            out.append(-c0 * pow(c1, -1, p) % p)
            continue
        budget.check("splitting the minimal polynomial of a sparse sequence")
        for _ in range(SPLIT_ATTEMPTS):
            h = flint.nmod_poly([rng.randrange(p), 1], p).pow_mod((p - 1) // 2, g) - 1
            a = g.gcd(h)
            if 0 < a.degree() < g.degree():
                stack += [a, g // a]
                break
        else:
            return None
    return out if len(set(out)) == len(out) else None      # a repeated root ends up in two factors


def transposed_vandermonde(bases: Sequence[int], values: Sequence[int], p: int) -> list[int]:
    """The weights w with sum_m w_m b_m^j = values[j] for j < len(bases) (distinct non-zero bases): with
    L = prod (x - b_m) and N = (sum_j values[j] x^j) * reverse(L) mod x^T, w_m = reverse(N)(b_m) / L'(b_m)."""
    t = len(bases)
    if t == 0:
        return []
    ctx = flint.fmpz_mod_poly_ctx(p)
    layer = [ctx([-b, 1]) for b in bases]
    while len(layer) > 1:
        layer = [a * b for a, b in zip(layer[0::2], layer[1::2])] + ([layer[-1]] if len(layer) % 2 else [])
    lam = layer[0]
    num = ctx(list(values[:t])).mul_low(lam.reverse(), t)
    tops: list[Any] = num.reverse(degree=t - 1).multipoint_evaluate(list(bases)) if num.length() else [0] * t
    bottoms = lam.derivative().multipoint_evaluate(list(bases))
    return [int(a) * pow(int(b), -1, p) % p for a, b in zip(tops, bottoms)]


def ben_or_tiwari(values: Sequence[int], grid: GeometricPoints, degree: int,
                  rng: random.Random | None = None
                  ) -> dict[tuple[int, ...], int] | None:
    """The polynomial of total degree <= `degree` whose values at grid.points(0, len(values)) these are
    (Ben-Or–Tiwari); None while the sequence is too short to have terminated (len < 2L + EARLY_TERMINATION).

    Raises UnluckyPrimeError when the recurrence has no valid monomial roots (an unlucky prime or point set)."""
    p = grid.p
    ctx = flint.fmpz_mod_poly_ctx(p)
    lam = ctx.minpoly(list(values))
    order = lam.degree()
    if len(values) < 2 * order + EARLY_TERMINATION:
        return None
    roots = distinct_roots(lam, p, rng or random.Random(order))
    nvars = len(grid.ratios)
    monomials = None if roots is None else grid.exponents_of(roots, nvars)
    if roots is None or monomials is None or any(sum(m) > degree for m in monomials):
        raise UnluckyPrimeError(f"the sequence of a degree-{degree} piece fits a recurrence of order {order} whose "
                                f"roots are not monomials of degree <= {degree} mod p = {p}")
    weights = transposed_vandermonde(roots, values, p)
    out = {}
    for m, w in zip(monomials, weights):
        a = w * pow(grid.scale_of(m), -1, p) % p
        if a == 0:
            raise UnluckyPrimeError(f"a zero coefficient in a Ben-Or–Tiwari solve mod p = {p}")
        out[m] = a
    return out
