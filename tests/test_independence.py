"""Functional independence by an exact Jacobian at a rational point (hkproof.hk.independence), against sympy."""
from __future__ import annotations

import flint
import pytest
import sympy

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import get_ring
from hkproof.errors import ParseError, SingularPointError
from hkproof.hk.independence import derivative_at, gradient_at, jacobian_rank_at

NAMES = ("x", "y", "z", "eps")
TEXTS = ("(x**2*y + eps*z)/(1 + x*y - eps**2*z**2)", "x*y*z + eps", "(x + y)**2/(3 - z)")
POINT = {"x": flint.fmpq(2, 3), "y": 5, "z": flint.fmpq(-1, 7), "eps": flint.fmpq(1, 4)}


def test_gradients_agree_with_sympy():
    ring = get_ring(NAMES)
    symbols = sympy.symbols(NAMES)
    at = {s: sympy.Rational(str(POINT[str(s)])) for s in symbols}
    for text in TEXTS:
        h = Frac.parse(ring, text)
        expected = [sympy.diff(sympy.sympify(text), s).subs(at) for s in symbols[:3]]
        got = gradient_at(h, ["x", "y", "z"], POINT)
        assert [sympy.Rational(str(v)) for v in got] == expected
        assert derivative_at(h, "y", POINT) == got[1]


def test_rank_sees_a_dependent_function():
    ring = get_ring(NAMES)
    hs = [Frac.parse(ring, t) for t in TEXTS]
    assert jacobian_rank_at(hs, ["x", "y", "z"], POINT) == 3
    dependent = hs[0] * hs[1] + hs[1]
    assert jacobian_rank_at([hs[0], hs[1], dependent], ["x", "y", "z"], POINT) == 2


def test_a_pole_and_a_missing_value_are_clear_errors():
    ring = get_ring(NAMES)
    h = Frac.parse(ring, TEXTS[2])
    with pytest.raises(SingularPointError):
        gradient_at(h, ["x"], {**POINT, "z": 3})
    with pytest.raises(ParseError, match="no value given"):
        gradient_at(h, ["x"], {"x": 1, "y": 2})
