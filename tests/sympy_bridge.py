"""sympy -> FLINT conversion for the tests' independent cross-checks (the package itself never reads sympy input)."""
from __future__ import annotations

import flint
import sympy

from hkproof.algebra.ring import Ring


def poly_from_sympy(ring: Ring, expr: sympy.Expr) -> tuple[flint.fmpz_mpoly, int]:
    """(P, d) with expr = P/d, P with integer coefficients over `ring`, d a positive integer."""
    poly = sympy.Poly(sympy.expand(expr), *[sympy.Symbol(n) for n in ring.names], domain="QQ")
    den = 1
    for _, c in poly.terms():
        den = sympy.ilcm(den, sympy.Rational(c).q)
    data = {tuple(int(e) for e in m): int(sympy.Rational(c) * den) for m, c in poly.terms()}
    return ring.ctx.from_dict(data), int(den)
