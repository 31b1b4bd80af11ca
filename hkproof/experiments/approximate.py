"""Algorithm (N) in floating point (float64 with numpy, mpmath at a chosen precision), deciding a rank only
across a clear singular-value gap and answering "ambiguous" otherwise."""
from __future__ import annotations

import math
from abc import abstractmethod
from itertools import pairwise
from typing import Sequence

import flint
import mpmath
import numpy as np

from hkproof.errors import SingularPointError
from hkproof.experiments.arithmetics import (
    FieldArithmetic,
    Number,
    Prepared,
    RawProfile,
)

__all__ = ["Approximate", "Float64", "MPMath"]


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

    def __init__(self, unit_roundoff: Number, gap: Number = 100.0):
        """`unit_roundoff` and `gap` in the arithmetic's own numbers: a binary float cannot hold mpmath's 10^-400."""
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
        certainty["orbit_error"] = float(max(errors))
        certainty["max_cond_M"] = cond
        zeros = any(r is not None and r < s for s, r in enumerate(ranks, 1))
        if zeros and (self.confirm == "always" or self.confirm == "suspicious" and cond >= self.u ** -0.25):
            checker = self.confirmer()
            other = checker.profile(scene, basis, point).ranks
            certainty["confirmed_with"] = checker.name
            certainty["confirmation"] = "agree" if other == ranks else "disagree"
            ranks = [a if a == b else None for a, b in zip(ranks, other, strict=True)]
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
        for x, y in pairwise(orbit):
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
            xn, yn = self.norm(x), self.norm(y)
            rel = jac_norm * errors[-1] * (xn / yn if yn else math.inf) + cond * self.u
            errors.append(min(rel, 1))
            worst = max(worst, float(cond))
        return errors, worst

    def prefix_ranks(self, rows, row_err=None) -> tuple[list[int | None], dict]:
        nrows, ncols = len(rows), len(rows[0])
        if row_err is None:
            row_err = [self.u] * nrows
        colnorm = [self.norm([rows[i][j] for i in range(nrows)]) or 1 for j in range(ncols)]
        scaled = [[v / cn for v, cn in zip(r, colnorm, strict=True)] for r in rows]
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
                       "noise": float(worst_noise), "gap_ratio": worst_gap, "gap_factor": float(self.gap)}

    def kernel(self, raw: RawProfile, d: int) -> list[list[Number]]:
        """The right singular vectors of the d smallest singular values, columns unscaled, then normalized."""
        rows = raw.rows[:len(raw.rows[0]) - d]
        ncols = len(rows[0])
        colnorm = [self.norm([r[j] for r in rows]) or 1 for j in range(ncols)]
        scaled = [[v / cn for v, cn in zip(r, colnorm, strict=True)] for r in rows]
        vectors = self.null_vectors(scaled, d)
        vectors = [[v / cn for v, cn in zip(vec, colnorm, strict=True)] for vec in vectors]
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
                    vecs[k] = [a - f * b for a, b in zip(vecs[k], vecs[i], strict=True)]
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
        super().__init__(mpmath.mpf(10) ** -dps, gap if gap is not None else mpmath.mpf(10) ** max(2, dps // 8))
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
