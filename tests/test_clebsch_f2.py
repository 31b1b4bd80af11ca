"""Group clebsch-f2 (Table "f2" of sec. 6.2, slow): perturbed monomial counts and degrees are refuted."""
from __future__ import annotations

import pytest

from hkproof.orchestration.registry import get_claim, proven
from hkproof.proof.status import Status


@pytest.mark.slow
@pytest.mark.parametrize("claim_id,key,text", [
    ("dc-f2-plain", "p1_monomials", "64056"),
    ("dc-f2-reduced", "g_degree", "9"),
])
def test_f2_perturbed_refuted(claim_id, key, text):
    proven(claim_id)
    assert get_claim(claim_id).prove({key: text}).status is Status.REFUTED
