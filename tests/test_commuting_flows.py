"""Group commuting-flows (sec. 7): the commutator at a rational point is zero for a map with itself and not for the
two flows."""
from __future__ import annotations

from hkproof.dynamics.catalogue import kahan_map
from hkproof.orchestration.registry import get_claim
from hkproof.proof.status import Status
from hkproof.theorems.commuting_flows import WITNESS, commutator_at
from tests.conftest import assert_group_certified


def test_a_map_commutes_with_itself_but_the_two_flows_do_not():
    f1, f2 = kahan_map("clebsch"), kahan_map("clebsch-flow2")
    assert all(d == 0 for d in commutator_at(f1, f1, WITNESS).values())
    assert any(d != 0 for d in commutator_at(f1, f2, WITNESS).values())


def test_claiming_commutation_or_a_shared_integral_is_refuted():
    assert get_claim("flows-commutation").prove({"commute": "yes"}).status is Status.REFUTED
    assert get_claim("flows-shared-integrals").prove({"shared_by_second_flow": "c1"}).status is Status.REFUTED


def test_the_script_certifies_the_group(monkeypatch, capsys):
    assert_group_certified("commuting-flows", monkeypatch, capsys)
