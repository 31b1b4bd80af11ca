"""Group clebsch-map (sec. 6.1-6.2): the Clebsch integrals and the discrete Clebsch map; corrections to the paper
recorded, perturbed claims refuted."""
from __future__ import annotations

import pytest

from hkproof.orchestration.registry import get_claim, proven
from hkproof.proof.status import Status
from tests.conftest import assert_group_certified


@pytest.mark.parametrize("claim_id,needle", [
    ("dc-continuous-integrals", "the right-hand side equals H2, not H1"),
    ("dc-complexity", "have total degree 5"),
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
])
def test_perturbed_refuted(claim_id, key, text):
    cert = get_claim(claim_id).prove({key: text})
    assert cert.status is Status.REFUTED, cert.render()


def test_the_script_certifies_the_group(monkeypatch, capsys):
    assert_group_certified("clebsch-map", monkeypatch, capsys)
