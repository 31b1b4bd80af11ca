"""sympy -> FLINT conversion for the tests' independent cross-checks (the package itself never reads sympy input)."""
from __future__ import annotations

import random
from fractions import Fraction
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
    x~ - x = 2 eps B(x, x~) with the polarization B(x, y) = 2 F((x + y)/2) - (F(x) + F(y))/2 of the quadratic F
    (linear and constant parts included), linear in x~, solved exactly at rational values."""
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
        middle, alone, new = at([(a + y) / 2 for a, y in zip(here, ys)]), at(here), at(ys)
        eqs = [sympy.expand(y - a - eps * (4 * m - p - q)) for y, a, m, p, q in zip(ys, here, middle, alone, new)]
        (sol,) = sympy.linsolve(eqs, ys)
        point = dict(zip(xs, sol))
        orbit.append(dict(point))
    return [{str(k): v for k, v in p.items()} for p in orbit]


def value_at(p: flint.fmpz_mpoly, names: Sequence[str], point: Mapping[str, object]) -> Fraction:
    """A polynomial's value at exact values, term by term in Python fractions (no hkproof evaluation)."""
    total = Fraction(0)
    for exps, c in zip(p.monoms(), p.coeffs()):
        term = Fraction(int(c))
        for name, e in zip(names, exps):
            if e:
                term *= Fraction(str(point[name])) ** int(e)
        total += term
    return total


def constant_along_sympy_orbit(field, integrals: Sequence, seed: int = 1, steps: int = 2) -> list[str]:
    """The names of the integrals (objects with .name and .frac) that are NOT constant along an orbit sympy computes
    from the printed field at random rational values of the variables, eps and the parameters (values where a
    denominator vanishes are drawn again)."""
    rng = random.Random(seed)
    names = [*field.variables, "eps", *field.parameters]
    while True:
        values = {n: Fraction(rng.choice([-1, 1]) * rng.randint(1, 29), rng.randint(1, 23)) for n in names}
        values["eps"] = Fraction(1, rng.randint(3, 9))
        try:
            orbit = kahan_orbit([str(c) for c in field.rhs], field.variables, values, steps)
            return [integral.name for integral in integrals
                    if len({_value(integral.frac, values | x) for x in orbit}) != 1]
        except (ZeroDivisionError, ValueError):
            continue


def _value(frac, point: Mapping[str, object]) -> Fraction:
    return value_at(frac.num, frac.ring.names, point) / value_at(frac.den, frac.ring.names, point)
