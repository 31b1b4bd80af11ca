"""The Kahan map iterated on a line mod p: f^n(a + t b) as a reduced projective vector of polynomials in t.

A point X / W goes to [adj M'(X, W) b'(X, W) : det M'(X, W)], where M' = M0 W + sum_k X_k M_k and b' = b0 W + B X
are the matrix form of eq. "Kahan gen" cleared of W (as in batch_map). On the image of a line X, W are polynomials in
t of degree D, and fraction-free (Bareiss) elimination gives the new vector with every entry of degree at most n D;
cancelling the common factor in t leaves the reduced vector, whose degree is deg f^n restricted to the line. Dense
univariate arithmetic (FLINT's nmod_poly: FFT products, half-gcd) does the work, so a step to degree a hundred
thousand costs seconds (8x faster than composing the map in nmod_mpoly on a dense 5-dimensional field).
"""
from __future__ import annotations

import random
from typing import Sequence

import flint

from hkproof.dynamics.modular_map import ModularKahanMap
from hkproof.errors import ParseError

__all__ = ["Line", "LineKahanMap", "degree"]

Line = list[flint.nmod_poly]     # X_1, ..., X_n, W as polynomials in t mod p
Affine = tuple[int, tuple[tuple[int, int], ...]]   # c0 W + sum c_k X_k: (c0, ((k, c_k), ...))


class LineKahanMap:
    """The projective Kahan map mod p (eps and the parameters fixed) acting on vectors of polynomials in t."""

    def __init__(self, modmap: ModularKahanMap):
        m0, mk, b0, bmat = modmap.matrices
        self.p, self.n = modmap.p, modmap.n
        n = self.n

        def form(c0: int, cs: Sequence[int]) -> Affine:
            return c0, tuple((k, c) for k, c in enumerate(cs) if c)
        self.rows = [[form(int(m0[i, j]), [int(m[i, j]) for m in mk]) for j in range(n)]
                     + [form(int(b0[i, 0]), [int(bmat[i, k]) for k in range(n)])] for i in range(n)]

    def line(self, rng: random.Random) -> Line:
        """X = a + t b, W = 1 with a, b random mod p."""
        p = self.p
        return ([flint.nmod_poly([rng.randrange(p), rng.randrange(1, p)], p) for _ in range(self.n)]
                + [flint.nmod_poly([1], p)])

    def _affine(self, form: Affine, point: Line) -> flint.nmod_poly:
        c0, cs = form
        acc = point[-1] * c0
        for k, c in cs:
            acc += point[k] * c
        return acc

    def step(self, point: Line) -> Line:
        """[adj M' b' : det M'] at the point, by Bareiss elimination of [M' | b'] (each division exact: Sylvester's
        identity) and fraction-free back substitution; not yet reduced."""
        n = self.n
        a = [[self._affine(form, point) for form in row] for row in self.rows]
        previous: _ExactQuotient | None = None
        for k in range(n):
            pivot = next((i for i in range(k, n) if not a[i][k].is_zero()), None)
            if pivot is None:
                raise ParseError(f"det M(x) vanishes on the image of the random line mod {self.p}: the Kahan map is "
                                 "not defined there")
            a[k], a[pivot] = a[pivot], a[k]
            for i in range(k + 1, n):
                for j in range(k + 1, n + 1):
                    entry = a[k][k] * a[i][j] - a[i][k] * a[k][j]
                    a[i][j] = entry if previous is None else previous(entry)
            following = [a[i][j] for i in range(k + 1, n) for j in range(k + 1, n + 1)] if k + 2 < n else []
            previous = _ExactQuotient(a[k][k], 2 * max((int(q.degree()) for q in following), default=0))
        det = a[n - 1][n - 1]
        ys: list[flint.nmod_poly] = [det] * n
        for i in range(n - 1, -1, -1):
            acc = det * a[i][n]
            for j in range(i + 1, n):
                acc -= a[i][j] * ys[j]
            ys[i] = acc // a[i][i]
        return ys + [det]

    def reduce(self, point: Line, rng: random.Random) -> Line:
        """The vector divided by the gcd of its entries: the gcd of two random combinations (generically the same;
        a division that leaves a remainder shows it was larger, and the gcd of all entries is taken instead)."""
        p = self.p
        if all(q.is_zero() for q in point):
            raise ParseError(f"the map collapses the random line to a point mod {p} (every coordinate vanishes)")
        u, v = (sum((q * rng.randrange(1, p) for q in point), flint.nmod_poly([], p)) for _ in range(2))
        g = u.gcd(v)
        if g.degree() == 0:
            return point
        parts = [divmod(q, g) for q in point]
        if not all(r.is_zero() for _, r in parts):
            g = _gcd_of(point)
            parts = [divmod(q, g) for q in point]
        return [q for q, _ in parts]

    def next(self, point: Line, rng: random.Random) -> Line:
        """f applied to the reduced vector, reduced."""
        return self.reduce(self.step(point), rng)


class _ExactQuotient:
    """Exact division by d: where d(0) != 0, a / d is the power series a d^(-1) cut after deg a - deg d + 1 terms, one
    product once d^(-1) is known (inverted once for every dividend of degree up to `top`); floor division else."""

    def __init__(self, divisor: flint.nmod_poly, top: int):
        self.divisor, self.degree = divisor, int(divisor.degree())
        length = top - self.degree + 1
        self.inverse = divisor.inverse_series_trunc(length) if length > 0 and int(divisor[0]) else None
        self.length = length

    def __call__(self, dividend: flint.nmod_poly) -> flint.nmod_poly:
        terms = int(dividend.degree()) - self.degree + 1
        if self.inverse is None or not 0 < terms <= self.length:
            return dividend // self.divisor
        return dividend.mul_low(self.inverse, terms)


def _gcd_of(point: Line) -> flint.nmod_poly:
    g = point[0]
    for q in point[1:]:
        g = g.gcd(q)
    return g


def degree(point: Line) -> int:
    """The degree of a vector of polynomials in t: the largest degree of an entry."""
    return max(int(q.degree()) for q in point)
