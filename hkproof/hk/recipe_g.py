"""Recipe (G) with a certificate: delta(x, x~) = p(x~) q(x) - p(x) q(x~) in the ideal of the Kahan equations.

The Kahan equations E = M(x) x~ - b(x) are linear in x~. With A = adj M and Delta = det M, A E = Delta x~ - N
(N = A b), so x~_j = N_j / Delta modulo the ideal after multiplying by Delta. Writing Delta^d delta as a
polynomial H(x, Delta x~) (d = degree of delta in x~) and telescoping H(Delta x~) - H(N) with divided
differences gives explicit cofactors in factored form: Delta^d delta = sum_j q_j (A E)_j + H(N), i.e.
lambda = A^T q, and H(N) = Delta^d delta(x, N/Delta) is the substitution residual. When it vanishes the certificate
Delta^d delta = sum_j q_j (A E)_j is checked by plain expansion (the six (A E)_j are small; lambda itself, 36
products of q and A, is expanded only for export). It proves: wherever Delta(x) != 0 (the Kahan equations have the
unique solution x~ = f(x)), delta(x, f(x)) = 0, i.e. c(f(x)) = c(x) wherever q(x) q(f(x)) != 0 -- c is an integral of f.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from functools import lru_cache

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.groebner import MembershipCertificate, groebner_basis, in_ideal
from hkproof.algebra.linalg import det
from hkproof.dynamics.kahan import KahanMap
from hkproof.proof.status import Status

__all__ = ["adjugate_data", "delta_polynomial", "eliminate", "groebner_membership", "recipe_g", "RecipeGResult",
           "WHAT_IT_PROVES"]

WHAT_IT_PROVES = ("Delta^k * delta = sum_i lambda_i E_i in Z[x, x~, eps, params] with lambda = adj(M)^T q "
                  "(checked by expansion as sum_j q_j (adj(M) E)_j), Delta = det M; "
                  "hence on the open set Delta(x) != 0, where x~ = f(x) is the unique solution of the Kahan equations, "
                  "p(f(x)) q(x) = p(x) q(f(x)), i.e. c o f = c wherever q(x) q(f(x)) != 0")


def delta_polynomial(kmap: KahanMap, c: Frac) -> flint.fmpz_mpoly:
    """delta(x, x~) = p(x~) q(x) - p(x) q(x~) in Z[x, x~, eps, params] (recipe (G), step ii)."""
    t, r = kmap.field.tilde_ring, kmap.ring
    to_tilde = {v: t.gen(w) for v, w in zip(kmap.variables, kmap.field.tilde_variables, strict=True)}
    p, q = r.substitute(c.num, to_tilde, t), r.substitute(c.den, to_tilde, t)
    p0, q0 = r.substitute(c.num, {}, t), r.substitute(c.den, {}, t)
    return p * q0 - p0 * q


@lru_cache(maxsize=None)
def adjugate_data(kmap: KahanMap) -> tuple[list[list[flint.fmpz_mpoly]], flint.fmpz_mpoly, list[flint.fmpz_mpoly]]:
    """(A, Delta, N) over the tilde ring: A = adj M (A M = Delta I), Delta = det M, N = A b (no gcd cancelled)."""
    t = kmap.field.tilde_ring
    m, b = kmap.matrix
    n = len(b)
    up = [[kmap.ring.substitute(e, {}, t) for e in row] for row in m]
    bt = [kmap.ring.substitute(e, {}, t) for e in b]
    zero, one = t.constant(0), t.constant(1)
    adj = [[det([[(one if r == i else zero) if col == j else up[r][col] for col in range(n)] for r in range(n)])
            for i in range(n)] for j in range(n)]
    delta = det(up)
    nums = [sum((adj[j][i] * bt[i] for i in range(n)), zero) for j in range(n)]
    return adj, delta, nums


def _tilde_degree(p: flint.fmpz_mpoly, tilde_idx: list[int]) -> int:
    """Total degree of p in the x~ variables."""
    return max((sum(mon[i] for i in tilde_idx) for mon in p.monoms()), default=0)


def eliminate(kmap: KahanMap, target: flint.fmpz_mpoly) -> tuple[MembershipCertificate, flint.fmpz_mpoly]:
    """(certificate, residual) with Delta^d target = sum_j q_j (A E)_j + residual, A = adj M, residual in
    Z[x, eps, params] (the certificate's weights are q, its combination A).

    The certificate is valid (check() is True) iff the residual is zero.
    """
    t = kmap.field.tilde_ring
    n = len(kmap.variables)
    adj, delta, nums = adjugate_data(kmap)
    tilde = list(kmap.field.tilde_variables)
    tidx = [t.index(v) for v in tilde]
    d = _tilde_degree(target, tidx)
    # H(x, u, D): target with x~_j -> u_j and each monomial homogenized by D up to degree d; extra names u_j, v_j, D
    s = t.extend([f"_u{j}" for j in range(n)] + [f"_v{j}" for j in range(n)] + ["_D"])
    u = [s.gen(f"_u{j}") for j in range(n)]
    v = [s.gen(f"_v{j}") for j in range(n)]
    data = {}
    width = len(s.names)
    for mon, coef in target.to_dict().items():
        e = [0] * width
        for k, ex in enumerate(mon):
            if k in tidx:
                e[len(t.names) + tidx.index(k)] = ex
            else:
                e[k] = ex
        e[-1] = d - sum(mon[i] for i in tidx)
        data[tuple(e)] = coef
    h = s.ctx.from_dict(data)
    gens = list(s.gens())
    # telescoping: H(u) - H(v) = sum_j (u_j - v_j) Q_j, Q_j = [H(v_<j, u_j, u_>j) - H(v_<j, v_j, u_>j)] / (u_j - v_j)
    back = [t.gen(nm) for nm in t.names] + [delta * t.gen(x) for x in tilde] + list(nums) + [delta]
    weights = []
    current = h
    for j in range(n):
        args = list(gens)
        args[len(t.names) + j] = v[j]
        nxt = current.compose(*args)
        weights.append(((current - nxt) / (u[j] - v[j])).compose(*back, ctx=t.ctx))
        current = nxt
    residual = current.compose(*back, ctx=t.ctx)
    cert = MembershipCertificate(target, list(kmap.equations), weights, delta, d, adj)
    return cert, residual


@dataclass
class RecipeGResult:
    """Outcome of recipe (G) for c = p/q: verified with a checked certificate, or refuted by a non-zero residual."""

    status: Status
    power: int
    certificate_terms: int
    residual_terms: int
    seconds: dict
    certificate: MembershipCertificate | None = None      # the checked identity, when verified

    def to_dict(self) -> dict:
        return {"verdict": self.status.label, "multiplier": f"det M ^ {self.power}",
                "certificate_terms": self.certificate_terms,
                "residual_terms": self.residual_terms, "seconds": {k: round(x, 4) for k, x in self.seconds.items()},
                "proves": WHAT_IT_PROVES if self.status is Status.VERIFIED else
                "delta(x, f(x)) = residual / Delta^k is not identically zero: c o f != c"}


def recipe_g(kmap: KahanMap, c: Frac) -> RecipeGResult:
    """Decide c o f = c by recipe (G): cofactors by elimination of x~, certificate checked by expansion."""
    start = time.perf_counter()
    target = delta_polynomial(kmap, c)
    cert, residual = eliminate(kmap, target)
    built = time.perf_counter()
    if not residual.is_zero():
        return RecipeGResult(Status.REFUTED, cert.power, cert.terms, len(residual),
                             {"cofactors": built - start, "check": 0.0})
    ok = cert.check()
    checked = time.perf_counter()
    if not ok:
        raise AssertionError("recipe (G): the cofactor identity failed to expand to Delta^k delta (internal error)")
    return RecipeGResult(Status.VERIFIED, cert.power, cert.terms, 0,
                         {"cofactors": built - start, "check": checked - built}, cert)


def groebner_membership(kmap: KahanMap, c: Frac, power: int = 0,
                        limits: tuple[int, int, int] | None = None) -> bool | None:
    """Recipe (G) literally: Delta^power delta reduced modulo a Groebner basis of the Kahan ideal in Q[x, x~, ...].

    None when Buchberger stopped at `limits`. The parameters live in the ring as variables, so use it on a map
    whose parameters are fixed (field.specialize) unless the system is tiny.
    """
    basis = groebner_basis(list(kmap.equations), limits)
    if basis is None:
        return None
    target = delta_polynomial(kmap, c)
    if power:
        target = target * adjugate_data(kmap)[1] ** power
    return in_ideal(target, basis)
