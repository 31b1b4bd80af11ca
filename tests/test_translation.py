"""The parameter translation w -> w + c (1, 1, 1) of the Clebsch system: invariance, slice and lift, and the slice
proofs refusing to decide a system that is not invariant."""
from __future__ import annotations

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.errors import HKProofError
from hkproof.hk.reduced import Relation, prove_by_evenness
from hkproof.hk.translation import ParameterTranslation, check_solution_on_slice, prove_on_slice
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import TRANSLATION, named

F = kahan_map("clebsch")
R = F.ring


@pytest.mark.parametrize("text,invariant", [
    ("p1**2 + m2**2/(w1 - w3) + m3**2/(w1 - w2)", True),            # I1
    ("(w2 - w3)*(w3 - w1)/(eps**2*(w1 - w2)*m1 + p1)", True),
    ("m1**2 + w1*p1**2", False),                                     # H1 shifts by c H3
    ("(p1**2 + p2**2 + p3**2)/(1 - eps**2*(w1*p1**2 + w2*p2**2 + w3*p3**2))", False),  # J
])
def test_invariance(text, invariant):
    assert TRANSLATION.is_invariant(named(F, text)) is invariant


@pytest.mark.parametrize("text", [
    "(m1*(w1 - w2)**2 + p3*(w3 - w1))/(1 + eps**2*(w2 - w3)*p2**2)",
    "m1/(w3 - w1 + eps*p1)",   # the lift changes the last term of the denominator: the sign must be normalized again
])
def test_lift_inverts_restrict_on_invariant_functions(text):
    h = named(F, text)
    h0 = TRANSLATION.restrict(h)
    assert "w3" not in h0.ring.names
    assert TRANSLATION.lift(h0, R) == h


def test_the_clebsch_map_is_invariant():
    assert all(TRANSLATION.is_invariant(c) for c in F.components())


def test_pivot_must_be_shifted():
    with pytest.raises(HKProofError, match="pivot"):
        ParameterTranslation(("w1", "w2"), "w3")


def _basis1(prover, relation_rhs: str) -> Certificate:
    """Th. "dC basis 1" (second route) with c1 - c2 = relation_rhs, through `prover`."""
    cert = Certificate("test", "test", "-", "-")
    rel = Relation([Frac(R, 1), Frac(R, -1), Frac(R, 0)], named(F, relation_rhs))
    try:
        prover(cert, [named(F, t) for t in ("p1**2", "p2**2", "p3**2")], Frac(R, 1), ("c1", "c2", "c3"),
               (0, 1), [rel])
    except ProofStopped as exc:
        cert.error = str(exc)
    return cert


def test_slice_proof_agrees_with_the_full_proof():
    # Th. "dC basis 1": J is not invariant, but c_k = 1/J + eps^2 w_k and the relation c1 - c2 = eps^2 (w1 - w2) are
    full = _basis1(lambda c, *a: prove_by_evenness(c, F, *a), "eps**2*(w1 - w2)")
    on_slice = _basis1(lambda c, *a: prove_on_slice(c, F, TRANSLATION, *a), "eps**2*(w1 - w2)")
    assert full.status is on_slice.status is Status.VERIFIED
    assert full.formulas["c1"] == on_slice.formulas["c1"]
    assert any("w3 = 0" in step.detail for step in on_slice.steps)


def test_a_system_that_is_not_invariant_is_decided_in_the_full_ring():
    # c1 - c2 = eps^2 w1 is not invariant: no slice; the full-ring proof finds the solution is not even
    cert = _basis1(lambda c, *a: prove_on_slice(c, F, TRANSLATION, *a), "eps**2*w1")
    assert any("not invariant" in step.detail for step in cert.steps)
    assert cert.status is Status.REFUTED and "not even" in cert.error


def test_check_solution_on_slice():
    basis = [named(F, t) for t in ("p1**2", "p2**2", "p3**2")]
    c = [named(F, f"(p1**2 + p2**2 + p3**2)**-1*(1 - eps**2*(w1*p1**2 + w2*p2**2 + w3*p3**2)) + eps**2*w{k}")
         for k in (1, 2, 3)]
    assert check_solution_on_slice(F, TRANSLATION, basis, Frac(R, 1), (-1, 0, 1), [], c)
    assert not check_solution_on_slice(F, TRANSLATION, basis, Frac(R, 1), (-1,), [], [c[0] + 1, *c[1:]])
    # not invariant: decided in the full ring, still exactly
    assert not check_solution_on_slice(F, TRANSLATION, basis, Frac(R, 1), (-1,), [], [c[0] + named(F, "w1"), *c[1:]])


def test_a_shift_that_moves_another_parameter_along():
    from hkproof.theorems.clebsch_flows.data import yz_map
    g = yz_map()
    shift = ParameterTranslation(("w1", "w2", "w3"), "w3", (("y", "-z"),))
    c1 = named(g, "(y + z*w1)/(w2 - w3 + y*p1)")
    assert not shift.is_invariant(c1)                       # y + z w1 stays, y alone moves by -z c
    h = named(g, "(y + z*w1)*(w1 - w2)/(eps*(y + z*w3) + m1)")
    assert shift.is_invariant(h) and not TRANSLATION.is_invariant(h)
    assert shift.lift(shift.restrict(h), g.ring) == h
    with pytest.raises(HKProofError, match="moving parameter"):
        ParameterTranslation(("w1", "w2", "w3"), "w3", (("y", "-w1"),))
