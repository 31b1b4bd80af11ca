"""Section 6, part I: the discrete Clebsch map, Table "f2", Th. "dC basis 1", "dC basis 2", "dC Theta", kernels."""
from __future__ import annotations

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.expansion import taylor
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.orchestration.registry import get_claim, proven
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import named
from hkproof.theorems.s6a_clebsch_bases import G1_VIA_ABCD, J_VIA_ABCD
from hkproof.theorems.s6a_clebsch_kernels import POINTS, check_kernel_profiles, kernel_evidence
from tests.conftest import THEOREM_RESULTS

FAST = ["dc-continuous-integrals", "dc-map-equations", "dc-explicit-map", "dc-map-symmetries", "dc-reversibility",
        "dc-complexity", "dc-basis1-relations", "dc-basis1-even", "dc-basis2", "dc-basis2-independence", "dc-theta",
        "dc-max-basis-bounds", "dc-theta-dependence"]
SLOW = ["dc-f2-plain", "dc-f2-reduced"]


@pytest.mark.parametrize("claim_id", FAST + [pytest.param(c, marks=pytest.mark.slow) for c in SLOW])
def test_verified(claim_id):
    cert = proven(claim_id)
    THEOREM_RESULTS.append((claim_id, cert.status.label, cert.seconds))
    assert cert.status is Status.VERIFIED, cert.render()


@pytest.mark.parametrize("claim_id,needle", [
    ("dc-continuous-integrals", "the right-hand side equals H2, not H1"),
    ("dc-complexity", "have total degree 5"),
    ("dc-basis2", "(w2 - w2) d9"),
])
def test_corrections_recorded(claim_id, needle):
    assert any(needle in c for c in proven(claim_id).corrections)


@pytest.mark.parametrize("claim_id,key,text", [
    ("dc-continuous-integrals", "H2", "w1*m1**2 + w2*m2**2 + w3*m3**2 - w2*w3*p1**2 - w3*w1*p2**2 - w1*w3*p3**2"),
    ("dc-continuous-integrals", "combination_3", "H3 = I1 + I2 + 2*I3"),
    ("dc-continuous-integrals", "change_of_basis_det", "(w1 - w2)*(w2 - w3)*(w3 - w1)"),
    ("dc-map-equations", "eq_p1", "p1_t - p1 - eps*(m3_t*p2 + m3*p2_t) + eps*(m2_t*p3 - m2*p3_t)"),
    ("dc-map-equations", "M", "[[1, 0, 0, 0, eps*(w2 - w3)*p3, eps*(w2 - w3)*p2], [0, 1, 0, eps*(w3 - w1)*p3, 0,"
                              " eps*(w3 - w1)*p1], [0, 0, 1, eps*(w1 - w2)*p2, eps*(w1 - w2)*p1, 0], [0, eps*p3,"
                              " -eps*p2, 1, -eps*m3, eps*m2], [-eps*p3, 0, eps*p1, eps*m3, 1, -eps*m1], [eps*p2,"
                              " -eps*p1, 0, -eps*m2, eps*m1, 2]]"),
    ("dc-complexity", "monomials_p_numerators", "30"),
    ("dc-complexity", "deg_denominator", "6"),
    ("dc-basis1-relations", "J", "(p1**2 + p2**2 + p3**2)/(1 + eps**2*(w1*p1**2 + w2*p2**2 + w3*p3**2))"),
    ("dc-basis1-relations", "relation_23", "c2 - c3 = eps**2*(w2 - w1)"),
    ("dc-basis1-relations", "twelve_variable_identity", "(p1_t + p1)*(m3_t*p2 + m3*p2_t) - (p1_t*p2 - p1*p2_t)*m3_t"),
    ("dc-basis1-even", "relation_12", "c1 - c2 = eps**2*(w1 - w3)"),
    ("dc-basis1-even", "c2", "(1 + eps**2*(w2 - w1)*p1**2 + eps**2*(w3 - w2)*p3**2)/(p1**2 + p2**2 + p3**2)"),
    ("dc-basis2", "relation", "(w2 - w3)*d7 + (w3 - w1)*d8 + (w1 - w3)*d9 = 0"),
    ("dc-basis2", "d8_2", "m1**2 + m2**2 + m3**2 + (w3 - w1)*p1**2 + (w3 + w1 - 2*w2)*p2**2 + (w3 - w1)*p3**2"),
    ("dc-basis2", "Delta_4", "m1*p1*d7_2 + m2*p2*d8_2 - m3*p3*d9_2"),
    ("dc-basis2-independence", "ratio_eps4", "(w2 - w1)*(2*H4**2 + w1*H3**2 - 2*H3*H1)"),
    ("dc-basis2-independence", "ratio_eps2", "(w1 - w2)*H3"),
    ("dc-theta-dependence", "g1", G1_VIA_ABCD.replace("(w1 - w3)*(w2 - w3)*B", "(w1 - w2)*(w2 - w3)*B")),
    ("dc-theta-dependence", "J", J_VIA_ABCD.replace("w3*D", "w2*D")),
])
def test_perturbed_refuted(claim_id, key, text):
    cert = get_claim(claim_id).prove({key: text})
    assert cert.status is Status.REFUTED, cert.render()


@pytest.mark.parametrize("key,text", [
    ("g_4", "2*H4**2 - H3*H1 - w_k*H3**2"),
    ("g5", "(g3 - g1)/(w1 - w3)"),
    ("rhs_forms", "(w3 - w1)*(w1 - w2)*(d9 - d8) = (w1 - w2)*(w2 - w3)*(d7 - d9)/2"),
])
def test_theta_perturbed_refuted(key, text):
    proven("dc-theta")  # the candidate solution is computed once; the perturbed keys are checked after it
    cert = get_claim("dc-theta").prove({key: text})
    assert cert.status is Status.REFUTED, cert.render()


def test_taylor_of_a_quotient():
    f = kahan_map("clebsch")
    h = named(f, "(1 + eps*m1)/(1 - eps**2*p1)")
    c = taylor(h, "eps", 3)
    assert [str(x) for x in c] == ["1", "m1", "p1", "m1*p1"]
    with pytest.raises(ZeroDivisionError):
        taylor(Frac(f.ring, 1) / named(f, "eps*m1"), "eps", 1)


def test_max_basis_bounds_refuted_when_perturbed():
    assert get_claim("dc-max-basis-bounds").prove({"upper": "3"}).status is Status.REFUTED


def test_kernels_are_evidence_only():
    cert = kernel_evidence(POINTS[:2])
    assert cert.status is Status.EVIDENCE_EXACT, cert.render()
    assert cert.steps[-1].points == 2


def test_kernel_profile_perturbed_refuted():
    cert = Certificate("x", "x", "x", "x")
    with pytest.raises(ProofStopped):
        check_kernel_profiles(cert, POINTS[:1], "9 8 7 6 5 4 3 3 3 3")
    assert cert.status is Status.REFUTED


def test_theta_dependence_rank_perturbed_refuted():
    assert get_claim("dc-theta-dependence").prove({"rank": "4"}).status is Status.REFUTED


@pytest.mark.slow
@pytest.mark.parametrize("claim_id,key,text", [
    ("dc-f2-plain", "p1_monomials", "64056"),
    ("dc-f2-reduced", "g_degree", "9"),
])
def test_f2_perturbed_refuted(claim_id, key, text):
    proven(claim_id)
    assert get_claim(claim_id).prove({key: text}).status is Status.REFUTED
