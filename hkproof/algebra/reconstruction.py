"""One interface for rebuilding rational functions over Q from their values modulo primes (docs/reconstruction.md).

FireFly and FiniteFlow put several algorithms behind one interface and one result type; so does hkproof. Here are the
pieces every algorithm shares: the result type `Rebuilt`, the prime stream `Primes`, the integer-primitive
normalization `primitive`, the check at a fresh prime `agrees_at_fresh_prime`, the reduced fractions and degrees of
functions restricted to a line (`fractions_on_line`, `degrees_on_line`), and the front function `reconstruct`, which
runs one of the two algorithms:

- "sparse" (hkproof.algebra.sparse_reconstruction): Thiele along lines, Cuyt–Lee shifts, Ben-Or–Tiwari; one function,
  any number of variables, cost by its terms: the large kernel coordinates of `discover`;
- "dense" (hkproof.algebra.dense_reconstruction): the dense ansatz g Q - P = 0 of the degrees along a line, several
  functions on shared probes; cost by the ansatz: small functions of few variables (relation coefficients, cofactors).

Every result is a candidate that agreed with the black box at random points modulo a fresh prime: callers prove it.

>>> def box(p, points):    # f = (x^2 - y/3) / (1 + 2 x y), one value per point
...     return [[(x * x - y * pow(3, -1, p)) * pow(1 + 2 * x * y, -1, p) % p] if (1 + 2 * x * y) % p else None
...             for x, y in points]
>>> [(sorted(r.numerator.items()), sorted(r.denominator.items())) for r in
...  (reconstruct(box, 2, 1, method=m, rng=random.Random(5))[0] for m in ("sparse", "dense"))]
[([((0, 1), -1), ((2, 0), 3)], [((0, 0), 3), ((1, 1), 6)]), ([((0, 1), -1), ((2, 0), 3)], [((0, 0), 3), ((1, 1), 6)])]
"""
from __future__ import annotations

import math
import random
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import flint

from hkproof import budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.modular import polynomial_mod_p, random_prime
from hkproof.algebra.monomials import Exponents
from hkproof.algebra.ring import Ring
from hkproof.algebra.sparse_interpolation import is_smooth_prime, smooth_prime
from hkproof.algebra.univariate_rational import ThieleInterpolator
from hkproof.errors import HKProofError

__all__ = ["Batch", "CHECK_POINTS", "Mapper", "memoized_values", "Polynomial", "Primes", "Rebuilt",
           "ReconstructionStats", "agrees_at_fresh_prime", "degrees_on_line", "fractions_on_line", "lift", "primitive",
           "reconstruct"]

Polynomial = dict[Exponents, int]
Batch = Callable[[int, Sequence[Sequence[int]]], "list[list[int] | None]"]
"""black_box(p, points) -> for each point the values mod p of every function (None where one is undefined)."""
Mapper = Callable[[Callable[[Any], Any], list[Any]], Iterable[Any]]
"""Like map: applies a function to each job (a process pool's or Dask's map runs the black-box batches)."""

CHECK_POINTS = 4
"""The final check compares the candidates with the black box at this many random points modulo a fresh prime."""


@dataclass
class ReconstructionStats:
    """What a reconstruction cost: probes (black-box evaluations), primes, sizes and seconds per stage."""
    probes: int = 0
    undefined_probes: int = 0
    black_box_calls: int = 0
    probes_by_stage: dict[str, int] = field(default_factory=dict)
    lines: int = 0
    primes_used: list[int] = field(default_factory=list)
    primes_rejected: list[tuple[int, str]] = field(default_factory=list)
    check_primes: list[int] = field(default_factory=list)
    terms_numerator: int = 0
    terms_denominator: int = 0
    degree_numerator: int = 0
    degree_denominator: int = 0
    shift: tuple[int, ...] = ()
    cleared: tuple[int, ...] = ()       # x^cleared: a monomial factor of the denominator, cleared before the shift
    seconds: dict[str, float] = field(default_factory=lambda: dict.fromkeys(
        ("probes", "univariate", "sparse", "crt", "check"), 0.0))

    def as_dict(self) -> dict[str, Any]:
        """The statistics as plain data (for printing or JSON)."""
        return {k: (dict(v) if isinstance(v, dict) else list(v) if isinstance(v, list) else v)
                for k, v in self.__dict__.items()}


@dataclass(frozen=True)
class Rebuilt:
    """f = numerator / denominator with integer coefficients ({exponents: coefficient}), primitive (the gcd of all
    coefficients of both is 1), signed so that the denominator's leading coefficient (highest total degree, then the
    lexicographically largest exponents) is positive; `stats` when the algorithm keeps them."""
    numerator: Polynomial
    denominator: Polynomial
    stats: ReconstructionStats | None = None

    def value_mod_p(self, point: Sequence[int], p: int) -> int | None:
        """numerator / denominator at a point mod p (None where the denominator vanishes)."""
        den = polynomial_mod_p(self.denominator, point, p)
        return None if den == 0 else polynomial_mod_p(self.numerator, point, p) * pow(den, -1, p) % p

    def to_frac(self, ring: Ring, names: Sequence[str]) -> Frac:
        """The function in `ring`, its exponents read as those of `names` (the black box's inputs, in order)."""
        return Frac(ring, lift(ring, names, self.numerator), lift(ring, names, self.denominator))


def lift(ring: Ring, names: Sequence[str], poly: Mapping[Exponents, int]) -> flint.fmpz_mpoly:
    """An integer polynomial in `names` (exponent tuples) as an element of `ring`."""
    idx = [ring.index(n) for n in names]
    data = {}
    for m, c in poly.items():
        full = [0] * len(ring.names)
        for i, e in zip(idx, m, strict=True):
            full[i] = e
        data[tuple(full)] = int(c)
    return ring.ctx.from_dict(data)


def _leading(poly: Polynomial) -> Exponents:
    return max(poly, key=lambda m: (sum(m), m))


def primitive(numerator: Mapping[Exponents, flint.fmpq], denominator: Mapping[Exponents, flint.fmpq]) -> Rebuilt:
    """Rational coefficients made integer, primitive and signed as `Rebuilt` says (zero coefficients dropped)."""
    scale = math.lcm(1, *(int(c.q) for c in (*numerator.values(), *denominator.values())))
    ints = [{m: int(c.p) * (scale // int(c.q)) for m, c in part.items() if c} for part in (numerator, denominator)]
    g = math.gcd(*(v for part in ints for v in part.values())) or 1
    if not ints[1]:
        raise HKProofError("a rebuilt denominator is zero")
    sign = -1 if ints[1][_leading(ints[1])] < 0 else 1
    num, den = ({m: sign * v // g for m, v in part.items()} for part in ints)
    return Rebuilt(num, den)


class Primes:
    """The primes a reconstruction uses, in order: given ones, or random ones of `bits` bits (smooth p - 1 where
    Ben-Or–Tiwari's support stage needs it). A given prime unfit for the support stage is kept for a later stage."""

    def __init__(self, rng: random.Random, given: Iterable[int] | None = None, bits: int = 62):
        self.given: Iterator[int] | None = None if given is None else iter(given)
        self.deferred: list[int] = []
        self.rng, self.bits = rng, bits
        self.seen: set[int] = set()

    def _next_given(self, purpose: str) -> int:
        assert self.given is not None
        for p in self.given:
            p = int(p)
            if p in self.seen:
                continue
            if p < 2 ** 20 or p >= 2 ** 64 or not flint.fmpz(p).is_prime():
                raise HKProofError(f"the primes given must be primes between 2^20 and 2^64, got {p}")
            self.seen.add(p)
            return p
        raise HKProofError(f"the primes given ran out ({len(self.seen)} used) while {purpose}: give more primes, or "
                           f"none to let the engine draw random ones")

    def support(self) -> int:
        """A prime with p - 1 smooth (Pohlig–Hellman discrete logarithms in the support stage)."""
        if self.given is None:
            return self._fresh(lambda: smooth_prime(self.rng, self.bits))
        while True:
            p = self._next_given("looking for a prime with smooth p - 1 for the support stage")
            if is_smooth_prime(p):
                return p
            self.deferred.append(p)

    def any(self) -> int:
        """A prime not used before (for coefficients, degrees or a check)."""
        if self.deferred:
            return self.deferred.pop(0)
        if self.given is None:
            return self._fresh(lambda: random_prime(self.rng, self.bits))
        return self._next_given("solving for coefficients modulo more primes")

    def _fresh(self, draw: Callable[[], int]) -> int:
        while True:
            p = draw()
            if p not in self.seen:
                self.seen.add(p)
                return p


def fractions_on_line(values: Callable[[list[int]], Sequence[Sequence[int] | None]], p: int, count: int,
                      nodes: Callable[[int], list[int]], max_degree: int, first: int = 8
                      ) -> list[tuple[list[int], list[int]] | None]:
    """Each of `count` functions of t, known through values(ts) (for each t the vector of values mod p, None where
    undefined), as its reduced numerator and denominator coefficient lists, by Thiele's interpolation with early
    termination; None for one that needs more than 2 max_degree + 2 nodes (a degree above max_degree). `nodes(k)`
    gives k new values of t (`first` of them at first). HKProofError when the functions are undefined almost
    everywhere."""
    thieles = [ThieleInterpolator(p) for _ in range(count)]
    limit = 2 * max_degree + 2
    defined = undefined = 0
    request = first
    while True:
        open_ = [th for th in thieles if not th.terminated and len(th.nodes) <= limit]
        if not open_:
            break
        budget.check("interpolating along a line")
        ts = nodes(request)
        for t, vector in zip(ts, values(ts), strict=True):
            if vector is None:
                undefined += 1
                continue
            defined += 1
            for th, v in zip(thieles, vector, strict=True):
                if not th.terminated and len(th.nodes) <= limit:
                    th.add(t, v)
        if undefined >= 16 and undefined > 3 * defined:
            raise HKProofError(f"the black box is undefined at {undefined} of {undefined + defined} random points mod "
                               f"p = {p}: it is undefined almost everywhere (or fails mod p); check the black box")
        request = max(2, min(8, limit + 1 - min(len(th.nodes) for th in open_)))
    return [th.fraction() if th.terminated else None for th in thieles]


def degrees_on_line(values: Callable[[list[int]], Sequence[Sequence[int] | None]], p: int, count: int,
                    nodes: Callable[[int], list[int]], max_degree: int) -> list[tuple[int, int] | None]:
    """(deg P, deg Q) of each function restricted to the line (`fractions_on_line`; deg 0 = -1 is read as 0 for the
    zero function). A generic line keeps both total degrees; a special line or prime only lowers them."""
    return [None if f is None else (max(len(f[0]) - 1, 0) if any(f[0]) else 0, len(f[1]) - 1)
            for f in fractions_on_line(values, p, count, nodes, max_degree)]


def agrees_at_fresh_prime(black_box: Batch, candidates: Sequence[Rebuilt], n: int, primes: Primes,
                          rng: random.Random, points: int = CHECK_POINTS) -> int | None:
    """The prime at which every candidate agreed with the black box at `points` random points, or None if one
    disagreed; up to three primes are tried where the black box is undefined at most points (then HKProofError)."""
    for _ in range(3):
        p = primes.any()
        agreed = tried = 0
        while agreed < points and tried < 8 * points:
            budget.check("checking a reconstruction at a fresh prime")
            xs = [[rng.randrange(p) for _ in range(n)] for _ in range(points - agreed)]
            tried += len(xs)
            for x, vector in zip(xs, black_box(p, xs), strict=True):
                if vector is None:
                    continue
                for c, v in zip(candidates, vector, strict=True):
                    den = polynomial_mod_p(c.denominator, x, p)
                    if (polynomial_mod_p(c.numerator, x, p) - v * den) % p:
                        return None
                agreed += 1
        if agreed >= points:
            return p
    raise HKProofError("the black box is undefined at most random points modulo three check primes")


def memoized_values(memo: dict[tuple[int, ...], Any], points: Sequence[Sequence[int]],
                    compute: Callable[[list[tuple[int, ...]]], Sequence[Any]]) -> list[Any]:
    """A vector black box's values at `points` (mod one prime), each computed once: the points not yet in `memo` go to
    `compute` together (once each, in order), the others are read back. Components rebuilt one at a time with equal
    seeds meet on the same points (the sparse engine's keyed streams), so they pay for each vector once."""
    keys = [tuple(int(v) for v in x) for x in points]
    missing = [x for x in dict.fromkeys(keys) if x not in memo]
    if missing:
        memo.update(zip(missing, compute(missing), strict=True))
    return [memo[x] for x in keys]


def reconstruct(black_box: Batch, n: int, count: int = 1, *, method: str = "sparse", rng: random.Random,
                **options: Any) -> list[Rebuilt]:
    """`count` rational functions of n variables over Q from their values mod primes, by the `method` "sparse" (one
    function at a time; options of sparse_reconstruction.sparse: budget, max_degree, primes, mapper, progress,
    batch_size, bits) or "dense" (all on shared probes; options of dense_reconstruction.dense: max_degree, bits,
    max_primes). Candidates, checked at a fresh prime."""
    from hkproof.algebra.dense_reconstruction import dense
    from hkproof.algebra.sparse_reconstruction import sparse
    if method == "dense":
        return dense(black_box, n, count, rng=rng, **options)
    if method == "sparse":
        return [sparse(_Component(black_box, k), n, rng=rng, **options) for k in range(count)]
    raise HKProofError(f"no reconstruction method {method!r}: choose 'sparse' or 'dense'")


class _Component:
    """The k-th function of a vector black box, as the scalar batch the sparse algorithm probes (picklable when the
    black box is, for a process pool's mapper)."""

    def __init__(self, black_box: Batch, k: int):
        self.black_box, self.k = black_box, k

    def __call__(self, p: int, points: Sequence[Sequence[int]]) -> list[int | None]:
        return [None if v is None else v[self.k] for v in self.black_box(p, points)]
