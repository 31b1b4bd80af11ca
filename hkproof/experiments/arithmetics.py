"""Four arithmetics for algorithm (N): orbits by solving M x~ = b, ranks of X_[0,s-1] (eq. "balance"), kernels.

Each arithmetic says how sure it is: exact Q is certain; mod p is certain up to an unlucky prime (a second
prime checks the first); float64 and mpmath decide a rank only across a clear gap in the singular values,
measured against an estimate of the rounding error carried along the orbit, and answer "ambiguous" otherwise.
"""
from __future__ import annotations

import math
import random
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import Any, Sequence

import flint
import mpmath
import numpy as np

from hkproof.experiments.scene import AffineEntry, CompiledPoly, Scene
from hkproof.errors import SingularPointError

Number = Any


class UnluckyPrimeError(SingularPointError):
    """A computation mod p failed where it may succeed over Q (a denominator or det M divisible by p)."""


@dataclass
class RawProfile:
    """ranks[s-1] = rank X_[0,s-1] (None: the arithmetic cannot tell), the rows used, and how sure we are."""

    ranks: list[int | None]
    rows: list[list[Number]]
    certainty: dict = field(default_factory=dict)


class Arithmetic(ABC):
    """An arithmetic for algorithm (N): the profile of ranks at one point, and kernels of its rows."""

    name: str = ""

    @abstractmethod
    def profile(self, scene: Scene, basis: Sequence[tuple[CompiledPoly, CompiledPoly]],
                point: Sequence[flint.fmpq]) -> RawProfile:
        """Orbit x, f(x), ..., f^(l-1)(x), the matrix X_[0,l-1](x) (eq. "balance") and the ranks of its top rows."""

    @abstractmethod
    def kernel(self, raw: RawProfile, d: int) -> list[list[Number]]:
        """A basis of ker X_[0,l-d-1] normalized as the paper does: chosen last coordinates -1 (recipe (B))."""

    def to_json(self, value: Number) -> str | float:
        return str(value)


@dataclass
class Prepared:
    """A scene's matrix pieces and a compiled basis with every constant converted to one arithmetic."""

    matrix: list[list[tuple[Number, tuple[tuple[int, Number], ...]]]]
    rhs: list[tuple[Number, tuple[tuple[int, Number], ...]]]
    basis: list[tuple[tuple, tuple]]
    matrices: Any = None  # arithmetic-specific form of M0, M_k, b0, B (see ModP)


class FieldArithmetic(Arithmetic):
    """Numbers of one field, with linear solves and ranks: the orbit and X_[0,l-1] computed directly."""

    def __init__(self) -> None:
        self._prepared: dict[tuple[int, int], tuple[Scene, Sequence, Prepared]] = {}

    def prepare(self, scene: Scene, basis: Sequence[tuple[CompiledPoly, CompiledPoly]]) -> Prepared:
        """Constants converted once per scene and basis (the hot loop then only multiplies and adds)."""
        key = (id(scene), id(basis))
        hit = self._prepared.get(key)
        if hit is None or hit[0] is not scene or hit[1] is not basis:
            def affine(e: AffineEntry):
                return self.number(e[0]), tuple((k, self.number(c)) for k, c in e[1])

            def poly(p: CompiledPoly):
                return tuple((self.number(c), tuple((i, e) for i, e in enumerate(exps) if e)) for c, exps in p)

            prep = Prepared([[affine(e) for e in row] for row in scene.matrix], [affine(e) for e in scene.rhs],
                            [(poly(n), poly(d)) for n, d in basis])
            if len(self._prepared) > 16:
                self._prepared.clear()
            self._prepared[key] = hit = (scene, basis, prep)
        return hit[2]

    def profile(self, scene: Scene, basis: Sequence[tuple[CompiledPoly, CompiledPoly]],
                point: Sequence[flint.fmpq]) -> RawProfile:
        prep = self.prepare(scene, basis)
        orbit = self.orbit(prep, point, len(basis) - 1)
        rows = [self.basis_row(prep, x) for x in orbit]
        ranks, certainty = self.prefix_ranks(rows)
        return RawProfile(ranks, rows, {"arithmetic": self.name, **certainty})

    def orbit(self, prep: Prepared, point: Sequence[flint.fmpq], steps: int) -> list[list[Number]]:
        """The orbit in this arithmetic; SingularPointError where det M(x, eps) vanishes."""
        x = [self.number(v) for v in point]
        orbit = [x]
        for i in range(steps):
            try:
                x = self.step(prep, x)
            except SingularPointError as exc:
                raise type(exc)(f"step {i + 1} of the orbit: {exc}") from None
            orbit.append(x)
        return orbit

    def step(self, prep: Prepared, x: Sequence[Number]) -> list[Number]:
        """x~ from M(x) x~ = b(x) (eq. "Kahan gen" in matrix form)."""
        m = [[self.affine(e, x) for e in row] for row in prep.matrix]
        return self.solve(m, [self.affine(e, x) for e in prep.rhs])

    def basis_row(self, prep: Prepared, x: Sequence[Number]) -> list[Number]:
        """(phi_1(x), ..., phi_l(x)): one row of X (eq. "balance")."""
        return [self.evaluate(num, x) / self.evaluate(den, x) for num, den in prep.basis]

    def affine(self, entry, x: Sequence[Number]) -> Number:
        value, lin = entry
        for k, c in lin:
            value = value + c * x[k]
        return value

    def evaluate(self, poly, x: Sequence[Number]) -> Number:
        total = 0
        for c, exps in poly:
            for i, e in exps:
                c = c * x[i] ** e
            total = total + c
        return total

    @abstractmethod
    def number(self, q: flint.fmpq) -> Number:
        """An exact rational in this arithmetic."""

    @abstractmethod
    def solve(self, m: list[list[Number]], b: list[Number]) -> list[Number]:
        """The solution of M x~ = b; SingularPointError if M is singular."""

    @abstractmethod
    def prefix_ranks(self, rows: list[list[Number]]) -> tuple[list[int | None], dict]:
        """rank X_[0,s-1] for s = 1..len(rows), with a statement of certainty."""


# ---- exact rationals ------------------------------------------------------------------------------
def _pivot_columns(rref: Any, rank: int) -> list[int]:
    """Columns holding the pivots of a reduced row echelon form."""
    pivots, j = [], 0
    for i in range(rank):
        while rref[i, j] == 0:
            j += 1
        pivots.append(j)
    return pivots


def _ranks_from_pivots(pivots: Sequence[int], nrows: int) -> list[int]:
    """rank of the top s rows of X = number of pivot columns < s in rref(X^T)."""
    return [sum(1 for p in pivots if p < s) for s in range(1, nrows + 1)]


def _free_kernel(rref: Any, rank: int, ncols: int, entry, minus_one) -> list[list]:
    """Kernel basis from a reduced row echelon form: free columns set to -1, pivots solved (recipe (B))."""
    pivots = _pivot_columns(rref, rank)
    basis = []
    for free in (j for j in range(ncols) if j not in pivots):
        v = [entry(None, None)] * ncols
        v[free] = minus_one
        for i, pj in enumerate(pivots):
            v[pj] = entry(i, free)
        basis.append(v)
    return basis


def integer_rows(rows: Sequence[Sequence[flint.fmpq]]) -> flint.fmpz_mat:
    """Each row times the lcm of its denominators: same prefix ranks and kernels, fraction-free."""
    out = []
    for row in rows:
        den = flint.fmpz(1)
        for v in row:
            den = den.lcm(v.q)
        out.append([int(v.p * (den // v.q)) for v in row])
    return flint.fmpz_mat(out)


class ExactQ(FieldArithmetic):
    """Exact rational arithmetic (fmpq_mat solves; ranks and kernels on fmpz_mat): the reference answer."""

    name = "exact"

    def number(self, q: flint.fmpq) -> flint.fmpq:
        return q

    def solve(self, m: list[list[flint.fmpq]], b: list[flint.fmpq]) -> list[flint.fmpq]:
        try:
            sol = flint.fmpq_mat(m).solve(flint.fmpq_mat([[v] for v in b]))
        except ZeroDivisionError:
            raise SingularPointError("det M(x, eps) = 0 (exactly)") from None
        return [sol[i, 0] for i in range(len(b))]

    def prefix_ranks(self, rows: list[list[flint.fmpq]]) -> tuple[list[int], dict]:
        r, _, rank = integer_rows(rows).transpose().rref()
        return _ranks_from_pivots(_pivot_columns(r, rank), len(rows)), {"method": "exact rank over Q"}

    def kernel(self, raw: RawProfile, d: int) -> list[list[flint.fmpq]]:
        rows = raw.rows[:len(raw.rows[0]) - d]
        r, den, rank = integer_rows(rows).rref()
        zero = flint.fmpq(0)
        return _free_kernel(r, rank, len(rows[0]),
                            lambda i, j: zero if i is None else flint.fmpq(r[i, j], den), flint.fmpq(-1))


# ---- one large prime at a time ------------------------------------------------------------------
def random_prime(rng: random.Random, bits: int = 62) -> int:
    """A random prime of the given size (nmod_mat takes moduli below 2^64)."""
    while True:
        n = flint.fmpz(rng.getrandbits(bits) | (1 << (bits - 1)) | 1)
        if n.is_prime():
            return int(n)


class ModP(FieldArithmetic):
    """Arithmetic in Z/p for one prime p (Python ints reduced mod p, nmod_mat for solves and ranks)."""

    def __init__(self, p: int):
        super().__init__()
        self.p = p
        self.name = f"mod {p}"

    def number(self, q: flint.fmpq) -> int:
        den = int(q.q) % self.p
        if den == 0:
            raise UnluckyPrimeError(f"the denominator {q.q} is divisible by p = {self.p}")
        return int(q.p) * pow(den, -1, self.p) % self.p

    def prepare(self, scene, basis) -> Prepared:
        prep = super().prepare(scene, basis)
        if prep.matrices is None:
            n = len(prep.rhs)
            mat = lambda rows: flint.nmod_mat(rows, self.p)  # noqa: E731
            prep.matrices = (mat([[e[0] for e in row] for row in prep.matrix]),
                             [mat([[dict(e[1]).get(k, 0) for e in row] for row in prep.matrix]) for k in range(n)],
                             mat([[e[0]] for e in prep.rhs]),
                             mat([[dict(e[1]).get(k, 0) for k in range(n)] for e in prep.rhs]))
        return prep

    def step(self, prep: Prepared, x: Sequence[int]) -> list[int]:
        """M(x) = M0 + sum_k x_k M_k and b(x) = b0 + B x as nmod_mat operations, then one solve."""
        m0, mk, b0, bmat = prep.matrices
        m = m0
        for k, v in enumerate(x):
            if v:
                m = m + mk[k] * v
        return self._solve(m, b0 + bmat * flint.nmod_mat([[v] for v in x], self.p))

    def _solve(self, m: flint.nmod_mat, b: flint.nmod_mat) -> list[int]:
        try:
            sol = m.solve(b)
        except ZeroDivisionError:
            raise UnluckyPrimeError(f"det M(x, eps) = 0 mod {self.p}") from None
        return [int(sol[i, 0]) for i in range(b.nrows())]

    def basis_row(self, prep: Prepared, x: Sequence[int]) -> list[int]:
        row = []
        for num, den in prep.basis:
            d = self.evaluate(den, x) % self.p
            if d == 0:
                raise UnluckyPrimeError(f"a basis denominator vanishes mod {self.p} on the orbit")
            row.append(self.evaluate(num, x) * pow(d, -1, self.p) % self.p)
        return row

    def solve(self, m: list[list[int]], b: list[int]) -> list[int]:
        return self._solve(flint.nmod_mat(m, self.p), flint.nmod_mat([[v] for v in b], self.p))

    def prefix_ranks(self, rows: list[list[int]]) -> tuple[list[int], dict]:
        r, rank = flint.nmod_mat(rows, self.p).transpose().rref()
        return _ranks_from_pivots(_pivot_columns(r, rank), len(rows)), {"prime": self.p}

    def kernel(self, raw: RawProfile, d: int) -> list[list[int]]:
        rows = raw.rows[:len(raw.rows[0]) - d]
        r, rank = flint.nmod_mat(rows, self.p).rref()
        return _free_kernel(r, rank, len(rows[0]), lambda i, j: 0 if i is None else int(r[i, j]), self.p - 1)


class Modular(Arithmetic):
    """Ranks mod large random primes: a second prime checks the first; an unlucky prime is replaced.

    Ranks mod p never exceed ranks over Q, so when two primes disagree the larger ranks are kept and the
    other prime is reported as unlucky and replaced.
    """

    name = "modular"

    def __init__(self, primes: Sequence[int] = (), *, seed: int = 0, checks: int = 1, bits: int = 62,
                 max_primes: int = 6):
        self.pool = list(primes)
        self._rng = random.Random(seed)
        self.checks = checks
        self.bits = bits
        self.max_primes = max_primes
        self._fields: dict[int, ModP] = {}

    def field(self, index: int) -> ModP:
        """The index-th prime of the pool (drawn at random when the pool is exhausted)."""
        while len(self.pool) <= index:
            self.pool.append(random_prime(self._rng, self.bits))
        p = self.pool[index]
        if p not in self._fields:
            self._fields[p] = ModP(p)
        return self._fields[p]

    def profile(self, scene, basis, point) -> RawProfile:
        results: list[tuple[int, RawProfile]] = []
        unlucky: list[dict] = []
        for index in range(self.max_primes):
            f = self.field(index)
            try:
                raw = f.profile(scene, basis, point)
            except UnluckyPrimeError as exc:
                unlucky.append({"prime": f.p, "reason": str(exc)})
                continue
            results.append((f.p, raw))
            best = max(results, key=lambda pr: sum(pr[1].ranks))[1].ranks
            agree = [q for q, r in results if r.ranks == best]
            if len(agree) > self.checks:
                unlucky += [{"prime": q, "reason": f"ranks {r.ranks} below {best}"}
                            for q, r in results if r.ranks != best]
                raw_best = next(r for q, r in results if q == agree[0])
                certainty = {"arithmetic": self.name, "method": f"ranks mod {len(agree)} primes agree",
                             "primes": agree, "unlucky_primes": unlucky, "prime": agree[0]}
                return RawProfile(raw_best.ranks, raw_best.rows, certainty)
        if not results:
            raise SingularPointError(
                f"det M vanishes or a denominator is divisible by p for {self.max_primes} primes: "
                "the orbit most likely meets Delta = 0")
        raise UnluckyPrimeError(f"{self.max_primes} primes gave no two agreeing rank profiles: {unlucky}")

    def kernel(self, raw: RawProfile, d: int) -> list[list[int]]:
        return self._fields[raw.certainty["prime"]].kernel(raw, d)


# ---- floating point: float64 (numpy) and mpmath --------------------------------------------------
class Approximate(FieldArithmetic):
    """Floating point with unit roundoff u: a rank is decided only across a clear singular-value gap.

    The noise level nu of X (rows scaled to norm 1) is estimated from the rounding error carried along the
    orbit (first-order propagation through Df, plus cond(M) u at every solve).  Singular values <= G nu count
    as zero, >= G^2 nu as non-zero; one in between makes the rank "ambiguous" (None).

    A tiny singular value that is not zero looks like noise at one precision.  So zeros are confirmed at a
    higher precision (`confirmer`) when `confirm` is "always", or when it is "suspicious" and the orbit passes
    close to Delta = 0 (cond M >= u^(-1/4)); prefixes whose ranks differ between the two precisions become
    "ambiguous".  `confirm = "never"` shows what one precision alone would say.
    """

    confirm = "suspicious"

    def __init__(self, unit_roundoff: float, gap: float = 100.0):
        super().__init__()
        self.u = unit_roundoff
        self.gap = gap

    def profile(self, scene, basis, point) -> RawProfile:
        prep = self.prepare(scene, basis)
        orbit = self.orbit(prep, point, len(basis) - 1)
        errors, cond = self.orbit_errors(prep, orbit)
        degree = max(sum(e for _, e in exps) for num, den in prep.basis for _, exps in num + den)
        rows = [self.basis_row(prep, x) for x in orbit]
        row_err = [max(1, degree) * (e + self.u) for e in errors]
        ranks, certainty = self.prefix_ranks(rows, row_err)
        certainty["orbit_error"] = max(errors)
        certainty["max_cond_M"] = cond
        zeros = any(r is not None and r < s for s, r in enumerate(ranks, 1))
        if zeros and (self.confirm == "always" or self.confirm == "suspicious" and cond >= self.u ** -0.25):
            other = self.confirmer().profile(scene, basis, point).ranks
            certainty["confirmed_with"] = self.confirmer().name
            certainty["confirmation"] = "agree" if other == ranks else "disagree"
            ranks = [a if a == b else None for a, b in zip(ranks, other)]
        return RawProfile(ranks, rows, {"arithmetic": self.name, **certainty})

    @abstractmethod
    def confirmer(self) -> "Approximate":
        """The same computation at a higher precision, to confirm zero singular values."""

    def orbit_errors(self, prep: Prepared, orbit: Sequence[list[Number]]) -> tuple[list[float], float]:
        """First-order relative error of each iterate (through Df = M^-1 (B - sum_k M_k x~ e_k^T), plus cond(M) u)
        and the largest cond(M) met on the orbit."""
        n = len(orbit[0])
        errors = [self.u]
        worst = 1.0
        for x, y in zip(orbit, orbit[1:]):
            m = [[self.affine(e, x) for e in row] for row in prep.matrix]
            dm = [[0.0] * n for _ in range(n)]
            for r, row in enumerate(prep.matrix):
                for c, (_, lin) in enumerate(row):
                    for k, coef in lin:
                        dm[r][k] = dm[r][k] - coef * y[c]
            for r, (_, lin) in enumerate(prep.rhs):
                for k, coef in lin:
                    dm[r][k] = dm[r][k] + coef
            jac_norm, cond = self.sensitivity(m, dm)
            xn, yn = float(self.norm(x)), float(self.norm(y))
            rel = jac_norm * errors[-1] * (xn / yn if yn else math.inf) + cond * self.u
            errors.append(float(min(rel, 1.0)))
            worst = max(worst, float(cond))
        return errors, worst

    def prefix_ranks(self, rows, row_err=None) -> tuple[list[int | None], dict]:
        nrows, ncols = len(rows), len(rows[0])
        if row_err is None:
            row_err = [self.u] * nrows
        colnorm = [self.norm([rows[i][j] for i in range(nrows)]) or 1 for j in range(ncols)]
        scaled = [[v / cn for v, cn in zip(r, colnorm)] for r in rows]
        scaled = [[v / (self.norm(r) or 1) for v in r] for r in scaled]
        ranks: list[int | None] = []
        worst_gap, worst_noise = math.inf, 0.0
        for s in range(1, nrows + 1):
            sigma = self.singular_values(scaled[:s])
            noise = math.sqrt(s * ncols) * max(row_err[:s]) + ncols * self.u
            worst_noise = max(worst_noise, noise)
            zero = [v for v in sigma if v <= self.gap * noise]
            big = [v for v in sigma if v >= self.gap**2 * noise]
            if len(zero) + len(big) != len(sigma) or self.gap**2 * noise >= 1:
                ranks.append(None)
                worst_gap = min(worst_gap, 1.0)
                continue
            ranks.append(len(big))
            if big and zero:
                worst_gap = min(worst_gap, float(min(big) / max(max(zero), 1e-300)))
        return ranks, {"method": "singular-value gap", "unit_roundoff": float(self.u),
                       "noise": worst_noise, "gap_ratio": worst_gap, "gap_factor": self.gap}

    def kernel(self, raw: RawProfile, d: int) -> list[list[Number]]:
        """The right singular vectors of the d smallest singular values, columns unscaled, then normalized."""
        rows = raw.rows[:len(raw.rows[0]) - d]
        ncols = len(rows[0])
        colnorm = [self.norm([r[j] for r in rows]) or 1 for j in range(ncols)]
        scaled = [[v / cn for v, cn in zip(r, colnorm)] for r in rows]
        vectors = self.null_vectors(scaled, d)
        vectors = [[v / cn for v, cn in zip(vec, colnorm)] for vec in vectors]
        return self.normalize(vectors)

    def normalize(self, vectors: list[list[Number]]) -> list[list[Number]]:
        """Make the last independent coordinates -I (greedy from the end, largest pivots)."""
        vecs = [list(v) for v in vectors]
        d, n = len(vecs), len(vecs[0]) if vecs else 0
        used: list[int] = []
        for i in range(d):
            scale = max(abs(v) for v in vecs[i]) or 1
            j = next(j for j in range(n - 1, -1, -1) if j not in used and abs(vecs[i][j]) > 1e-6 * scale)
            piv = vecs[i][j]
            vecs[i] = [-v / piv for v in vecs[i]]
            for k in range(d):
                if k != i:
                    f = vecs[k][j] / vecs[i][j]
                    vecs[k] = [a - f * b for a, b in zip(vecs[k], vecs[i])]
            used.append(j)
        return vecs

    @abstractmethod
    def norm(self, v: Sequence[Number]) -> Number:
        """Euclidean norm."""

    @abstractmethod
    def singular_values(self, rows) -> list[Number]:
        """Singular values, all of them (min(rows, cols))."""

    @abstractmethod
    def null_vectors(self, rows, d: int) -> list[list[Number]]:
        """Right singular vectors of the d smallest singular values (as rows)."""

    @abstractmethod
    def sensitivity(self, m, dm) -> tuple[float, float]:
        """(||M^-1 dm||, cond(M)) in the 2-norm."""


class Float64(Approximate):
    """IEEE double precision with numpy (SVD, solves)."""

    name = "float"

    def __init__(self, gap: float = 100.0, confirm: str = "suspicious"):
        super().__init__(float(np.finfo(float).eps) / 2, gap)
        self.confirm = confirm

    def number(self, q: flint.fmpq) -> float:
        return float(q)

    def confirmer(self) -> "MPMath":
        return MPMath(32, confirm="never")

    def solve(self, m, b) -> list[float]:
        a = np.array(m, dtype=float)
        if not np.all(np.isfinite(a)) or np.linalg.cond(a) > 1 / self.u:
            raise SingularPointError("det M(x, eps) = 0 to working precision (float64)")
        return [float(v) for v in np.linalg.solve(a, np.array(b, dtype=float))]

    def norm(self, v) -> float:
        return float(np.linalg.norm(np.array(v, dtype=float)))

    def singular_values(self, rows) -> list[float]:
        return [float(v) for v in np.linalg.svd(np.array(rows, dtype=float), compute_uv=False)]

    def null_vectors(self, rows, d: int) -> list[list[float]]:
        a = np.array(rows, dtype=float)
        _, _, vt = np.linalg.svd(a)
        return [list(map(float, vt[-k])) for k in range(d, 0, -1)]

    def sensitivity(self, m, dm) -> tuple[float, float]:
        a = np.array(m, dtype=float)
        return float(np.linalg.norm(np.linalg.solve(a, np.array(dm, dtype=float)), 2)), float(np.linalg.cond(a))

    def to_json(self, value) -> float:
        return float(value)


class MPMath(Approximate):
    """mpmath at a chosen number of decimal digits (svd_r, lu_solve)."""

    def __init__(self, dps: int = 50, gap: float | None = None, confirm: str = "always"):
        super().__init__(10.0 ** (-dps), gap if gap is not None else 10.0 ** max(2, dps // 8))
        self.dps = dps
        self.name = f"mpmath({dps})"
        self.confirm = confirm

    def profile(self, scene, basis, point) -> RawProfile:
        with mpmath.workdps(self.dps):
            raw = super().profile(scene, basis, point)
        raw.certainty["digits"] = self.dps
        return raw

    def kernel(self, raw, d):
        with mpmath.workdps(self.dps):
            return super().kernel(raw, d)

    def number(self, q: flint.fmpq) -> mpmath.mpf:
        return mpmath.mpf(int(q.p)) / int(q.q)

    def confirmer(self) -> "MPMath":
        return MPMath(2 * self.dps, confirm="never")

    def solve(self, m, b):
        a = mpmath.matrix(m)
        try:
            inv = mpmath.inverse(a)
        except ZeroDivisionError:
            inv = None
        if inv is None or mpmath.mnorm(a, "f") * mpmath.mnorm(inv, "f") > 1 / self.u:
            raise SingularPointError(f"det M(x, eps) = 0 to working precision ({self.dps} digits)")
        sol = inv * mpmath.matrix(b)
        return [sol[i] for i in range(len(b))]

    def norm(self, v):
        return mpmath.sqrt(mpmath.fsum(x * x for x in v))

    def singular_values(self, rows):
        s = mpmath.svd_r(mpmath.matrix(rows), compute_uv=False)
        return [s[i] for i in range(len(s))]

    def null_vectors(self, rows, d: int):
        a = mpmath.matrix(rows)
        if a.rows < a.cols:
            a = mpmath.matrix(list(rows) + [[0] * a.cols] * (a.cols - a.rows))
        _, s, v = mpmath.svd_r(a)
        order = sorted(range(len(s)), key=lambda i: s[i])
        return [[v[i, j] for j in range(a.cols)] for i in order[:d]][::-1]

    def sensitivity(self, m, dm):
        a = mpmath.matrix(m)
        inv = mpmath.inverse(a)
        return float(mpmath.mnorm(inv * mpmath.matrix(dm), "f")), float(mpmath.mnorm(a, "f") * mpmath.mnorm(inv, "f"))

    def to_json(self, value) -> str:
        return mpmath.nstr(value, min(self.dps, 20))


def get_arithmetic(name: str, *, digits: int = 50, seed: int = 0) -> Arithmetic:
    """'exact', 'modular', 'float' or 'mpmath' (at `digits` decimal digits)."""
    if name == "exact":
        return ExactQ()
    if name == "modular":
        return Modular(seed=seed)
    if name == "float":
        return Float64()
    if name == "mpmath":
        return MPMath(digits)
    raise ValueError(f"unknown arithmetic {name!r}: use exact, modular, float or mpmath")
