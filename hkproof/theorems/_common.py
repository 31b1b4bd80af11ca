"""Small helpers shared by the theorem modules: reading claimed formulas in a map's ring."""
from __future__ import annotations

from typing import Sequence

from hkproof.algebra import formula
from hkproof.algebra.fraction import Frac
from hkproof.dynamics.kahan import KahanMap
from hkproof.proof.certificate import StepRecorder


def parse(kmap: KahanMap, text: str) -> Frac:
    """A claimed formula as an element of Q(x, eps, params) of the map."""
    return Frac.parse(kmap.ring, text)


def parse_matrix(kmap: KahanMap, text: str) -> list[list[Frac]]:
    """A claimed matrix written as a nested list '[[a, b], [c, d]]'."""
    return formula.parse_matrix(kmap.ring, text)


def monomial_squares(kmap: KahanMap, names: Sequence[str]) -> list[Frac]:
    """The basis functions v^2 for the given variables (and 1 for the name '1')."""
    return [Frac(kmap.ring, 1) if n == "1" else parse(kmap, f"{n}**2") for n in names]



def require_matrix_form(s: StepRecorder, kmap: KahanMap, want_m: Sequence[Sequence[Frac]],
                        want_b: Sequence[Frac] | None = None, normalize_rows: bool = False) -> None:
    """The coefficients (M, b) of x~ in the Kahan equations equal a printed matrix form M x~ = b (b = x if omitted).

    With `normalize_rows`, each row is divided by its diagonal entry first (the printed M has 1 on the diagonal
    while the equations were cleared of parameter denominators).
    """
    r = kmap.ring
    m, b = kmap.matrix
    want_b = want_b if want_b is not None else [Frac(r, r.gen(v)) for v in kmap.variables]
    for i in range(len(b)):
        scale = Frac(r, m[i][i]) if normalize_rows else Frac(r, 1)
        s.require_equal(Frac(r, b[i]) / scale, want_b[i], f"right-hand side {i + 1}")
        for j in range(len(b)):
            s.require_equal(Frac(r, m[i][j]) / scale, want_m[i][j], f"M[{i + 1},{j + 1}]")
