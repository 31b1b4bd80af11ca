"""Group clebsch-kernels (sec. 6.3): the proven bounds of Th. "dClebsch max basis" and the kernel profiles at points
(evidence only)."""
from __future__ import annotations

import pytest

from hkproof.orchestration.registry import get_claim
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status
from hkproof.theorems.clebsch_kernels import POINTS, check_kernel_profiles, kernel_evidence
from tests.conftest import assert_group_certified


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


def test_the_script_certifies_the_group(monkeypatch, capsys):
    assert_group_certified("clebsch-kernels", monkeypatch, capsys)
