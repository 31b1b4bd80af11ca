"""The atlas systems are what docs/atlas.md says: their continuous integrals are checked here, exactly."""
from __future__ import annotations

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import get_system
from hkproof.hk.integrals import lie_derivative
from hkproof.proof.status import Status
from tests.conftest import assert_group_certified

# (system, continuous integrals: Casimirs and Hamiltonians) -- conventions of docs/atlas.md
CONTINUOUS = {
    "so4-euler-top": ["m12**2 + m13**2 + m14**2 + m23**2 + m24**2 + m34**2",          # -tr M^2 / 2
                      "m12*m34 - m13*m24 + m14*m23",                                  # Pf M
                      "(a1 + a2)*m12**2 + (a1 + a3)*m13**2 + (a1 + a4)*m14**2 + (a2 + a3)*m23**2"
                      " + (a2 + a4)*m24**2 + (a3 + a4)*m34**2",                        # -tr(M Omega) / 2
                      "(a1**2 + a1*a2 + a2**2)*m12**2 + (a1**2 + a1*a3 + a3**2)*m13**2"
                      " + (a1**2 + a1*a4 + a4**2)*m14**2 + (a2**2 + a2*a3 + a3**2)*m23**2"
                      " + (a2**2 + a2*a4 + a4**2)*m24**2 + (a3**2 + a3*a4 + a4**2)*m34**2"],
    # the last two: coefficients of lambda in tr (M + lambda A)^3 and tr (M + lambda A)^4, A = diag(a)
    "volterra-3": ["x1 + x2 + x3", "x1*x2*x3"],
    "volterra-4": ["x1 + x2 + x3 + x4", "x1*x3", "x2*x4"],
    "volterra-5": ["x1 + x2 + x3 + x4 + x5", "x1*x2*x3*x4*x5",
                   "x1**2 + x2**2 + x3**2 + x4**2 + x5**2 + 2*(x1*x2 + x2*x3 + x3*x4 + x4*x5 + x5*x1)"],
    "toda-3": ["b1 + b2 + b3", "a1*a2*a3", "b1**2 + b2**2 + b3**2 + 2*(a1**2 + a2**2 + a3**2)",
               "b1**3 + b2**3 + b3**3 + 3*(a1**2*(b1 + b2) + a2**2*(b2 + b3) + a3**2*(b3 + b1))"],
    "gaudin-2": ["s1**2 + s2**2 + s3**2", "t1**2 + t2**2 + t3**2", "s3 + t3", "b*s3 + g*(s1*t1 + s2*t2 + s3*t3)"],
    "zhukovsky-volterra": ["x1**2 + x2**2 + x3**2", "a1*x1**2 + a2*x2**2 + a3*x3**2 - 2*(b1*x1 + b2*x2 + b3*x3)"],
    "zhukovsky-volterra-1": ["x1**2 + x2**2 + x3**2", "a1*x1**2 + a2*x2**2 + a3*x3**2 - 2*b1*x1"],
    "lagrange-top": ["p1**2 + p2**2 + p3**2", "m1*p1 + m2*p2 + m3*p3", "m3", "m1**2 + m2**2 + a*m3**2 + 2*p3"],
    "kirchhoff": ["p1**2 + p2**2 + p3**2", "m1*p1 + m2*p2 + m3*p3", "m3",
                  "a*(m1**2 + m2**2) + a3*m3**2 + b*(p1**2 + p2**2) + b3*p3**2"],
}
FLOW2 = "so4-euler-top-flow2"


@pytest.mark.parametrize("name", sorted(CONTINUOUS))
def test_continuous_integrals(name):
    field = get_system(name)
    for text in CONTINUOUS[name]:
        h = Frac.parse(field.ring, text)
        assert lie_derivative(field, h).is_zero(), f"{text} is not an integral of {name}"


@pytest.mark.parametrize("name", sorted(CONTINUOUS))
def test_a_perturbed_integral_fails(name):
    field = get_system(name)
    h = Frac.parse(field.ring, CONTINUOUS[name][-1]) + Frac.parse(field.ring, f"{field.variables[0]}**2")
    assert not lie_derivative(field, h).is_zero()


def test_so4_flows_commute_and_share_integrals():
    """The second Manakov flow has the same integrals, and the two vector fields commute ([X, Y] = 0)."""
    f1, f2 = get_system("so4-euler-top"), get_system(FLOW2)
    for text in CONTINUOUS["so4-euler-top"]:
        assert lie_derivative(f2, Frac.parse(f2.ring, text)).is_zero()
    for v in f1.variables:
        x = Frac.parse(f1.ring, v)
        bracket = lie_derivative(f1, lie_derivative(f2, x)) - lie_derivative(f2, lie_derivative(f1, x))
        assert bracket.is_zero()


def test_atlas_claims_fail_when_perturbed():
    from hkproof.orchestration.registry import get_claim
    c = get_claim("atlas-volterra-3-integrals")
    assert c.prove().status == Status.VERIFIED
    assert c.prove({"independent": "3"}).status == Status.REFUTED
    k = get_claim("atlas-volterra-3-kernels")
    assert k.prove().status == Status.EVIDENCE_EXACT
    assert k.prove({"new_dimensions": "1,1,1"}).status == Status.REFUTED
    assert k.prove({"gradient_rank": "3"}).status == Status.REFUTED


def test_negative_results_are_evidence_not_verified():
    from hkproof.orchestration.registry import get_claim
    assert get_claim("atlas-toda-3-kernels").prove().status == Status.EVIDENCE_EXACT
    cert = get_claim("atlas-toda-3-integrals").prove()
    assert cert.status == Status.VERIFIED and list(cert.formulas) == ["I1"]
    ring = get_system("toda-3").ring
    times_sum = Frac.parse(ring, cert.formulas["I1"]) * Frac.parse(ring, "b1 + b2 + b3")
    assert not times_sum.variables()                   # a constant: I1 is a function of b1 + b2 + b3 alone


def test_the_script_certifies_the_group(monkeypatch, capsys):
    assert_group_certified("atlas", monkeypatch, capsys)


@pytest.mark.slow          # 30 s: the independent sympy cross-check of a verified claim
def test_commuting_flow_integrals_at_fixed_a_are_constant_along_a_sympy_orbit():
    """The four integrals of the commuting so(4) flow at a = (1, 2, 3, 5) (claim atlas-so4-euler-top-flow2-integrals),
    by an independent route: constant along an orbit sympy computes from the printed field at those values; a
    perturbed one is not."""
    from types import SimpleNamespace

    from hkproof.budget import Budget
    from hkproof.pipelines.discover import discover
    from hkproof.theorems.atlas import _A_FIXED
    from tests.sympy_bridge import constant_along_sympy_orbit
    fixed = dict(_A_FIXED)
    report = discover(FLOW2, 2, params=fixed, budget=Budget(600))
    proven = [i for i in report.integrals if i.frac is not None and i.status >= Status.VERIFIED_SPECIALIZED]
    assert len([i for i in proven if i.independent]) == 4
    field = get_system(FLOW2).specialize(fixed)
    assert constant_along_sympy_orbit(field, proven) == []
    bad = SimpleNamespace(name="bad", frac=proven[-1].frac + Frac.parse(proven[-1].frac.ring, "eps**2*m12"))
    assert constant_along_sympy_orbit(field, [bad]) == ["bad"]


@pytest.mark.slow
def test_commuting_flow_integrals_with_a_symbolic_are_proven_and_constant_along_a_sympy_orbit():
    """The commuting so(4) flow with a1..a4 symbolic (about 30 minutes on 2 cores): discover proves four independent
    integrals (step 5d, the row i = 1 on the lattice of hk.row_check), and each is constant along an orbit sympy
    computes from the printed field at random rational x, eps and a; a perturbed one is not."""
    from concurrent.futures import ProcessPoolExecutor
    from types import SimpleNamespace

    from hkproof.budget import Budget
    from hkproof.pipelines.discover import discover
    from tests.sympy_bridge import constant_along_sympy_orbit
    with ProcessPoolExecutor(2) as pool:
        report = discover(FLOW2, 2, budget=Budget(5400), mapper=pool.map)
    proven = [i for i in report.integrals if i.frac is not None and i.status is Status.VERIFIED]
    assert report.complete and len([i for i in proven if i.independent]) == 4
    assert any("principal lattice" in step.detail for i in proven for step in i.certificate.steps)
    field = get_system(FLOW2)
    assert constant_along_sympy_orbit(field, proven, steps=1) == []
    bad = SimpleNamespace(name="bad", frac=proven[0].frac + Frac.parse(proven[0].frac.ring, "eps**2*m12"))
    assert constant_along_sympy_orbit(field, [bad], steps=1) == ["bad"]
