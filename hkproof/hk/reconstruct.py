"""Rational function reconstruction from exact values: h = P/Q with P, Q of bounded total degree (dense ansatz).

The integrals of an HK-basis are kernel coordinates c_k(x) (paper, eq. "smaller system"), known only through
exact values at rational points. The ansatz h Q(v) - P(v) = 0, with P and Q spanned by the monomials of total
degree <= e in the variables v, is linear in their coefficients; each exact sample gives one row. The smallest e
with a non-zero null space gives h in lowest terms (a larger e would give the multiples k (P, Q)). Ranks are first
taken modulo a prime (a null space mod p of dimension 0 proves there is none over Q either), the null space is
then found exactly, and the result is checked at fresh samples. Weighted homogeneity (scaling symmetries of the
Kahan map) lets names be set to 1 while sampling; `restore_weights` puts them back exactly.
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from typing import Callable, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring

Point = dict[str, flint.fmpq]
# sample(outer values, inner points) -> the function's value at each point (None where it is undefined)
Sampler = Callable[[Point, list[Point]], list["flint.fmpq | None"]]
PRIME = 2**61 - 1


@dataclass
class Reconstruction:
    """h = P/Q over `ring`, or None with the reason; the degree bound used and the number of exact samples."""

    frac: Frac | None
    degree: int | None
    samples: int
    checks: int = 0
    notes: list[str] = field(default_factory=list)


def monomials_upto(count: int, degree: int) -> list[tuple[int, ...]]:
    """Exponent vectors in `count` variables of total degree <= degree, highest degree first."""
    out: list[tuple[int, ...]] = []

    def rec(prefix: tuple[int, ...], left: int) -> None:
        if len(prefix) == count - 1:
            out.append(prefix + (left,))
            return
        for e in range(left, -1, -1):
            rec(prefix + (e,), left - e)
    for total in range(degree, -1, -1):
        if count == 0:
            if total == 0:
                out.append(())
            continue
        rec((), total)
    return out


def _value(exps: Sequence[int], point: Sequence[flint.fmpq]) -> flint.fmpq:
    v = flint.fmpq(1)
    for x, e in zip(point, exps):
        if e:
            v *= x ** e
    return v


def _mod(q: flint.fmpq, p: int) -> int | None:
    den = int(q.q) % p
    return None if den == 0 else int(q.p) * pow(den, -1, p) % p


class _Samples:
    """Exact samples (variable values, function value), drawn on a grid: few outer values, many inner points."""

    def __init__(self, sample: Sampler, outer: Sequence[str], inner: Sequence[str], rng: random.Random, size: int):
        self.sample, self.outer, self.inner, self.rng, self.size = sample, list(outer), list(inner), rng, size
        self.rows: list[tuple[list[flint.fmpq], flint.fmpq]] = []
        self.failures = 0

    def _rational(self) -> flint.fmpq:
        while True:
            a = self.rng.randint(-self.size, self.size)
            if a:
                return flint.fmpq(a, self.rng.randint(1, self.size))

    def extend(self, wanted: int, outer_draws: int) -> None:
        """At least `wanted` samples in all, spread over `outer_draws` random outer values."""
        per = max(1, math.ceil((wanted - len(self.rows)) / max(outer_draws, 1)))
        while len(self.rows) < wanted:
            if self.failures > 4 * wanted + 40:
                raise ArithmeticError(f"only {len(self.rows)} of {wanted} samples: the function is undefined at "
                                      "almost every random point")
            outer = {n: self._rational() for n in self.outer}
            pts = [{n: self._rational() for n in self.inner} for _ in range(per)]
            for pt, v in zip(pts, self.sample(outer, pts)):
                if v is None:
                    self.failures += 1
                    continue
                self.rows.append(([outer[n] for n in self.outer] + [pt[n] for n in self.inner], v))


def reconstruct_rational(ring: Ring, outer: Sequence[str], inner: Sequence[str], sample: Sampler, *,
                         max_degree: int = 8, max_unknowns: int = 2500, checks: int = 4, seed: int = 0,
                         size: int = 30) -> Reconstruction:
    """h = P/Q in the variables outer + inner (names of `ring`) from exact values: rising total degree e of P and
    Q until the ansatz h Q - P = 0 has a null space; the answer is checked at `checks` fresh samples."""
    names = list(outer) + list(inner)
    samples = _Samples(sample, outer, inner, random.Random(seed), size)
    result = Reconstruction(None, None, 0)
    for e in range(0, max_degree + 1):
        monos = monomials_upto(len(names), e)
        unknowns = 2 * len(monos)
        if unknowns > max_unknowns:
            result.notes.append(f"no P/Q of total degree <= {e - 1} fits; degree {e} needs {unknowns} unknowns "
                                f"(more than {max_unknowns})")
            break
        outer_draws = len(monomials_upto(len(outer), e)) + 2 if outer else 1
        samples.extend(unknowns + 6, outer_draws)
        vals = [[_value(m, pt) for m in monos] for pt, _ in samples.rows]
        if not _has_kernel_mod_p(vals, [v for _, v in samples.rows]):
            continue
        vec = _exact_kernel_vector(vals, [v for _, v in samples.rows])
        if vec is None:
            continue
        h = _as_frac(ring, names, monos, vec)
        fresh = _Samples(sample, outer, inner, random.Random(seed + 7919 * (e + 1)), size)
        fresh.extend(checks, checks)
        ok = all(_agrees(h, names, pt, v) for pt, v in fresh.rows)
        result.samples = len(samples.rows) + len(fresh.rows)
        if ok:
            result.frac, result.degree, result.checks = h, e, len(fresh.rows)
            return result
        result.notes.append(f"degree {e}: the interpolant failed a fresh check")
    else:
        result.notes.append(f"no P/Q of total degree <= {max_degree} fits the samples")
    result.samples = len(samples.rows)
    return result


def _rows_mod_p(vals: list[list[flint.fmpq]], hs: list[flint.fmpq], p: int) -> list[list[int]] | None:
    rows = []
    for mv, h in zip(vals, hs):
        hm = _mod(h, p)
        row = [_mod(v, p) for v in mv]
        if hm is None or None in row:
            return None
        rows.append([hm * v % p for v in row] + [(-v) % p for v in row])
    return rows


def _has_kernel_mod_p(vals: list[list[flint.fmpq]], hs: list[flint.fmpq]) -> bool:
    """False only when the ansatz matrix has full column rank mod p (then also over Q)."""
    rows = _rows_mod_p(vals, hs, PRIME)
    if rows is None:
        return True
    m = flint.nmod_mat(rows, PRIME)
    return m.rank() < m.ncols()


def _exact_kernel_vector(vals: list[list[flint.fmpq]], hs: list[flint.fmpq]) -> list[flint.fmpz] | None:
    """The one kernel vector of the ansatz over Q (fraction-free), or None when the kernel is not 1-dimensional."""
    rows = []
    for mv, h in zip(vals, hs):
        row = [h * v for v in mv] + [-v for v in mv]
        den = flint.fmpz(1)
        for v in row:
            den = den.lcm(v.q)
        rows.append([int(v.p * (den // v.q)) for v in row])
    x, nullity = flint.fmpz_mat(rows).nullspace()
    if nullity != 1:
        return None
    return [x[i, 0] for i in range(x.nrows())]


def _as_frac(ring: Ring, names: Sequence[str], monos: Sequence[tuple[int, ...]], vec: Sequence[flint.fmpz]) -> Frac:
    idx = [ring.index(n) for n in names]

    def poly(coeffs: Sequence[flint.fmpz]) -> flint.fmpz_mpoly:
        data = {}
        for m, c in zip(monos, coeffs):
            if c != 0:
                full = [0] * len(ring.names)
                for i, e in zip(idx, m):
                    full[i] = e
                data[tuple(full)] = int(c)
        return ring.ctx.from_dict(data)
    k = len(monos)
    return Frac(ring, poly(vec[k:]), poly(vec[:k]))


def _agrees(h: Frac, names: Sequence[str], pt: Sequence[flint.fmpq], value: flint.fmpq) -> bool:
    at = {n: flint.fmpq(0) for n in h.ring.names} | dict(zip(names, pt))
    den = h.ring.evaluate(h.den, at)
    return den != 0 and h.ring.evaluate(h.num, at) == value * den
