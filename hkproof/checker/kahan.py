"""The checker's own Kahan map of a field read from a certificate: Cramer's rule on x~ - x = 2 eps F(x, x~) (eq. "Kahan
gen", eps = h/2), compositions h(N/Delta) Delta^d by one compose of h homogenized, det Df by one bordered determinant.
Sizes are bounded before the work (MAX_VARIABLES, MAX_DEGREE): a composition beyond them is refused with a
ResourceLimitError (exit 4) instead of exhausting memory inside FLINT."""
from __future__ import annotations

import hashlib
from typing import Any, Mapping, Sequence

import flint

from hkproof.algebra.formula import check_name, parse_formula, tokens
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring
from hkproof.checker.reading import get, strings
from hkproof.errors import CertificateError, HKProofError, Refutation, ResourceLimitError

__all__ = ["EPS", "KahanData", "MAX_DEGREE", "MAX_VARIABLES", "read", "det", "minors"]

EPS = "eps"
MAX_VARIABLES = 12         # phase variables: the Laplace determinants keep at most 2^12 minors
MAX_DEGREE = 1000          # degree in the phase variables of a composition h(N/Delta) Delta^d
Poly = flint.fmpz_mpoly



def _limit(what: str, limit: str) -> ResourceLimitError:
    return ResourceLimitError(f"{what}: above the checker's limit of {limit} (a certificate this large is not checked "
                              "on this machine)", limit=limit, raise_with="no option raises it")


class KahanData:
    """A field read from a certificate and its Kahan map f = N / Delta, rebuilt by Cramer's rule on
    x~ - x = 2 eps F(x, x~), F(x, y) = 2 F((x + y)/2) - (F(x) + F(y))/2 (eq. "Kahan gen", eps = h/2)."""

    def __init__(self, key: str, data: Any):
        where = f"field {key}"
        self.key = key
        self.variables = [check_name(v, "variable") for v in strings(data, "variables", where)]
        self.parameters = [check_name(v, "parameter") for v in strings(data, "parameters", where)]
        names = [*self.variables, EPS, *self.parameters]
        if len(set(names)) != len(names) or not self.variables:
            raise CertificateError(f"{where}: the variables, eps and the parameters must be distinct names")
        if len(self.variables) > MAX_VARIABLES:
            raise _limit(f"{where} has {len(self.variables)} phase variables", f"{MAX_VARIABLES} phase variables")
        self.ring = Ring(names)
        self._rhs = rhs = [self.parse(t, where) for t in strings(data, "rhs", where)]
        self._jacobian: Frac | None = None
        if len(rhs) != len(self.variables):
            raise CertificateError(f"{where}: {len(self.variables)} variables but {len(rhs)} right-hand sides")
        for v, g in zip(self.variables, rhs, strict=True):
            if EPS in g.variables() or g.den_variables_in(self.variables) or g.degrees_in(self.variables)[0] > 2:
                raise CertificateError(f"{where}: {v}' = {g} is not a quadratic polynomial in the phase variables "
                                       "free of eps")
        self.nums, self.delta = self._kahan()
        if self.delta.is_zero():
            raise CertificateError(f"{where}: the Kahan system is singular (det M = 0)")

    def summary(self, width: int = 300) -> str:
        """The right-hand sides as the checker read them (cut at `width` characters) and the sha256 of their full
        text: what a referee compares with the system the claim is about."""
        text = ", ".join(f"{v}' = {g}" for v, g in zip(self.variables, self._rhs, strict=True))
        digest = hashlib.sha256(text.encode()).hexdigest()[:16]
        return f"{text[:width]}{' ...' if len(text) > width else ''} [sha256 {digest}]"

    @property
    def rhs(self) -> list[Frac]:
        """The right-hand sides F_i as read."""
        return list(self._rhs)

    def parse(self, text: str, where: str) -> Frac:
        """A formula over the field's names, read exactly."""
        return read(self.ring, text, where)

    def parse_in(self, text: str, known: Mapping[str, Frac], where: str) -> Frac:
        """A formula in the names `known`, eps and the parameters only (no phase variable directly)."""
        allowed = {EPS, *self.parameters, *known}
        for tok in tokens(text):
            if tok.kind == "name" and tok.text not in allowed:
                raise CertificateError(f"{where}: {tok.text!r} in {text[:80]!r} is neither an integral proven "
                                       "before nor eps nor a parameter")
        return read(self.ring, text, where, known)

    def equations(self, tilde: Sequence[str]) -> tuple[Ring, list[Poly]]:
        """The Kahan equations E_i = d_i (y_i - x_i) - eps (4 g_i((x+y)/2) - g_i(x) - g_i(y)) for F_i = g_i/d_i, in
        Z[x, eps, params, y] with y named `tilde` (eq. "Kahan gen", eps = h/2)."""
        n, big = len(self.variables), Ring([*self.ring.names, *tilde])
        xs, ys = [big.gen(v) for v in self.variables], [big.gen(v) for v in tilde]
        z = flint.fmpz_mpoly_ctx.get((*self.ring.names, "_z"), "degrevlex")
        out = []
        for i, g in enumerate(self._rhs):
            num, den = (p.compose(*big.gens()[:len(self.ring.names)], ctx=big.ctx) for p in (g.num, g.den))
            hom = _homogenize(g.num, [self.ring.index(v) for v in self.variables], 2, z)
            mid = hom.compose(*[xs[k] + ys[k] if k < n else big.gens()[k] for k in range(len(self.ring.names))],
                              big.constant(2), ctx=big.ctx)
            at_y = big.substitute(num, dict(zip(self.variables, ys, strict=True)))
            out.append(den * (ys[i] - xs[i]) - big.gen(EPS) * (mid - num - at_y))
        return big, out

    def _kahan(self) -> tuple[list[Poly], Poly]:
        """(N_1..N_n, Delta) with f = N/Delta: the equations are linear in y = x~; Cramer's rule (fraction-free
        determinants)."""
        n = len(self.variables)
        big, equations = self.equations(self._tilde)
        rows = [[self._down(big, e.derivative(big.index(y))) for y in self._tilde] for e in equations]
        rhs_b = [-self._down(big, e) for e in equations]
        delta = det(rows)
        nums = [det([[rhs_b[r] if c == j else rows[r][c] for c in range(n)] for r in range(n)]) for j in range(n)]
        return nums, delta

    def jacobian(self) -> Frac:
        """det Df from the map itself (computed once): Df = (Delta dN - N grad(Delta)^T) / Delta^2, and
        det(Delta J - u v^T) = Delta^(n-1) det [[Delta, v^T], [u, J]] (Schur complement), so
        det Df = det [[Delta, grad(Delta)^T], [N, dN]] / Delta^(n+1): one bordered determinant of the small entries."""
        if self._jacobian is None:
            idx = [self.ring.index(v) for v in self.variables]
            rows = [[self.delta, *(self.delta.derivative(k) for k in idx)],
                    *([p, *(p.derivative(k) for k in idx)] for p in self.nums)]
            self._jacobian = Frac(self.ring, det(rows), self.delta ** (len(idx) + 1))
        return self._jacobian

    @property
    def _tilde(self) -> list[str]:
        """Names for x~ in Cramer's rule: a leading '_' keeps them apart from every name a file can use."""
        return [f"_y{k}" for k in range(len(self.variables))]

    def _degree(self, p: Poly) -> int:
        """The total degree of p in the phase variables."""
        idx = [self.ring.index(v) for v in self.variables]
        return max((sum(m[k] for k in idx) for m in p.monoms()), default=0)

    def _down(self, big: Ring, p: Poly) -> Poly:
        """p with y = 0, in the field's ring."""
        return big.substitute(p, dict.fromkeys(self._tilde, 0), self.ring)

    def image(self, i: int) -> tuple[list[Poly], Poly]:
        """f^i = (N, Delta) for i in {-1, 1} (f^-1(x, eps) = f(x, -eps)); the identity for i = 0."""
        if i == 0:
            return [self.ring.gen(v) for v in self.variables], self.ring.constant(1)
        if i == 1:
            return self.nums, self.delta
        flip = {EPS: -self.ring.gen(EPS)}
        return [self.ring.substitute(p, flip) for p in self.nums], self.ring.substitute(self.delta, flip)

    def pull(self, h: Frac, i: int) -> Frac:
        """h o f^i, exactly."""
        nums, delta = self.image(i)
        idx = [self.ring.index(v) for v in self.variables]
        (pn, dn), (pd, dd) = (self._compose(p, idx, nums, delta) for p in (h.num, h.den))
        if pd.is_zero():
            raise Refutation(f"the denominator of {h} vanishes on the image of the Kahan map")
        return Frac(self.ring, pn * delta ** max(dd - dn, 0), pd * delta ** max(dn - dd, 0))

    def _compose(self, p: Poly, idx: list[int], nums: list[Poly], delta: Poly) -> tuple[Poly, int]:
        """(p(N/Delta) Delta^d, d), d the degree of p in the phase variables: one compose of p homogenized; refused
        before the work when the result's degree d * deg f passes MAX_DEGREE."""
        d = self._degree(p)
        degree = d * max(self._degree(q) for q in (*nums, delta))
        if degree > MAX_DEGREE:
            raise _limit(f"composing a function of degree {d} with the Kahan map of field {self.key} gives degree "
                         f"{degree} in the phase variables", f"degree {MAX_DEGREE} for one composition")
        z = flint.fmpz_mpoly_ctx.get((*self.ring.names, "_z"), "degrevlex")
        args = list(self.ring.gens())
        for k, image in zip(idx, nums, strict=True):
            args[k] = image
        return _homogenize(p, idx, d, z).compose(*args, delta, ctx=self.ring.ctx), d


def read(ring: Ring, text: str, where: str, known: Mapping[str, Frac] | None = None) -> Frac:
    """A formula over `ring` (names in `known` stand for their values), read exactly; a CertificateError otherwise."""
    try:
        return parse_formula(ring, text, known)
    except HKProofError as exc:
        raise CertificateError(f"{where}: {exc}") from None


def _homogenize(p: Poly, idx: list[int], d: int, ctx: flint.fmpz_mpoly_ctx) -> Poly:
    """p with the extra last variable z making every term of degree d in the variables `idx` (and z)."""
    return ctx.from_dict({(*m, d - sum(m[k] for k in idx)): c for m, c in p.to_dict().items()})


def det(matrix: list[list[Poly]]) -> Poly:
    """The determinant of a square polynomial matrix by Laplace expansion (`minors`)."""
    zero = matrix[0][0] - matrix[0][0]
    return minors(matrix).get(tuple(range(len(matrix))), zero)


def minors(rows: list[list[Poly]]) -> dict[tuple[int, ...], Poly]:
    """The maximal minors of k rows of length n, keyed by their columns (sorted): Laplace expansion row by row from
    the bottom, each minor of the last rows computed once; no division, products of the rows' own entries."""
    n = len(rows[0])
    zero = rows[0][0] - rows[0][0]
    out: dict[tuple[int, ...], Poly] = {(): zero + 1}
    for row in reversed(rows):
        grown: dict[tuple[int, ...], Poly] = {}
        for cols, sub in out.items():
            for j in range(n):
                if j in cols or row[j].is_zero():
                    continue
                key = tuple(sorted((*cols, j)))
                term = row[j] * sub
                grown[key] = grown.get(key, zero) + (-term if sum(c < j for c in cols) % 2 else term)
        out = grown
    return out
