"""Rational function reconstruction from exact values: h = P/Q with P, Q of known total degrees (dense ansatz).

The integrals of an HK-basis are kernel coordinates c_k(x) (paper, eq. "smaller system"), known only through
exact values at rational points. The total degrees of P and Q (h in lowest terms) are those of h restricted to a
generic line, found by univariate interpolation in a handful of samples (`line_degrees`). The ansatz h Q(v) - P(v)
= 0 with those degrees is linear in the coefficients; each exact sample gives one row. A rank test mod p comes first
(full column rank mod p means no solution over Q either), then the one-dimensional null space is found exactly
(fraction-free) and the result is checked at fresh samples. The caller sets scaled names to 1 while sampling and
restores them by weighted homogeneity (hkproof.experiments.weights.Weights.restore_frac).
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from typing import Callable, Sequence

import flint

from hkproof import budget
from hkproof.algebra.sampling import random_rational
from hkproof.algebra.fraction import Frac
from hkproof.algebra.modular import kernel_mod_p
from hkproof.algebra.monomials import count_upto, exponents_upto, value
from hkproof.algebra.multimodular_kernel import one_kernel_vector
from hkproof.algebra.ring import Ring
from hkproof.experiments.arithmetics import integer_rows

__all__ = ["dense_size", "line_degrees", "Point", "reconstruct_rational", "Reconstruction", "Sampler",
           "univariate_degrees"]

Point = dict[str, flint.fmpq]
# sample(outer values, inner points) -> the function's value at each point (None where it is undefined)
Sampler = Callable[[Point, list[Point]], list["flint.fmpq | None"]]


@dataclass
class Reconstruction:
    """h = P/Q over `ring`, or None with the reason; the degree bound used and the number of exact samples."""

    frac: Frac | None
    degree: int | None
    samples: int
    checks: int = 0
    notes: list[str] = field(default_factory=list)


class _Samples:
    """Exact samples (variable values, function value), drawn on a grid: few outer values, many inner points."""

    def __init__(self, sample: Sampler, outer: Sequence[str], inner: Sequence[str], rng: random.Random, size: int):
        self.sample, self.outer, self.inner, self.rng, self.size = sample, list(outer), list(inner), rng, size
        self.rows: list[tuple[list[flint.fmpq], flint.fmpq]] = []
        self.failures = 0

    def _rational(self) -> flint.fmpq:
        return random_rational(self.rng, self.size)

    def extend(self, wanted: int, outer_draws: int) -> None:
        """At least `wanted` samples in all, spread over `outer_draws` random outer values."""
        per = max(1, math.ceil((wanted - len(self.rows)) / max(outer_draws, 1)))
        while len(self.rows) < wanted:
            budget.check("sampling exact values for a reconstruction")
            if self.failures > 4 * wanted + 40:
                raise ArithmeticError(f"only {len(self.rows)} of {wanted} samples: the function is undefined at "
                                      "almost every random point")
            outer = {n: self._rational() for n in self.outer}
            pts = [{n: self._rational() for n in self.inner} for _ in range(per)]
            for pt, v in zip(pts, self.sample(outer, pts), strict=True):
                if v is None:
                    self.failures += 1
                    continue
                self.rows.append(([outer[n] for n in self.outer] + [pt[n] for n in self.inner], v))


def line_degrees(sample: Sampler, outer: Sequence[str], inner: Sequence[str], *, max_degree: int = 16,
                 seed: int = 0, size: int = 30, modulus: int | None = None) -> tuple[int, int] | None:
    """(deg P, deg Q) of h = P/Q in lowest terms, read off h restricted to a random line through all variables
    (a generic line keeps both total degrees); None when no degree <= max_degree fits. With `modulus` the sampler
    returns values mod that prime (cheap probes; the degrees are right unless the prime or the line is unlucky)."""
    rng = random.Random(seed)
    names = list(outer) + list(inner)

    def r() -> flint.fmpq:
        return random_rational(rng, size)
    a, b = [r() for _ in names], [r() for _ in names]
    ts: list[int] = []
    vs: list = []
    t = 0
    for e in range(max_degree + 1):
        while len(ts) < 2 * e + 5:
            budget.check("sampling a line to read degrees")
            t += 1
            if t > 8 * max_degree + 40:
                return None
            pt = dict(zip(names, (x + t * y for x, y in zip(a, b, strict=True)), strict=True))
            v = sample({n: pt[n] for n in outer}, [{n: pt[n] for n in inner}])[0]
            if v is not None:
                ts.append(t)
                vs.append(v)
        found = _fit(ts, vs, e, modulus)
        if found is not None:
            return found
    return None


def univariate_degrees(ts: Sequence[int], values: Sequence[int], p: int, max_degree: int) -> tuple[int, int] | None:
    """(deg P, deg Q) of the lowest-degree rational function P/Q of t through the values mod p (None: none of
    degree <= max_degree fits the points given)."""
    for e in range(max_degree + 1):
        if len(ts) < 2 * e + 5:
            return None
        found = _fit(ts[:2 * e + 5], values[:2 * e + 5], e, p)
        if found is not None:
            return found
    return None


def _fit(ts: Sequence[int], vs: Sequence, e: int, modulus: int | None) -> tuple[int, int] | None:
    """Degrees of P/Q with deg <= e through the points (t, v): exact over Q, or mod `modulus`."""
    vec: list | None
    if modulus is None:
        vec = _exact_kernel_vector([[flint.fmpq(tt) ** j for j in range(e + 1)] for tt in ts], list(vs))
    else:
        vec = _kernel_vector_mod_p([[v * pow(tt, j, modulus) % modulus for j in range(e + 1)]
                                    + [-pow(tt, j, modulus) % modulus for j in range(e + 1)]
                                    for tt, v in zip(ts, vs, strict=True)], modulus)
    if vec is None:
        return None
    q, p = vec[:e + 1], vec[e + 1:]
    top = lambda c: max((j for j, x in enumerate(c) if x != 0), default=0)  # noqa: E731
    return top(p), top(q)


def _kernel_vector_mod_p(rows: list[list[int]], p: int) -> list[int] | None:
    kernel = kernel_mod_p(rows, p)
    return kernel[0] if len(kernel) == 1 else None


def dense_size(variables: int, degrees: tuple[int, int]) -> int:
    """Unknowns of the dense ansatz h Q - P = 0 with deg P <= degrees[0], deg Q <= degrees[1]."""
    return sum(count_upto(variables, d) for d in degrees)


def reconstruct_rational(ring: Ring, outer: Sequence[str], inner: Sequence[str], sample: Sampler,
                         degrees: tuple[int, int], *, checks: int = 4, seed: int = 0,
                         size: int = 30) -> Reconstruction:
    """h = P/Q in the variables outer + inner (names of `ring`) with deg P <= degrees[0], deg Q <= degrees[1]
    (from `line_degrees`), from exact values; checked at `checks` fresh samples."""
    names = list(outer) + list(inner)
    samples = _Samples(sample, outer, inner, random.Random(seed), size)
    result = Reconstruction(None, None, 0)
    p_monos, q_monos = (exponents_upto(len(names), d) for d in degrees)
    unknowns = len(p_monos) + len(q_monos)
    outer_draws = count_upto(len(outer), max(degrees)) + 2 if outer else 1
    samples.extend(unknowns + 6, outer_draws)
    hs = [v for _, v in samples.rows]
    vals = ([value(m, pt) for m in q_monos] for pt, _ in samples.rows)
    pvals = ([value(m, pt) for m in p_monos] for pt, _ in samples.rows)
    rows = [[h * v for v in qv] + [-v for v in pv] for h, qv, pv in zip(hs, vals, pvals, strict=True)]
    result.samples = len(samples.rows)
    vec = _integer_kernel_vector(rows)
    if vec is None:
        result.notes.append(f"no P/Q with degrees <= {degrees} fits the samples: the ansatz has no one-dimensional "
                            "kernel (kernels mod primes)")
        return result
    h = Frac(ring, _poly(ring, names, p_monos, vec[len(q_monos):]), _poly(ring, names, q_monos, vec[:len(q_monos)]))
    fresh = _Samples(sample, outer, inner, random.Random(seed + 7919), size)
    fresh.extend(checks, checks)
    result.samples += len(fresh.rows)
    if all(_agrees(h, names, pt, v) for pt, v in fresh.rows):
        result.frac, result.degree, result.checks = h, max(degrees), len(fresh.rows)
    else:
        result.notes.append("the interpolant failed a fresh check")
    return result


def _integer_kernel_vector(rows: list[list[flint.fmpq]]) -> list[flint.fmpz] | None:
    """The one kernel vector over Q (integer, by kernels mod primes and an exact check), or None when the kernel is
    not one-dimensional (hkproof.algebra.multimodular_kernel: the budget can stop it between primes)."""
    return one_kernel_vector(integer_rows(rows), random.Random(len(rows)))


def _exact_kernel_vector(vals: list[list[flint.fmpq]], hs: list[flint.fmpq]) -> list[flint.fmpz] | None:
    """Kernel of the dense ansatz h Q - P = 0 with one monomial list for both (Q coefficients first)."""
    return _integer_kernel_vector([[h * v for v in mv] + [-v for v in mv] for mv, h in zip(vals, hs, strict=True)])


def _poly(ring: Ring, names: Sequence[str], monos: Sequence[tuple[int, ...]],
          coeffs: Sequence[flint.fmpz]) -> flint.fmpz_mpoly:
    idx = [ring.index(n) for n in names]
    data = {}
    for m, c in zip(monos, coeffs, strict=True):
        if c != 0:
            full = [0] * len(ring.names)
            for i, e in zip(idx, m, strict=True):
                full[i] = e
            data[tuple(full)] = int(c)
    return ring.ctx.from_dict(data)


def _agrees(h: Frac, names: Sequence[str], pt: Sequence[flint.fmpq], value: flint.fmpq) -> bool:
    at = {n: flint.fmpq(0) for n in h.ring.names} | dict(zip(names, pt, strict=True))
    den = h.ring.evaluate(h.den, at)
    return den != 0 and h.ring.evaluate(h.num, at) == value * den
