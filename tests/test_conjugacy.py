"""Kahan maps in other linear coordinates (hkproof.hk.conjugacy): the so(4) chart so(3) + so(3) is checked exactly,
a wrong chart is caught, and an integral proven in one chart is an integral in the other (checked there directly)."""
import pytest

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import SO4_SPLIT, SO4_SPLIT_FLOW2, kahan_map
from hkproof.errors import HKProofError
from hkproof.hk.conjugacy import LinearChart, conjugacy_mismatches, pull_back
from hkproof.hk.certified_integrals import certify
from hkproof.proof.status import Status

# a claim to check: the ratio of quadrics that `discover so4-euler-top-split` proves from the basis (u1 v1, u2 v2,
# u3 v3, 1)
SPLIT_INTEGRAL = ("(-u3*v3*eps**2*b1**2*b2 - u2*v2*eps**2*b1*b2**2 + u2*v2*eps**2*b1*b3**2 + u3*v3*eps**2*b2*b3**2 - b3)"
                  "/(-u3*v3*b1 - u2*v2*b2 + u1*v1*b3)")


def _chart(images=SO4_SPLIT) -> LinearChart:
    return LinearChart(kahan_map("so4-euler-top"), kahan_map("so4-euler-top-split"), images)


def test_so4_chart_conjugates_the_kahan_maps():
    assert conjugacy_mismatches(_chart()) == []


@pytest.mark.parametrize("name, image", [("b3", "(a1 - a2 - a3 - a4)/2"), ("u2", "m13 - m24"), ("v3", "m12 - 2*m34")])
def test_a_wrong_chart_is_caught(name, image):
    assert conjugacy_mismatches(_chart({**SO4_SPLIT, name: image}))


@pytest.mark.parametrize("name, image, message", [("u1", "m23*m14", "not a linear form"),
                                                  ("v1", "m23 + m14", "not invertible"),
                                                  ("u3", "m12 + eps", "not a linear form")])
def test_a_chart_that_is_not_linear_and_invertible_is_refused(name, image, message):
    with pytest.raises(HKProofError, match=message):
        _chart({**SO4_SPLIT, name: image}).substitution()


def test_a_missing_image_is_refused():
    with pytest.raises(HKProofError, match="no image"):
        _chart({k: v for k, v in SO4_SPLIT.items() if k != "b2"}).substitution()


def test_an_integral_of_the_split_map_pulled_back_is_an_integral_of_the_so4_map():
    split = kahan_map("so4-euler-top-split")
    h = Frac.parse(split.ring, SPLIT_INTEGRAL)
    assert certify(split, h).status is Status.VERIFIED
    (pulled,) = pull_back(_chart(), [h])
    assert pulled.variables() & {"m12", "a4"}
    assert certify(kahan_map("so4-euler-top"), pulled).status is Status.VERIFIED     # checked directly in m


def test_a_perturbed_integral_is_refuted_in_both_charts():
    split = kahan_map("so4-euler-top-split")
    h = Frac.parse(split.ring, SPLIT_INTEGRAL.replace("- b3)", "- 2*b3)"))
    assert certify(split, h).status is Status.REFUTED
    (pulled,) = pull_back(_chart(), [h])
    assert certify(kahan_map("so4-euler-top"), pulled).status is Status.REFUTED


@pytest.mark.slow
def test_split_integrals_are_constant_along_sympy_orbits_in_both_charts():
    """Independent route: the four integrals discover proves in the split chart (the fourth by step 5d) are constant
    along an orbit sympy computes from the split field, and pulled back, along one it computes from the so(4) field
    in m_ij."""
    from types import SimpleNamespace

    from hkproof.budget import Budget
    from hkproof.dynamics.catalogue import get_system
    from hkproof.pipelines.discover import discover
    from tests.sympy_bridge import constant_along_sympy_orbit
    report = discover("so4-euler-top-split", 2, budget=Budget(900))
    proven = [i for i in report.integrals if i.status is Status.VERIFIED and i.frac is not None and i.independent]
    assert len(proven) == 4
    assert not constant_along_sympy_orbit(get_system("so4-euler-top-split"), proven)
    pulled = pull_back(_chart(), [i.frac for i in proven])
    assert not constant_along_sympy_orbit(get_system("so4-euler-top"),
                                          [SimpleNamespace(name=i.name, frac=h) for i, h in zip(proven, pulled)])


def test_the_commuting_flow_in_the_split_chart_is_conjugate():
    """so4-euler-top-flow2-split is the commuting Manakov flow in the chart so(3) + so(3), with s = a1 + ... + a4."""
    chart = LinearChart(kahan_map("so4-euler-top-flow2"), kahan_map("so4-euler-top-flow2-split"), SO4_SPLIT_FLOW2)
    assert conjugacy_mismatches(chart) == []
    wrong = LinearChart(kahan_map("so4-euler-top-flow2"), kahan_map("so4-euler-top-flow2-split"),
                        {**SO4_SPLIT_FLOW2, "s": "a1 + a2 + a3 - a4"})
    assert conjugacy_mismatches(wrong)
