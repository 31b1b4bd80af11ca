"""The Kahan equations in matrix form M(x, eps) x~ = b(x, eps), compared with a printed one (eqs. "dET", "dC")."""
from __future__ import annotations

from typing import Sequence

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.kahan import KahanMap
from hkproof.proof.certificate import StepRecorder

__all__ = ["require_matrix_form"]


def require_matrix_form(s: StepRecorder, kmap: KahanMap, want_m: Sequence[Sequence[Frac]],
                        want_b: Sequence[Frac] | None = None, normalize_rows: bool = False) -> None:
    """The coefficients (M, b) of x~ in the Kahan equations equal a printed matrix form M x~ = b (b = x if omitted).

    With `normalize_rows`, each row is divided by its diagonal entry first (the printed M has 1 on the diagonal
    while the equations were cleared of parameter denominators).
    """
    r = kmap.ring
    m, b = kmap.matrix
    want_b = want_b if want_b is not None else [Frac(r, r.gen(v)) for v in kmap.variables]
    n = len(b)
    s.require(len(want_m) == n and all(len(row) == n for row in want_m),
              f"the claimed M has shape {[len(row) for row in want_m]} (entries per row), the Kahan equations are "
              f"{n} x {n}")
    s.require(len(want_b) == n, f"the claimed right-hand side has {len(want_b)} entries, the Kahan equations {n}")
    for i in range(n):
        scale = Frac(r, m[i][i]) if normalize_rows else Frac(r, 1)
        s.require_equal(Frac(r, b[i]) / scale, want_b[i], f"right-hand side {i + 1}")
        for j in range(n):
            s.require_equal(Frac(r, m[i][j]) / scale, want_m[i][j], f"M[{i + 1},{j + 1}]")
