"""sympy -> FLINT conversion for the tests' independent cross-checks (the package itself never reads sympy input)."""
from __future__ import annotations

from typing import Mapping, Sequence

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


def kahan_orbit(rhs: Sequence[str], variables: Sequence[str], values: Mapping[str, object], steps: int
                ) -> list[dict[str, sympy.Rational]]:
    """An orbit of Kahan's map with sympy alone, from the field's printed components (test data, not user text):
    x~ - x = eps (F(x + x~) - F(x) - F(x~)), linear in x~, solved exactly at rational values."""
    xs = [sympy.Symbol(v) for v in variables]
    ys = [sympy.Symbol(f"{v}_next") for v in variables]
    consts = {sympy.Symbol(k): sympy.Rational(str(v)) for k, v in values.items() if k not in variables}
    field = [sympy.sympify(t, locals={str(s): s for s in [*xs, *consts]}).subs(consts) for t in rhs]
    eps = consts[sympy.Symbol("eps")]
    point = {x: sympy.Rational(str(values[str(x)])) for x in xs}
    orbit = [dict(point)]
    for _ in range(steps):
        def at(args: Sequence[sympy.Expr]) -> list[sympy.Expr]:
            return [F.subs(dict(zip(xs, args)), simultaneous=True) for F in field]
        here = [point[x] for x in xs]
        summed, alone, new = at([a + y for a, y in zip(here, ys)]), at(here), at(ys)
        eqs = [sympy.expand(y - a - eps * (s - p - q)) for y, a, s, p, q in zip(ys, here, summed, alone, new)]
        (sol,) = sympy.linsolve(eqs, ys)
        point = dict(zip(xs, sol))
        orbit.append(dict(point))
    return [{str(k): v for k, v in p.items()} for p in orbit]
