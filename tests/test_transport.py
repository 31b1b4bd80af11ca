"""hk/transport.Substitution: names replaced by rational functions (one compose), as the sec. 6 proofs use it."""
from __future__ import annotations

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
