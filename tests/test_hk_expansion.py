"""hk.expansion: coefficients in eps, even pieces (Prop. "prop: even") and weighted degrees."""
from __future__ import annotations

import re

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import get_ring
from hkproof.hk.expansion import even_pieces, homogeneous_eps_pieces, support_degrees, support_stats, weighted_degrees
from hkproof.proof.certificate import Refuted


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


def test_homogeneous_eps_pieces_reads_the_form_and_refutes_a_broken_one():
    r = get_ring(("x", "y", "eps", "w"))
    h = Frac.parse(r, "(x**2 + eps**2*w*x**3*y + eps**4*y**6)/(w + 1)")
    pieces = homogeneous_eps_pieces(h, "eps", ("x", "y"), 3, 2, "h")
    assert pieces == [Frac.parse(r, t) for t in ("x**2/(w + 1)", "w*x**3*y/(w + 1)", "y**6/(w + 1)")]
    for broken, why in (("x**2 + eps*x**3", "eps^2"), ("x**2 + eps**2*x**3", "homogeneous"),
                        ("x**2/(1 + eps)", "not a polynomial"), ("x**2 + eps**6*x**8", "eps^2 of degree 2")):
        with pytest.raises(Refuted, match=re.escape(why)):
            homogeneous_eps_pieces(Frac.parse(r, broken), "eps", ("x", "y"), 3, 2, "h")


@pytest.mark.parametrize("names", [("x", "y"), ("x", "z"), ("z",)])
def test_support_stats_reads_the_monomials_in_the_given_names(names):
    """Degrees, distinct monomials in `names` and terms, read term by term, against the plain dictionary."""
    ring = get_ring(("x", "y", "z", "eps"))
    x, y, z, e = (ring.gen(v) for v in ring.names)
    p = (x + y * e + z ** 2 + 3) ** 4 - x ** 4 * (1 + e)
    idx = [ring.index(n) for n in names]
    monomials = {tuple(m[i] for i in idx) for m in p.to_dict()}
    stats = support_stats(ring, p, names)
    assert stats == {"degree": max(sum(m) for m in monomials), "monomials": len(monomials), "terms": len(p),
                     "degrees": {n: max(m[k] for m in monomials) for k, n in enumerate(names)}}
    without = {k: v for k, v in stats.items() if k != "monomials"}
    assert support_degrees(ring, p, names) == without          # no loop over the terms, the same degrees


def test_support_degrees_reads_the_total_degree_where_no_variable_peaks():
    """The total degree in the names is not the sum of their separate degrees (x^3 + y^3: 3, not 6), a name
    called t does not clash with the compose's new variable, and the zero polynomial has degree 0."""
    ring = get_ring(("x", "y", "t"))
    x, y, t = (ring.gen(v) for v in ring.names)
    assert support_degrees(ring, x ** 3 * t ** 5 + y ** 3 - x * y, ("x", "y")) == \
        {"degree": 3, "degrees": {"x": 3, "y": 3}, "terms": 3}
    assert support_degrees(ring, x ** 2 * t ** 7 + x * y * t, ("x", "t"))["degree"] == 9
    assert support_degrees(ring, x - x, ("x",)) == {"degree": 0, "degrees": {"x": 0}, "terms": 0}
