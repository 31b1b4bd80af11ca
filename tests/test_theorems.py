"""Every registered theorem: proven (status verified) and refuted when any claimed formula is perturbed."""
from __future__ import annotations

import re

import pytest

from hkproof.orchestration.registry import load_all
from hkproof.proof.status import Status
from tests.conftest import THEOREM_RESULTS

CLAIMS = list(load_all().values())


def _param(c):
    return pytest.param(c, id=c.id, marks=[pytest.mark.slow] if c.slow else [])


def perturb(text: str) -> str:
    """A small change of a claimed formula: add 1/7 (to the first entry of a matrix or vector)."""
    if text.lstrip().startswith("["):
        return re.sub(r"^(\s*\[+)", r"\g<1>1/7 + ", text, count=1)
    return f"({text}) + 1/7"


@pytest.mark.parametrize("claim", [_param(c) for c in CLAIMS])
def test_theorem_verified(claim, record_property):
    cert = claim.prove()
    THEOREM_RESULTS.append((claim.id, cert.status.label, cert.seconds))
    record_property("status", cert.status.label)
    record_property("seconds", round(cert.seconds, 4))
    assert claim.succeeded(cert), cert.render()
    if not claim.is_open:
        assert cert.status is Status.VERIFIED


PERTURBATIONS = [pytest.param(c, key, id=f"{c.id}:{key}", marks=[pytest.mark.slow] if c.slow else [])
                 for c in CLAIMS for key in c.claimed]


@pytest.mark.parametrize("claim,key", PERTURBATIONS)
def test_perturbed_claim_not_verified(claim, key):
    cert = claim.prove({key: perturb(claim.claimed[key])})
    assert not claim.succeeded(cert), f"perturbing {key} left {claim.id} {cert.status.label}"
