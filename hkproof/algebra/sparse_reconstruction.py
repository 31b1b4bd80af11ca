"""The sparse algorithm behind hkproof.algebra.reconstruction (method "sparse"): functional reconstruction over prime
fields: a rational function f = P/Q with rational coefficients, known
only through its values mod primes (a black box), rebuilt exactly over Q (the method of FireFly, Klappert–Lange 2019,
and FiniteFlow, Peraro 2019). See docs/reconstruction.md for the method, the choices and the measurements.

Stages, for one prime: degrees along a random line (Thiele); a sparse shift s with Q(s) != 0; lines
x = t z_j + s through the geometric points z_j = (1, c_i w_i^j) (Ben-Or–Tiwari with Kronecker substitution), one
small rational fit per line (FireFly: only the t-coefficients not yet known are unknowns); each homogeneous piece,
top-down with the shift's contributions subtracted (Cuyt–Lee), by Berlekamp–Massey, roots and discrete logs. Later
primes solve only for the coefficients on that support (one transposed Vandermonde solve per piece); Chinese
remaindering and Wang's rational reconstruction; a final check at fresh random points modulo a fresh prime.

The result is a candidate that agreed with f at random points mod a fresh prime, not a proof: callers prove it.

>>> def box(p, points):   # f = (x^2 - y/3) / (1 + 2 x y)
...     return [(x * x - y * pow(3, -1, p)) * pow(1 + 2 * x * y, -1, p) % p if (1 + 2 * x * y) % p else None
...             for x, y in points]
>>> r = sparse(box, 2, rng=random.Random(5))
>>> sorted(r.numerator.items()), sorted(r.denominator.items())
([((0, 1), -1), ((2, 0), 3)], [((0, 0), 3), ((1, 1), 6)])
"""
from __future__ import annotations

import itertools
import math
import random
import sys
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any

import flint

from hkproof.algebra.homogeneous_shift import ShiftedPieces
from hkproof.algebra.rational_lifting import CoefficientLifter
from hkproof.algebra.reconstruction import (Mapper, Polynomial, Primes, Rebuilt, ReconstructionStats,
                                            agrees_at_fresh_prime, fractions_on_line, primitive)
from hkproof.algebra.sparse_interpolation import (EARLY_TERMINATION, ExponentialSum, GeometricPoints, ben_or_tiwari,
                                                  transposed_vandermonde)
from hkproof.algebra.univariate_rational import THIELE_AGREEMENTS, fit_lines
from hkproof.budget import UNLIMITED, Budget
from hkproof.errors import HKProofError, ResourceLimitError, UnluckyPrimeError

__all__ = ["ProbeBatch", "sparse"]

ProbeBatch = Callable[[int, Sequence[Sequence[int]]], "list[int | None]"]
"""black_box(p, points) -> f(point) mod p for each point (n residues each), None where f is undefined there."""
CoefficientName = tuple[str, tuple[int, ...]]
"""("n", exponents) for a numerator coefficient, ("d", exponents) for a denominator one."""

SPARE_NODES = 16
"""Extra values of t a line may use where f is undefined at the usual ones."""
SHIFT_SUBSETS = 12
"""Random subsets of each size from three variables to n - 1 whose shifts are tried before the full shift."""
LINES_PER_WAVE = 256
"""Lines probed and fitted between two budget checks (a few seconds for the largest kernel coordinates)."""
MAX_SUPPORT_RESTARTS = 4
"""Support primes given up (unlucky) before the engine reports failure."""
KRONECKER_FLOOR = 16
"""The smallest Kronecker base of the support stage (a larger base costs nothing: the discrete logarithms depend on
p - 1 only), so that functions of low degree probe one grid."""
SHIFTED_TERMS_LIMIT = 50_000_000
"""Terms of a shift's contributions one chain may keep (about 1.2 GB in FLINT's packed form): a piece whose
expansion could pass it is a clean ResourceLimitError before it is composed, not an allocation failure that aborts
the process."""


class _BatchCall:
    """One job of the mapper: (p, points) -> black_box(p, points) (picklable when the black box is)."""

    def __init__(self, black_box: ProbeBatch):
        self.black_box = black_box

    def __call__(self, job: tuple[int, list[list[int]]]) -> list[int | None]:
        return self.black_box(*job)


class _TimesMonomial:
    """x^k f(x): the black box with the monomial factor x^k of f's denominator cleared (picklable when f's is)."""

    def __init__(self, black_box: ProbeBatch, exponents: Sequence[int]):
        self.black_box, self.exponents = black_box, tuple(exponents)

    def __call__(self, p: int, points: Sequence[Sequence[int]]) -> list[int | None]:
        out: list[int | None] = []
        for x, v in zip(points, self.black_box(p, points)):
            if v is None:
                out.append(None)
                continue
            for xi, e in zip(x, self.exponents):
                if e:
                    v = v * pow(int(xi), e, p) % p
            out.append(v)
        return out


@dataclass
class _Support:
    """What the support stage found: degrees, the shift, the normalizing monomial and the pieces mod its prime."""
    degree_num: int
    degree_den: int
    shift: list[int]
    num: dict[int, Polynomial]
    den: dict[int, Polynomial]
    normalizer: tuple[int, ...] = ()


class _Chain:
    """The t-coefficients c_0..c_d of the numerator (or the denominator) along the lines, for one prime: values
    measured while unknown, homogeneous pieces once solved, and the known coefficients' values as exponential sums."""

    def __init__(self, degree: int, shift: Sequence[int], p: int, grid: GeometricPoints, denominator: bool):
        self.degree, self.shift, self.p, self.grid, self.denominator = degree, list(shift), p, grid, denominator
        self.shifted = any(shift)
        self.pieces: dict[int, Polynomial] = {}
        self.moved = ShiftedPieces(len(shift), shift, p, SHIFTED_TERMS_LIMIT)  # sum of the solved P_k(z + s)
        self.raw: dict[int, list[int]] = {r: [] for r in range(degree + 1)}
        self._sums: dict[int, ExponentialSum] = {}
        self._higher: dict[int, ExponentialSum] = {}

    def known(self, r: int) -> bool:
        """Whether c_r is known on every line (the denominator's c_0 is 1: the normalization Q(s) = 1)."""
        if self.denominator and r == 0:
            return True
        return all(k in self.pieces for k in range(r, self.degree + 1)) if self.shifted else r in self.pieces

    def unknown(self) -> list[int]:
        return [r for r in range(self.degree + 1) if not self.known(r)]

    def solvable(self) -> list[int]:
        """Pieces that can be solved now (top-down when shifted: every higher piece is solved)."""
        return [r for r in range(self.degree, -1, -1) if r not in self.pieces
                and (not self.shifted or all(k in self.pieces for k in range(r + 1, self.degree + 1)))]

    def _exponential_sum(self, terms: Iterable[tuple[tuple[int, ...], int]]) -> ExponentialSum:
        """The values along the lines of a polynomial in the n coordinates (the first one is 1 on every line)."""
        return ExponentialSum(self.grid.exponential_terms(((m[1:], c) for m, c in terms), self.degree), self.p)

    def _contributions(self, r: int) -> ExponentialSum:
        """sum over the solved pieces k >= r of [t^r] P_k(t z + s) on the lines: the higher pieces' contributions
        while P_r is unsolved (cleaned), the whole c_r once it is known (values); no later piece adds to degree r."""
        return self._exponential_sum(self.moved.part(r))

    def values(self, r: int, start: int, stop: int) -> list[int]:
        """c_r on the lines start <= j < stop (c_r known)."""
        if self.denominator and r == 0:
            return [1] * (stop - start)
        if r not in self._sums:
            self._sums[r] = self._contributions(r) if self.shifted else self._exponential_sum(self.pieces[r].items())
        return self._sums[r].values(start, stop)

    def cleaned(self, r: int, length: int) -> list[int]:
        """The values of the piece P_r on lines 0..length-1: measured c_r minus the higher pieces' contributions."""
        raw = [1] * length if self.denominator and r == 0 else self.raw[r][:length]
        if not self.shifted:
            return raw
        if r not in self._higher:
            self._higher[r] = self._contributions(r)
        higher = self._higher[r].values(0, length)
        return [(a - b) % self.p for a, b in zip(raw, higher)]

    def measured(self, r: int) -> int:
        """How many lines have measured (or, for the normalization, know) c_r."""
        return sys.maxsize if self.denominator and r == 0 else len(self.raw[r])

    def set_piece(self, r: int, poly: Polynomial) -> None:
        self.pieces[r] = poly
        if not self.shifted:
            return
        self.moved.add(poly)


class _Engine:
    """One reconstruction: the prime loop, the stages, the statistics."""

    def __init__(self, black_box: ProbeBatch, n: int, rng: random.Random, budget: Budget, max_degree: int,
                 primes: Iterable[int] | None, mapper: Mapper | None, progress: Callable[[dict], None] | None,
                 batch_size: int, bits: int):
        self.black_box, self.n, self.rng, self.budget = black_box, n, rng, budget
        self.max_degree, self.batch_size = max_degree, batch_size
        self.seed = rng.getrandbits(64)
        self.primes = Primes(self._keyed("primes"), primes, bits)
        self.mapper: Mapper = mapper or (lambda fn, jobs: [fn(job) for job in jobs])
        self.report = progress
        self.stats = ReconstructionStats()
        self._nested: list[float] = []      # seconds spent in stages nested in each open stage
        self._throughput = 0.0
        self._last_report = 0.0
        self.pole: tuple[int, ...] | None = None     # x^pole divides f's denominator (cleared from the black box)

    # -- bookkeeping ---------------------------------------------------------------------------------------------
    def _keyed(self, *key: object) -> random.Random:
        """The random stream of one purpose (a line's nodes, a grid, a shift's values, the primes, ...), drawn from the
        engine's seed and the key alone: engines given equal seeds probe the same points wherever their stages meet
        (the same line, the prefix of its nodes, the same prime), so a memoized vector black box pays once for the
        components it serves, whatever their degrees and supports."""
        return random.Random("/".join(map(str, (self.seed, *key))))

    @contextmanager
    def _stage(self, name: str) -> Iterator[None]:
        """Time a stage, excluding the time of nested stages (the black box's time goes to 'probes')."""
        start = time.perf_counter()
        self._nested.append(0.0)
        try:
            yield
        finally:
            spent = time.perf_counter() - start
            self.stats.seconds[name] = self.stats.seconds.get(name, 0.0) + spent - self._nested.pop()
            if self._nested:
                self._nested[-1] += spent

    def _progress(self, force: bool = False, **info: Any) -> None:
        now = time.perf_counter()
        if self.report is None or (not force and now - self._last_report < 0.5):
            return
        self._last_report = now
        self.report({"probes": self.stats.probes, "lines": self.stats.lines,
                     "primes_used": len(self.stats.primes_used), **info})

    def _reject(self, p: int, reason: str) -> None:
        self.stats.primes_rejected.append((p, reason))
        self._progress(force=True, rejected=p, reason=reason)

    # -- the black box -------------------------------------------------------------------------------------------
    def _probe(self, p: int, points: list[list[int]], stage: str) -> list[int | None]:
        """f at the points mod p, in batches through the mapper, in waves of about half a second (budget checks)."""
        out: list[int | None] = []
        call = _BatchCall(self.black_box)
        pos = 0
        while pos < len(points):
            self.budget.check(f"evaluating the black box ({stage})")
            wave = max(self.batch_size, int(0.5 * self._throughput))
            jobs = [(p, points[i:i + self.batch_size])
                    for i in range(pos, min(pos + wave, len(points)), self.batch_size)]
            with self._stage("probes"):
                start = time.perf_counter()
                results = list(self.mapper(call, jobs))
                spent = time.perf_counter() - start
            count = sum(len(pts) for _, pts in jobs)
            self._throughput = count / max(spent, 1e-6)
            for (_, pts), res in zip(jobs, results):
                if len(res) != len(pts):
                    raise HKProofError(f"the black box returned {len(res)} values for {len(pts)} points")
                out.extend(None if v is None else int(v) % p for v in res)
            self.stats.black_box_calls += len(jobs)
            pos += count
        self.stats.probes += len(points)
        self.stats.probes_by_stage[stage] = self.stats.probes_by_stage.get(stage, 0) + len(points)
        self.stats.undefined_probes += sum(v is None for v in out)
        return out

    # -- univariate stages ---------------------------------------------------------------------------------------
    def _thiele_line(self, p: int, shift: Sequence[int], stage: str, expected: int = 8,
                     direction: Sequence[int] | None = None) -> tuple[list[int], list[int]]:
        """The reduced N/D (coefficient lists) of t -> f(t z + s) for a random z (or the given direction), by Thiele
        with early termination (hkproof.algebra.reconstruction.fractions_on_line)."""
        if direction is None:
            draws = self._keyed("direction", p, *shift)
            direction = [draws.randrange(1, p) for _ in range(self.n)]
        z = list(direction)
        nodes = self._keyed("nodes", p, *z, *shift)

        def values(ts: list[int]) -> list[list[int] | None]:
            return [None if v is None else [v] for v in
                    self._probe(p, [[(t * zi + si) % p for zi, si in zip(z, shift)] for t in ts], stage)]
        with self._stage("univariate"):
            found = fractions_on_line(values, p, 1, lambda k: [nodes.randrange(1, p) for _ in range(k)],
                                      self.max_degree, first=expected)[0]
        if found is None:
            raise ResourceLimitError(
                f"f restricted to a line needs more than {2 * self.max_degree + 2} points: its numerator or "
                f"denominator has degree above max_degree = {self.max_degree} (raise max_degree)")
        return found

    def _degrees(self, p: int) -> tuple[int, int]:
        """deg P, deg Q from a random line with a random shift (-1 for f = 0)."""
        draws = self._keyed("degrees", p)
        num, den = self._thiele_line(p, [draws.randrange(1, p) for _ in range(self.n)], "degrees")
        return (-1 if num == [0] else len(num) - 1), len(den) - 1

    def _poles(self, p: int) -> tuple[int, ...]:
        """For each variable x_i, the order k_i of the pole of f along x_i = 0 (the others at random values): the
        power of x_i dividing the denominator of f in lowest terms. Clearing x^k lets a sparse shift s, with
        Q(s) != 0, exist where the denominator has a monomial factor (then the full shift's expansions are avoided)."""
        out = []
        for i in range(self.n):
            draws = self._keyed("pole", p, i)
            base = [draws.randrange(1, p) for _ in range(self.n)]
            base[i] = 0
            num, den = self._thiele_line(p, base, "shift", direction=[int(j == i) for j in range(self.n)])
            order = next(k for k, c in enumerate(den) if c) - next((k for k, c in enumerate(num) if c), 0)
            out.append(max(0, order))
        return tuple(out)

    def _shift(self, p: int, degrees: tuple[int, int], sizes: range, known_to_fail: frozenset[int] = frozenset()
               ) -> list[int] | None:
        """The sparsest shift s with Q(s) != 0 whose number of variables is in `sizes`: all subsets of one and two
        variables, SHIFT_SUBSETS random subsets of each size from three to n - 1, all variables (random integer
        values); None if there is none. One probe at each candidate s of a size screens them (f is defined at s only
        if Q(s) != 0); a defined one is confirmed by a line through s with the full degrees and no pole at t = 0. A
        black box may fail at s where f is defined (an orbit through a point with many zero coordinates
        degenerates), so the sparse shifts that fail the probe are tried by their line too, before the full shift: a
        line costs about 2 deg + 3 probes, the expansions of a full shift's contributions far more (Cuyt-Lee; a term
        of P_k gives up to binom(k + n, n) terms, against prod (e_i + 1) over the shifted variables). Q needs a
        shift of k variables when each of its monomials involves at least k of them. Subsets that contain every
        variable of `known_to_fail` are skipped (after a monomial factor x^k is cleared, Q/x^k vanishes wherever Q
        did on such a subset)."""
        n = self.n
        for k in sizes:
            if k <= 2 or math.comb(n, k) <= SHIFT_SUBSETS:
                group = list(itertools.combinations(range(n), k))
            else:
                chosen: set[tuple[int, ...]] = set()
                draws = self._keyed("subsets", p, k)
                while len(chosen) < SHIFT_SUBSETS:
                    chosen.add(tuple(sorted(draws.sample(range(n), k))))
                group = sorted(chosen)
            group = [subset for subset in group if not known_to_fail or not known_to_fail <= set(subset)]
            if not group:
                continue
            candidates = [self._shift_values(p, subset) for subset in group]
            screened = self._probe(p, [[v % p for v in s] for s in candidates], "shift")
            lines = [s for s, value in zip(candidates, screened) if value is not None or k == n]
            if 0 < k < n:
                lines += [s for s, value in zip(candidates, screened) if value is None]
            for shift in lines:
                num, den = self._thiele_line(p, shift, "shift", expected=2 * max(degrees) + 1 + THIELE_AGREEMENTS)
                if den[0] == 1 and (len(num) - 1, len(den) - 1) == degrees:
                    return shift
        return None

    def _shift_values(self, p: int, subset: Sequence[int]) -> list[int]:
        """A candidate shift on the variables of `subset` (random integers, 0 elsewhere), the same for every engine
        of this seed."""
        draws = self._keyed("shift", p, *subset)
        return [draws.randrange(1, 2 ** 31) if i in subset else 0 for i in range(self.n)]

    # -- the lines -----------------------------------------------------------------------------------------------
    def _run_lines(self, p: int, grid: GeometricPoints, chains: tuple[_Chain, _Chain],
                   solve: Callable[[_Chain, int], Polynomial | None],
                   batch: Callable[[int, list[tuple[_Chain, int]]], int], stage: str) -> None:
        """Probe lines x = t z_j + s in batches until every piece of both chains is solved (`solve` returns None
        while a piece needs more lines; `batch` says how many lines to probe next)."""
        width = chains[0].degree + chains[1].degree + 1
        nodes: list[int] = []
        draws = self._keyed("line nodes", p)
        while len(nodes) < width + SPARE_NODES:
            t = draws.randrange(1, p)
            if t not in nodes:
                nodes.append(t)
        lines = 0
        while True:
            self.budget.check(f"reconstructing homogeneous pieces mod p ({stage})")
            solved_one = True
            while solved_one:
                solved_one = False
                for chain in chains:
                    for r in chain.solvable():
                        poly = solve(chain, r)
                        if poly is not None:
                            chain.set_piece(r, poly)
                            solved_one = True
            unknown = [(c, r) for c in chains for r in c.unknown()]
            if all(len(c.pieces) == c.degree + 1 for c in chains):
                break
            if not unknown:      # every coefficient known but a piece still waits for its own values
                raise UnluckyPrimeError(f"a homogeneous piece could not be solved mod p = {p}")
            count = batch(lines, unknown)
            for start in range(lines, lines + count, LINES_PER_WAVE):      # budget checks between waves
                self._probe_lines(p, grid, chains, nodes, start, min(start + LINES_PER_WAVE, lines + count), stage)
            lines += count
            self.stats.lines += count
            self._progress(stage=stage, prime=p, pieces_solved=sum(len(c.pieces) for c in chains),
                           terms_found=sum(len(t) for c in chains for t in c.pieces.values()))

    def _probe_lines(self, p: int, grid: GeometricPoints, chains: tuple[_Chain, _Chain], nodes: list[int],
                     start: int, stop: int, stage: str) -> None:
        """Measure the unknown t-coefficients of both chains on the lines start <= j < stop."""
        self.budget.check(f"reconstructing homogeneous pieces mod p ({stage})")
        num, den = chains
        unknown_num, unknown_den = num.unknown(), den.unknown()
        width = len(unknown_num) + len(unknown_den)
        shift = num.shift
        with self._stage("sparse"):
            known_num = {r: num.values(r, start, stop) for r in range(num.degree + 1) if num.known(r)}
            known_den = {r: den.values(r, start, stop) for r in range(den.degree + 1) if den.known(r)}
        zs = [[1, *z] for z in grid.points(start, stop)]
        line_nodes: list[list[int]] = [[] for _ in zs]
        line_values: list[list[int]] = [[] for _ in zs]
        tried = [0] * len(zs)
        pending = list(range(len(zs)))
        while pending:
            asks = []
            for k in pending:
                need = width - len(line_nodes[k])
                if tried[k] + need > len(nodes):
                    raise UnluckyPrimeError(f"the black box is undefined on too many points of a line mod p = {p}")
                asks += [(k, t) for t in nodes[tried[k]:tried[k] + need]]
                tried[k] += need
            values = self._probe(p, [[(t * zi + si) % p for zi, si in zip(zs[k], shift)] for k, t in asks], stage)
            for (k, t), v in zip(asks, values):
                if v is not None:
                    line_nodes[k].append(t)
                    line_values[k].append(v)
            pending = [k for k in pending if len(line_nodes[k]) < width]
        with self._stage("univariate"):
            solutions = fit_lines(line_nodes, line_values, p, unknown_num, unknown_den,
                                  [{r: v[k] for r, v in known_num.items()} for k in range(len(zs))],
                                  [{r: v[k] for r, v in known_den.items()} for k in range(len(zs))])
        for sol in solutions:
            for r, v in zip(unknown_num, sol):
                num.raw[r].append(v)
            for r, v in zip(unknown_den, sol[len(unknown_num):]):
                den.raw[r].append(v)

    # -- one prime -----------------------------------------------------------------------------------------------
    def _discover(self, p: int) -> _Support:
        """The support stage mod a smooth prime: degrees, shift, and every piece by Ben-Or–Tiwari."""
        degrees = self._degrees(p)
        if degrees[0] < 0:
            return _Support(-1, 0, [0] * self.n, {}, {0: {(0,) * self.n: 1}}, (0,) * self.n)
        if max(degrees) > self.max_degree:
            raise ResourceLimitError(f"f has degrees {degrees} along a line, above max_degree = {self.max_degree}"
                                     f" (raise max_degree)")
        sparse = range(min(3, self.n + 1))
        shift = self._shift(p, degrees, sparse)
        if shift is None and self.pole is None:      # no shift of at most two variables: a monomial factor of Q?
            self.pole = self._poles(p)
            if any(self.pole):
                self.black_box = _TimesMonomial(self.black_box, self.pole)
                degrees = (degrees[0], degrees[1] - sum(self.pole))
                shift = self._shift(p, degrees, sparse, frozenset(i for i, k in enumerate(self.pole) if k))
        shift = shift or self._shift(p, degrees, range(3, self.n + 1))
        if shift is None:
            raise UnluckyPrimeError(f"no shift s with Q(s) != 0 mod p = {p} was found (a random full shift failed)")
        with self._stage("sparse"):
            base = _kronecker_base(max(degrees) + 1, self.n - 1, p)
            grid = GeometricPoints.kronecker(p, self.n - 1, base, self._keyed("grid", p, base))
        chains = (_Chain(degrees[0], shift, p, grid, False),
                  _Chain(degrees[1], shift, p, grid, True))

        def solve(chain: _Chain, r: int) -> Polynomial | None:
            # the denominator's constant piece is 1 - (the higher pieces' contributions): a constant, 4 values do
            length = 2 + EARLY_TERMINATION if chain.denominator and r == 0 else chain.measured(r)
            with self._stage("sparse"):
                found = ben_or_tiwari(chain.cleaned(r, length), grid, r, self.rng)
            return None if found is None else {(r - sum(m), *m): c for m, c in found.items()}

        def batch(lines: int, unknown: list[tuple[_Chain, int]]) -> int:
            return max(4, lines // 4)

        self._run_lines(p, grid, chains, solve, batch, "support")
        return _Support(degrees[0], degrees[1], shift, chains[0].pieces, chains[1].pieces)

    def _coefficients(self, p: int, support: _Support) -> dict[CoefficientName, int]:
        """The coefficients mod p on the known support (transposed Vandermonde per piece, one extra line checks
        each), normalized to a denominator coefficient 1 at support.normalizer."""
        with self._stage("sparse"):
            grid = GeometricPoints.random(p, self.n - 1, self._keyed("coefficient grid", p))
            for pieces in (support.num, support.den):
                for poly in pieces.values():
                    bases = [grid.base_of(m[1:]) for m in poly]
                    if len(set(bases)) < len(bases):
                        raise UnluckyPrimeError(f"two monomials have the same value at the points mod p = {p}")
        chains = (_Chain(support.degree_num, support.shift, p, grid, False),
                  _Chain(support.degree_den, support.shift, p, grid, True))
        size = {id(chains[0]): {r: len(support.num[r]) for r in support.num},
                id(chains[1]): {r: len(support.den[r]) for r in support.den}}

        def solve(chain: _Chain, r: int) -> Polynomial | None:
            monomials = list((support.den if chain.denominator else support.num)[r])
            if chain.measured(r) < len(monomials) + 1:
                return None
            with self._stage("sparse"):
                values = chain.cleaned(r, len(monomials) + 1)
                bases = [grid.base_of(m[1:]) for m in monomials]
                weights = transposed_vandermonde(bases, values, p)
                extra = ExponentialSum(zip(weights, bases), p).values(len(monomials), len(monomials) + 1)
            if extra[0] != values[-1]:
                raise UnluckyPrimeError(f"the values mod p = {p} do not fit the support of the degree-{r} piece of "
                                        f"the {'denominator' if chain.denominator else 'numerator'}")
            return {m: w * pow(grid.scale_of(m[1:]), -1, p) % p for m, w in zip(monomials, weights)}

        def batch(lines: int, unknown: list[tuple[_Chain, int]]) -> int:
            return min((size[id(c)][r] + 1 for c, r in unknown if c.measured(r) < size[id(c)][r] + 1),
                       default=lines + 1) - lines

        self._run_lines(p, grid, chains, solve, batch, "coefficients")
        return self._normalized(p, chains[0].pieces, chains[1].pieces, support.normalizer)

    def _normalized(self, p: int, num: dict[int, Polynomial], den: dict[int, Polynomial],
                    normalizer: tuple[int, ...]) -> dict[CoefficientName, int]:
        """All coefficients divided by the denominator's coefficient at `normalizer` (the same rule for each prime)."""
        scale = den.get(sum(normalizer), {}).get(normalizer, 0)
        if scale == 0:
            raise UnluckyPrimeError(f"p = {p} divides the normalizing coefficient of the denominator (a denominator "
                                    f"of f's normalized coefficients)")
        inv = pow(scale, -1, p)
        out = {("n", m): c * inv % p for poly in num.values() for m, c in poly.items()}
        out.update({("d", m): c * inv % p for poly in den.values() for m, c in poly.items()})
        return out

    # -- the check -----------------------------------------------------------------------------------------------
    def _check(self, candidate: Rebuilt) -> bool:
        """Whether the candidate agrees with f at random points modulo a fresh prime (one shared rule)."""
        def vectors(p: int, points: Sequence[Sequence[int]]) -> list[list[int] | None]:
            return [None if v is None else [v] for v in self._probe(p, [list(x) for x in points], "check")]
        with self._stage("check"):
            p = agrees_at_fresh_prime(vectors, [candidate], self.n, self.primes, self._keyed("check"))
        if p is not None:
            self.stats.check_primes.append(p)
        return p is not None

    # -- the prime loop ------------------------------------------------------------------------------------------
    def run(self) -> Rebuilt:
        with self.budget.active():          # the one budget rule: code below checks the active budget
            return self._run()

    def _run(self) -> Rebuilt:
        for _ in range(MAX_SUPPORT_RESTARTS + 1):
            p0 = self.primes.support()
            try:
                support = self._discover(p0)
            except UnluckyPrimeError as exc:
                self._reject(p0, str(exc))
                continue
            result = self._lift(p0, support)
            if result is not None:
                return result
        raise HKProofError(f"{MAX_SUPPORT_RESTARTS + 1} support primes failed (see the rejected primes: "
                           f"{self.stats.primes_rejected[-3:]}); the black box may not be a fixed rational function "
                           f"of degree <= {self.max_degree}")

    def _lift(self, p0: int, support: _Support) -> Rebuilt | None:
        """More primes on the support of p0 until the rationals reconstruct and pass the check (None: p0 was
        unlucky, its support is contradicted)."""
        den_terms = [m for poly in support.den.values() for m in poly]
        support.normalizer = min(den_terms, key=lambda m: (sum(m), m))
        lifter: CoefficientLifter[CoefficientName] = CoefficientLifter()
        with self._stage("crt"):
            missing = lifter.add(self._normalized(p0, support.num, support.den, support.normalizer), p0)[1]
        self.stats.primes_used.append(p0)
        failures = 0
        while True:
            if not missing:
                with self._stage("crt"):
                    candidate = primitive({m: q for (side, m), q in lifter.rationals.items() if side == "n"},
                                          {m: q for (side, m), q in lifter.rationals.items() if side == "d"})
                if self._check(candidate):
                    return self._result(candidate.numerator, candidate.denominator, support)
                if lifter.changed == 0 and len(lifter.primes) > 1:
                    self._reject(p0, "the support found modulo this prime gives coefficients that are stable over "
                                     "the primes but fail the final check")
                    return None
            p = self.primes.any()
            try:
                residues = self._coefficients(p, support)
            except UnluckyPrimeError as exc:
                self._reject(p, str(exc))
                failures += 1
                if failures >= 2:
                    self._reject(p0, "the support found modulo this prime does not fit two other primes")
                    self.stats.primes_used = [q for q in self.stats.primes_used if q not in lifter.primes]
                    return None
                continue
            failures = 0
            with self._stage("crt"):
                missing = lifter.add(residues, p)[1]
            self.stats.primes_used.append(p)
            self._progress(force=True, stage="crt", prime=p, coefficients_missing=len(missing))

    def _result(self, numerator: Polynomial, denominator: Polynomial, support: _Support) -> Rebuilt:
        if self.pole and any(self.pole):           # f = (x^k f) / x^k, in lowest terms should k have been too large
            common = [min(e) for e in zip(*numerator)] if numerator else [0] * self.n
            lower = [min(c, k) for c, k in zip(common, self.pole)]
            numerator = {tuple(a - b for a, b in zip(m, lower)): c for m, c in numerator.items()}
            denominator = {tuple(a + k - b for a, k, b in zip(m, self.pole, lower)): c for m, c in denominator.items()}
        s = self.stats
        s.terms_numerator, s.terms_denominator = len(numerator), len(denominator)
        s.degree_numerator = max((sum(m) for m in numerator), default=-1)
        s.degree_denominator = max(sum(m) for m in denominator)
        s.shift = tuple(support.shift)
        s.cleared = self.pole if self.pole and any(self.pole) else ()
        self._progress(force=True, stage="done", terms=s.terms_numerator + s.terms_denominator)
        return Rebuilt(numerator, denominator, s)


def _kronecker_base(base: int, nvars: int, p: int) -> int:
    """The Kronecker base for partial degrees below `base`, rounded up to a power of two of at least
    KRONECKER_FLOOR where the prime allows it (base^nvars < p - 1): engines with equal seeds then share their lines
    whatever their degrees below the floor, and in each power-of-two range above it."""
    rounded = max(KRONECKER_FLOOR, 1 << max(0, base - 1).bit_length())
    return rounded if rounded ** nvars < p - 1 else base


def sparse(black_box: ProbeBatch, n: int, *, rng: random.Random, budget: Budget | None = None, max_degree: int = 60,
           primes: Iterable[int] | None = None, mapper: Mapper | None = None,
           progress: Callable[[dict], None] | None = None, batch_size: int = 256, bits: int = 62) -> Rebuilt:
    """f = P/Q over Q from its values mod primes (FireFly/FiniteFlow: Thiele along lines, Cuyt–Lee shifts,
    Ben-Or–Tiwari, Wang's rational reconstruction), checked at random points modulo a fresh prime.

    black_box(p, points) gives f at many points mod p (None where undefined); n is the number of variables; rng
    makes the run reproducible; budget bounds the time (BudgetExhausted); max_degree bounds the total degrees of P
    and Q (ResourceLimitError above it); primes replaces the random primes of `bits` bits (used in order; the support
    stage takes the first with smooth p - 1); mapper runs the independent black-box batches of `batch_size` points
    (default: a loop); progress receives a dict now and then. The result is a candidate for the caller to prove."""
    if n < 1:
        raise HKProofError(f"a black box needs at least one variable, got n = {n}")
    if max_degree < 0 or batch_size < 1:
        raise HKProofError(f"max_degree must be >= 0 and batch_size >= 1, got {max_degree} and {batch_size}")
    return _Engine(black_box, n, rng, budget or UNLIMITED, max_degree, primes, mapper, progress, batch_size,
                   bits).run()
