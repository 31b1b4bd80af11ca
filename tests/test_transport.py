"""hk/transport.Substitution: names replaced by rational functions (one compose), as the sec. 6 proofs use it."""
from __future__ import annotations

from fractions import Fraction

import flint
import pytest

from hkproof.algebra import Frac
from hkproof.algebra.ring import get_ring
from hkproof.errors import HKProofError
from hkproof.hk.transport import Substitution

R = get_ring(("x", "y"))
BIG = R.extend(["A", "L"])


def test_names_replaced_by_fractions_agree_with_the_direct_formula():
    sigma = Substitution(BIG, R, {"A": Frac.parse(R, "x/(y + 1)"), "L": Frac.parse(R, "1/x")})
    q = Frac.parse(BIG, "A**2*L - x/(A + L)")
    direct = Frac.parse(R, "(x/(y + 1))**2/x - x/(x/(y + 1) + 1/x)")
    assert sigma.apply(q) == direct
    assert direct.is_ratio(*sigma.apply_terms(q))
    assert sigma.apply(q) != Frac.parse(R, "(x/(y + 1))**2/x + x/(x/(y + 1) + 1/x)")


def test_a_kept_name_missing_from_the_target_is_refused():
    with pytest.raises(HKProofError):
        Substitution(BIG, R, {"A": Frac.parse(R, "x")})


def test_a_triangular_substitution_cancels_by_units_exactly_as_a_gcd_would():
    """w -> w + y/z, e -> z*e (the reduction of sec. 6) extends to an automorphism of Q[x, e, w, y][1/z]: its
    `apply` cancels only a power of z and an integer, and gives the same lowest terms as Frac's gcd on random
    functions built to share factors with z-powers and integers."""
    import random

    source, target = get_ring(("x", "e", "w")), get_ring(("x", "e", "w", "y", "z"))
    sigma = Substitution(source, target, {"w": Frac.parse(target, "w + y/z"), "e": Frac.parse(target, "z*e")})
    assert sigma.units == ("z",)
    rng = random.Random(7)
    names = ("x", "e", "w")
    for _ in range(40):
        def poly() -> str:
            return " + ".join(f"{rng.randint(-5, 5)}*" + "*".join(f"{v}**{rng.randint(0, 3)}" for v in names)
                              for _ in range(rng.randint(1, 4)))
        shared = rng.choice(["1", "6", "e", "e**2*w", "(x + e*w)", "2*e*(w - x)"])
        h = Frac.parse(source, f"({poly()})*{shared}/(({poly()} + 1)*{shared})")
        num, den = sigma.apply_terms(h)
        assert sigma.apply(h) == Frac(target, num, den)       # Frac takes the full gcd


@pytest.mark.parametrize("images", [{"w": "w*e", "e": "e + 1"}, {"w": "w**2 + 1"}, {"w": "x + 1"}, {"w": "w/(w + 1)"},
                                    {"w": "(w + e)/z", "e": "z*e"}, {"w": "w + y/(z + 1)"}])
def test_substitutions_that_are_not_triangular_automorphisms_take_the_gcd(images):
    """A leading term that is not a unit times the name itself, a name replaced by another, a denominator that is
    not a monomial, or a remainder involving another moved name: no units, so `apply` takes the gcd."""
    source, target = get_ring(("x", "e", "w")), get_ring(("x", "e", "w", "y", "z"))
    sigma = Substitution(source, target, {k: Frac.parse(target, v) for k, v in images.items()})
    assert sigma.units is None


def test_a_denominator_shared_by_several_functions_is_composed_once_with_the_same_result():
    source, target = get_ring(("x", "e", "w")), get_ring(("x", "e", "w", "y", "z"))
    images = {"w": Frac.parse(target, "w + y/z"), "e": Frac.parse(target, "z*e")}
    sigma = Substitution(source, target, images)
    den = "(x**2*e + w**3 - 2*e*w + 1)"
    functions = [Frac.parse(source, f"({n})/{den}") for n in ("x", "e*w - x", "w**2 + 3")]
    got = [sigma.apply(h) for h in functions]
    assert got == [Substitution(source, target, images).apply(h) for h in functions]    # fresh: no cache
    assert len(sigma._composed) == 1


def test_the_pullback_point_gives_the_value_of_the_image():
    """sigma(h)(P) = h(sigma*(P)): what flow-conjecture evaluates instead of forming sigma(h); a point that ignores
    an image (the kept value of w) gives another value."""
    source, target = get_ring(("x", "e", "w")), get_ring(("x", "e", "w", "y", "z"))
    sigma = Substitution(source, target, {"w": Frac.parse(target, "w + y/z"), "e": Frac.parse(target, "z*e")})
    h = Frac.parse(source, "(x**2 + e**2*w)/(w - x + 3)")
    point = {"x": 2, "e": Fraction(1, 3), "w": 5, "y": -1, "z": Fraction(7, 2)}
    at = sigma.pullback(point)
    assert at == {"x": flint.fmpq(2), "e": flint.fmpq(7, 6), "w": flint.fmpq(33, 7)}
    assert h.evaluate(at) == sigma.apply(h).evaluate(point)
    assert h.evaluate({**at, "w": 5}) != sigma.apply(h).evaluate(point)


@pytest.mark.parametrize("images,commutes", [
    ({"w": "w + y/z", "e": "z*e"}, True),          # the reduction of sec. 6
    ({"e": "y*e"}, True),                          # sigma0
    ({"w": "w + e", "e": "z*e"}, False),           # an image of w odd in e
    ({"e": "e + y"}, False),                       # an image of e not odd
    ({"w": "w + e**2", "e": "e**3*z"}, True),
])
def test_sigma_commutes_with_the_sign_of_eps_exactly_when_its_images_say_so(images, commutes):
    """Substitution.commutes_with_sign: the image of e odd in e and the others even; then sigma keeps functions
    even in e even (checked on one even function), and otherwise it does not."""
    source, target = get_ring(("x", "e", "w")), get_ring(("x", "e", "w", "y", "z"))
    sigma = Substitution(source, target, {k: Frac.parse(target, v) for k, v in images.items()})
    assert sigma.commutes_with_sign("e") is commutes
    even = Frac.parse(source, "(x + e**2*w)/(1 + w*e**2 + x)")
    assert sigma.apply(even).is_even_in("e") is commutes


def test_apply_cancelled_removes_the_image_factors_without_a_gcd():
    """sigma(h) with L -> (x + y)/(y + 2): the numerator's factor x + y is cancelled from sigma(num) and sigma(den)
    by exact division; the quotient equals sigma(h), in lowest terms here, and differs from the uncancelled pair."""
    small = get_ring(("x", "y"))
    big = small.extend(["L"])
    sigma = Substitution(big, small, {"L": Frac.parse(small, "(x + y)/(y + 2)")})
    h = Frac.parse(big, "(L*x + x**2 + x*y)/(L*y**3 + L)")
    num, den = sigma.apply_cancelled(h)
    assert Frac(small, num, den) == sigma.apply(h)
    raw = sigma.apply_terms(h)
    assert len(raw[1]) > len(den) and (num.total_degree(), den.total_degree()) == (
        sigma.apply(h).num.total_degree(), sigma.apply(h).den.total_degree())
