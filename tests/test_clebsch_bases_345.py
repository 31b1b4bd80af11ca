"""Section 6.7, Th. "dC bases 345": certified pieces, and perturbed relations / formulas refuted."""
from __future__ import annotations

import pytest

from hkproof.dynamics.catalogue import kahan_map
from hkproof.orchestration.registry import get_claim, proven
from hkproof.proof.status import Status
from hkproof.theorems.clebsch_bases import G1_VIA_ABCD
from hkproof.theorems.clebsch_bases_345.data import REL18, relation_rows
from tests.conftest import THEOREM_RESULTS
from tests.conftest import assert_group_certified

@pytest.mark.parametrize("claim_id,expected", [("dc345-abcd", Status.VERIFIED),
                                               ("dc345-step1", Status.VERIFIED),
                                               ("dc345-relations", Status.VERIFIED),
                                               ("dc345-relations-found", Status.EVIDENCE_EXACT),
                                               ("dc345-alpha", Status.VERIFIED),
                                               ("dc345-step5", Status.VERIFIED),
                                               ("dc345-max-basis", Status.VERIFIED),
                                               ("dc345-independence", Status.VERIFIED),
                                               ("dc345-dependence", Status.VERIFIED)])
def test_status(claim_id, expected):
    cert = proven(claim_id)
    THEOREM_RESULTS.append((claim_id, cert.status.label, cert.seconds))
    assert cert.status is expected, cert.render()


@pytest.mark.parametrize("claim_id,key,text", [
    ("dc345-relations", "rel18_1", "(w1 - w3)*a5 = (w1 - w2)*a6 + a4"),       # one coefficient changed
    ("dc345-relations", "rel18_6", REL18["rel18_6"].replace("(w3 - w1)", "(w1 - w3)", 1)),
    ("dc345-abcd", "add_1", "a4 - b4 - c4 = -d7/2"),                          # wrong sign
    ("dc345-abcd", "add_4_abcd", "D - (B - C)/(w2 - w3) = g4"),
    ("dc345-abcd", "abcd_dependence", "D**2 - A*B/((w1 - w3)*(w2 - w3)) + B*C/((w2 - w1)*(w3 - w1)) "
                                      "- C*A/((w3 - w2)*(w1 - w2)) = 0"),
    ("dc345-abcd", "M2", "a4 = D, a5 = A/(w1 - w2), a6 = A/(w1 - w3), b4 = B/(w2 - w3), b5 = D, "
                         "b6 = B/(w2 - w1), c4 = C/(w3 - w2), c5 = C/(w3 - w1), c6 = D"),
    ("dc345-alpha", "F_row", "(w2 - w3)*a1 - (w3 - w1)*a2 + (w1 - w2)*a3"),   # F with a wrong sign
    ("dc345-alpha", "F", "((w2 - w3)*(A*D + 1/4) + A*(B - C))/D"),
    ("dc345-alpha", "a1_2", "H3 + I1"),
    ("dc345-step5", "rel18_6", REL18["rel18_6"].replace("(w1 - w2)", "(w2 - w1)", 1)),
    ("dc-theta-dependence", "g1", G1_VIA_ABCD.replace("(w1 - w3)*(w2 - w3)*B", "w1*(w2 - w3)*B")),  # not invariant
    ("dc345-step1", "kernel_vector", "[(w2 - w3)*n, (w1 - w3)*n, (w1 - w2)*n]"),
])
def test_perturbed_refuted(claim_id, key, text):
    cert = get_claim(claim_id).prove({key: text})
    assert cert.status is Status.REFUTED, cert.render()


def test_relation_chain_parsed_as_two_rows():
    f = kahan_map("clebsch")
    assert len(relation_rows(f, REL18["rel18_4"])) == 2 and len(relation_rows(f, REL18["rel18_6"])) == 2


def test_the_script_certifies_the_group(monkeypatch, capsys):
    assert_group_certified("clebsch-bases-345", monkeypatch, capsys)
