"""The Jacobian of a Kahan map: M(x, eps) Df(x) = M(f(x), -eps), hence det Df = det M(f(x), -eps) / det M(x, eps).

Differentiating the bilinear Kahan equations E(x, f(x), eps) = 0 gives (I - eps F'(x)) Df = I + eps F'(f(x)); with the
rows of hkproof's M(x, eps) = diag(den) (I - eps F'(x)) this is the matrix identity above (Celledoni, McLachlan, Owren,
Quispel 2013, with h = 2 eps).  `matrix_identity_holds` checks it as a polynomial identity for a given map.
"""
from __future__ import annotations

import flint

from hkproof.algebra.fraction import Frac, homogenized_compose
from hkproof.algebra.linalg import det
from hkproof.dynamics.kahan import KahanMap

__all__ = ["det_m", "jacobian_determinant", "matrix_identity_holds", "pulled_matrix"]


def det_m(kmap: KahanMap) -> flint.fmpz_mpoly:
    """det M(x, eps) in Z[x, eps, params]."""
    return det(kmap.matrix[0])


def pulled_matrix(kmap: KahanMap) -> list[list[flint.fmpz_mpoly]]:
    """M(f(x), -eps) Delta(x): each entry of M is affine in x, one homogenized compose of degree 1."""
    r = kmap.ring
    nums, delta = kmap.explicit
    out = []
    for row in kmap.matrix[0]:
        line = []
        for e in row:
            q, d = homogenized_compose(r, kmap.negate_eps(e), kmap.variables, nums, delta)
            line.append(q * delta ** (1 - d))
        out.append(line)
    return out


def matrix_identity_holds(kmap: KahanMap) -> bool:
    """M(x, eps) (Delta dN/dx_j - N dDelta/dx_j) = Delta (Delta M0 + M1(N))|_(eps -> -eps), column by column, exactly:
    the identity M(x, eps) Df(x) = M(f(x), -eps) cleared of denominators (M = M0 + M1(x) affine in x)."""
    r = kmap.ring
    m = kmap.matrix[0]
    nums, delta = kmap.explicit
    n = len(kmap.variables)
    pulled = pulled_matrix(kmap)
    for j, v in enumerate(kmap.variables):
        k = r.index(v)
        col = [p.derivative(k) * delta - p * delta.derivative(k) for p in nums]
        for i in range(n):
            lhs = sum((m[i][l] * col[l] for l in range(n)), r.constant(0))
            if lhs != delta * pulled[i][j]:
                return False
    return True


def jacobian_determinant(kmap: KahanMap, expand: bool = True
                         ) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly, flint.fmpz_mpoly | None]:
    """det Df as (num, den, None) in lowest terms (expand), or as (1, det M(x, eps), det M(x, -eps)) meaning
    det M(x, -eps) o f / det M(x, eps) (the composition left unexpanded for large systems)."""
    dm = det_m(kmap)
    minus = kmap.negate_eps(dm)
    if not expand:
        return kmap.ring.constant(1), dm, minus
    jac = kmap.pullback(Frac(kmap.ring, minus)) / Frac(kmap.ring, dm)
    return jac.num, jac.den, None
