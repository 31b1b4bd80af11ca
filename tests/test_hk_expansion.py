"""hk.expansion: coefficients in eps, even pieces (Prop. "prop: even") and weighted degrees."""
from __future__ import annotations

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import get_ring
from hkproof.hk.expansion import even_pieces, weighted_degrees


def _poly(r, text):
    return Frac.parse(r, text).num


def test_even_pieces_of_an_even_polynomial_are_padded_to_the_bound():
    r = get_ring(("x", "y", "eps"))
    p = _poly(r, "1 + eps**2*x*y - eps**4*x**2")
    pieces = even_pieces(r, p, "eps", 6)
    assert pieces == [_poly(r, "1"), _poly(r, "x*y"), _poly(r, "-x**2"), _poly(r, "0")]


def test_even_pieces_refuses_an_odd_power_or_a_too_high_degree():
    r = get_ring(("x", "eps"))
    assert even_pieces(r, _poly(r, "1 + eps**3*x"), "eps", 6) is None
    assert even_pieces(r, _poly(r, "1 + eps**8*x"), "eps", 6) is None


def test_weighted_degrees_of_a_homogeneous_and_an_inhomogeneous_polynomial():
    r = get_ring(("x", "y", "eps"))
    ones = {"x": 1, "y": 1}
    assert weighted_degrees(r, _poly(r, "x**2 + eps*x*y"), ones) == {2}
    assert weighted_degrees(r, _poly(r, "x**2 + y"), ones) == {1, 2}
    assert weighted_degrees(r, _poly(r, "0"), ones) == set()
