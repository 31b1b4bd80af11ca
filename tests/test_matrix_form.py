"""hk.matrix_form: the Kahan equations of the Euler top against the printed matrix form of eq. "dET"."""
from __future__ import annotations

import pytest

from hkproof.algebra.formula import parse_matrix
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.matrix_form import require_matrix_form
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

A = "[[1, -eps*a1*x3, -eps*a1*x2], [-eps*a2*x3, 1, -eps*a2*x1], [-eps*a3*x2, -eps*a3*x1, 1]]"
A_SIGN = "[[1, eps*a1*x3, -eps*a1*x2], [-eps*a2*x3, 1, -eps*a2*x1], [-eps*a3*x2, -eps*a3*x1, 1]]"


def _check(text: str) -> Certificate:
    f = kahan_map("euler-top")
    cert = Certificate("t", "t", "-", "-")
    try:
        with cert.step("matrix form", "coefficients of x~", f.ring) as s:
            require_matrix_form(s, f, parse_matrix(f.ring, text))
    except ProofStopped:
        pass
    return cert


def test_the_printed_matrix_of_the_euler_top_is_its_matrix_form():
    assert _check(A).steps[0].status is Status.VERIFIED


@pytest.mark.parametrize("text", [A_SIGN, "[[1, 0], [0, 1]]"])
def test_a_perturbed_or_misshapen_matrix_is_refuted(text):
    step = _check(text).steps[0]
    assert step.status is not Status.VERIFIED and ("M[1,2]" in step.detail or "shape" in step.detail)
