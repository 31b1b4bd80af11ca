"""hk.block_system, the steps of Th. "dC bases 345" written once, on the Euler top: two bases in one system, a block
solved with another known, a kernel direction, a candidate with a symmetry -- and each broken on purpose."""
from __future__ import annotations

import flint
import pytest

from hkproof.algebra import Frac
from hkproof.dynamics import kahan_map
from hkproof.errors import HKProofError
from hkproof.hk.block_system import (
    BlockSymmetry,
    BlockSystem,
    check_block,
    determined_components,
    prove_block,
    verify_candidate,
)
from hkproof.hk.reduced import Relation, prove_by_evenness
from hkproof.hk.translation import ParameterTranslation
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

F = kahan_map("euler-top")
R = F.ring
POINT = {"x1": 1, "x2": 2, "x3": -1, "eps": flint.fmpq(1, 3), "a1": 2, "a2": -3, "a3": 5}
# the cyclic shift x1 -> x2 -> x3 -> x1, a likewise: a symmetry of the Euler top's Kahan map
CYCLE = {"x1": "x2", "x2": "x3", "x3": "x1", "a1": "a2", "a2": "a3", "a3": "a1"}


def frac(text: str) -> Frac:
    return Frac.parse(R, text)


def cycled(h: Frac) -> Frac:
    moves = {n: R.gen(m) for n, m in CYCLE.items()}
    return Frac(R, R.substitute(h.num, moves), R.substitute(h.den, moves))


def commutes(kmap) -> bool:
    comps = dict(zip(kmap.variables, kmap.components(), strict=True))
    return all(cycled(comps[v]) == comps[CYCLE[v]] for v in kmap.variables)


# (x1^2, x2^2 | x3^2) and its cyclic image (x2^2, x3^2 | x1^2): c1 x1^2 + c2 x2^2 = x3^2 along orbits
BASES = ((frac("x1**2"), frac("x2**2"), frac("x3**2")), (frac("x2**2"), frac("x3**2"), frac("x1**2")))
SYSTEM = BlockSystem(F, BASES)
SHIFT = BlockSymmetry(cycled, commutes, ((0, 1, (0, 1, 2)),))


def run(step) -> Certificate:
    cert = Certificate("test", "test", "-", "-")
    try:
        step(cert)
    except ProofStopped as exc:
        cert.error = str(exc)
    return cert


def solution() -> list[Frac]:
    cert = Certificate("test", "test", "-", "-")
    first = prove_by_evenness(cert, F, BASES[0][:2], BASES[0][2], ("c1", "c2"))
    return [*first, *SHIFT.image(first, (0, 1, 2))]


def test_candidate_of_two_blocks_is_verified_and_a_perturbed_one_refuted():
    sol = solution()
    names = ["c1", "c2", "d1", "d2"]
    cert = run(lambda c: verify_candidate(c, SYSTEM, names, sol, POINT, SHIFT))
    assert cert.status is Status.VERIFIED, cert.error
    assert run(lambda c: verify_candidate(c, SYSTEM, names, sol, POINT)).status is Status.VERIFIED
    bad = [sol[0], sol[1], sol[2], sol[3] + frac("eps**2")]
    assert run(lambda c: verify_candidate(c, SYSTEM, names, bad, POINT)).status is Status.REFUTED
    assert run(lambda c: verify_candidate(c, SYSTEM, names, bad, POINT, SHIFT)).status is Status.REFUTED
    # a change along the row i = 0 of block 2 passes that row; the carried row i = 1 is not checked directly, so
    # the image check must catch it
    moved = [sol[0], sol[1], sol[2] + frac("x3**2"), sol[3] - frac("x2**2")]
    cert = run(lambda c: verify_candidate(c, SYSTEM, names, moved, POINT, SHIFT))
    assert cert.status is Status.REFUTED and "not the image" in cert.error
    assert run(lambda c: verify_candidate(c, SYSTEM, names, moved, POINT)).status is Status.REFUTED


def test_a_symmetry_that_does_not_carry_the_bases_is_refused():
    sol = solution()
    wrong = BlockSymmetry(cycled, commutes, ((0, 1, (1, 0, 2)),))
    cert = run(lambda c: verify_candidate(c, SYSTEM, ["c1", "c2", "d1", "d2"], sol, POINT, wrong))
    assert cert.status is Status.REFUTED and "does not carry basis 1" in cert.error
    fake = BlockSymmetry(cycled, lambda kmap: False, SHIFT.images)
    cert = run(lambda c: verify_candidate(c, SYSTEM, ["c1", "c2", "d1", "d2"], sol, POINT, fake))
    assert cert.status is Status.REFUTED and "commute" in cert.error


def test_block_solved_with_the_other_known_through_a_relation():
    sol = solution()
    # d1 + c1 = (d1 + c1 known), across blocks: with block 1 known, block 2 has one row i = 0 and this relation
    link = Relation([Frac(R, 1), Frac(R, 0), Frac(R, 1), Frac(R, 0)], sol[0] + sol[2], "test")
    system = SYSTEM.with_(relations=[link], iterates=(0, 1))
    with pytest.raises(HKProofError, match="not square"):
        prove_block(Certificate("t", "t", "-", "-"), system, 1, dict(enumerate(sol[:2])), ["d1", "d2"], "test")
    (rel,) = system.restricted(1, dict(enumerate(sol[:2])), "known block")
    assert rel.rhs == sol[2] and rel.source == "test; known block"
    assert system.restricted(1, {}, "") == []
    assert check_block(system.with_(iterates=(0,)), 1, dict(enumerate(sol[:2])), sol[2:],
                       ParameterTranslation(("a1", "a2", "a3"), "a3"))


def test_kernel_direction_determines_the_components_where_it_vanishes():
    # the rows i = 0 of (x1^2, x2^2 | x3^2) alone: direction (x2^2, -x1^2), nothing determined
    system = BlockSystem(F, BASES[:1], iterates=(0,))
    got: list[int] = []
    cert = run(lambda c: got.extend(determined_components(c, system, [[frac("x2**2"), frac("-x1**2")]], POINT)))
    assert cert.status is Status.VERIFIED and got == []
    # with c2 = (its value) as a relation: the direction must vanish at c2, and then c2 is determined
    c2 = solution()[1]
    fixed = system.with_(relations=[Relation([Frac(R, 0), Frac(R, 1)], c2, "test")])
    cert = run(lambda c: determined_components(c, fixed, [[frac("x2**2"), frac("-x1**2")]], POINT))
    assert cert.status is Status.REFUTED and "relation 1" in cert.error
    cert = run(lambda c: determined_components(c, system, [[frac("x2**2"), frac("x1**2")]], POINT))
    assert cert.status is Status.REFUTED and "row i = 0" in cert.error
    with pytest.raises(HKProofError, match="one shape"):
        determined_components(Certificate("t", "t", "-", "-"), system, [[frac("x2**2")]], POINT)


def test_prove_block_in_the_full_ring_and_on_a_slice_agree():
    sol = solution()
    got: list[Frac] = []
    cert = run(lambda c: got.extend(prove_block(c, SYSTEM, 1, {}, ["d1", "d2"], "")))
    assert cert.status is Status.VERIFIED and got == sol[2:]
    # the Euler top's map is not invariant under a common shift of a1, a2, a3: the slice is refused, the full ring used
    sliced: list[Frac] = []
    cert = run(lambda c: sliced.extend(prove_block(c, SYSTEM, 1, {}, ["d1", "d2"], "",
                                                   ParameterTranslation(("a1", "a2", "a3"), "a3"))))
    assert cert.status is Status.VERIFIED and sliced == sol[2:]
    assert any("not invariant" in step.detail for step in cert.steps)
