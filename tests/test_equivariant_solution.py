"""A reduced system solved by one Cramer component and a symmetry (hk.equivariant_solution): the same solution as the
full Cramer solve with substitution, and no verdict 'verified' when the symmetry is not one of the system."""
from __future__ import annotations

import pytest

from hkproof.algebra import Frac
from hkproof.dynamics import kahan_map
from hkproof.hk.equivariant_solution import prove_by_symmetry, system_permutation
from hkproof.hk.reduced import Relation, prove_by_evenness
from hkproof.hk.symmetries import SignedPermutation
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

F = kahan_map("euler-top")
R = F.ring
CYCLE = SignedPermutation(tuple((f"x{k}", f"x{k % 3 + 1}", 1) for k in (1, 2, 3)),
                          tuple((f"a{k}", f"a{k % 3 + 1}") for k in (1, 2, 3)))
BASIS = [Frac.parse(R, f"x{k}**2") for k in (1, 2, 3)]
NAMES = ("c1", "c2", "c3")
POINT = {"x1": 2, "x2": 3, "x3": 5, "eps": "1/7", "a1": 1, "a2": -2, "a3": 3}


def relation(*coefficients: str) -> Relation:
    return Relation([Frac.parse(R, c) for c in coefficients], Frac(R, 1))


def run(sigma: SignedPermutation, rel: Relation) -> tuple[Certificate, list[Frac] | None]:
    cert = Certificate("test", "test", "-", "-")
    try:
        return cert, prove_by_symmetry(cert, F, BASIS, Frac(R, 1), NAMES, sigma, POINT, (0, 1), [rel])
    except ProofStopped as exc:
        cert.error = str(exc)
        return cert, None


def test_the_built_solution_is_the_substituted_one():
    cert, built = run(CYCLE, relation("1", "1", "1"))
    assert cert.status is Status.VERIFIED and built is not None
    assert any("by construction" in step.method for step in cert.steps)
    plain = prove_by_evenness(Certificate("t", "t", "-", "-"), F, BASIS, Frac(R, 1), NAMES, (0, 1),
                              [relation("1", "1", "1")])
    assert built == plain


@pytest.mark.parametrize("sigma, rel, why", [
    # x1 <-> x2 without a1 <-> a2: not a symmetry of the field
    (SignedPermutation((("x1", "x2", 1), ("x2", "x1", 1))), relation("1", "1", "1"), "not a symmetry"),
    # a symmetry of the map, but the relation is not carried to itself
    (CYCLE, relation("1", "2", "3"), "not a symmetry"),
])
def test_a_false_symmetry_is_not_verified(sigma, rel, why):
    cert, built = run(sigma, rel)
    assert cert.status is Status.REFUTED and why in cert.error and built is None


def test_a_symmetry_that_moves_the_target_is_refused():
    assert system_permutation(F, BASIS, Frac.parse(R, "x1"), [], CYCLE) is None
    assert system_permutation(F, BASIS, Frac(R, 1), [], CYCLE) == (1, 2, 0)


def test_an_odd_solution_is_still_refuted():
    """The construction replaces substitution only: evenness (check 3) is checked as before."""
    odd = [Frac.parse(R, f"x{k}") for k in (1, 2, 3)]
    cert = Certificate("test", "test", "-", "-")
    with pytest.raises(ProofStopped, match="not even"):
        prove_by_symmetry(cert, F, odd, Frac(R, 1), NAMES, CYCLE, POINT, (0, 1), [relation("1", "1", "1")])
    assert cert.status is Status.REFUTED


def test_a_symmetry_with_two_orbits_takes_cramer_twice():
    """x1 <-> x2 with a1 <-> a2 fixes x3**2: two orbits, {c1, c2} and {c3}, each with its own Cramer component."""
    swap = SignedPermutation((("x1", "x2", 1), ("x2", "x1", 1)), (("a1", "a2"), ("a2", "a1")))
    assert system_permutation(F, BASIS, Frac(R, 1), [relation("1", "1", "1")], swap) == (1, 0, 2)
    cert, built = run(swap, relation("1", "1", "1"))
    assert cert.status is Status.VERIFIED and built is not None
    assert any("for c1, c3" in step.method for step in cert.steps)
    assert built == run(CYCLE, relation("1", "1", "1"))[1]
