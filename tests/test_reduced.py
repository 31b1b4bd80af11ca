"""Prop. "prop: even" as implemented: each hypothesis, when broken, keeps the verdict from being 'verified'."""
from __future__ import annotations

import flint
import pytest

from hkproof.errors import ShapeError

from hkproof.algebra import Frac
from hkproof.dynamics import kahan_map
from hkproof.hk.reduced import (OverCommonDenominator, Relation, block_rows_at, kernel_coordinates,
                                linear_combination_equals, prove_by_evenness)
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

F = kahan_map("euler-top")
R = F.ring


def run(basis, target, iterates=(0, 1), relations=()) -> Certificate:
    cert = Certificate("test", "test", "-", "-")
    try:
        prove_by_evenness(cert, F, [Frac.parse(R, b) for b in basis], Frac.parse(R, target),
                          [f"a{k}" for k in range(len(basis))], iterates, relations)
    except ProofStopped as exc:
        cert.error = str(exc)
    return cert


def test_true_basis_is_verified():
    assert run(["x1**2", "x2**2"], "1").status is Status.VERIFIED


def test_symmetric_range_is_not_enough():
    cert = run(["x1**2", "x2**2", "x1*x2"], "1", iterates=(-1, 0, 1))
    assert cert.status is Status.REFUTED and "non-symmetric" in cert.error


def test_a_basis_that_is_none_is_refuted():
    cert = run(["x1**2", "x2"], "1")
    assert cert.status is Status.REFUTED and "not even" in cert.error


def test_dependent_basis_gives_unknown_not_a_traceback():
    cert = run(["x1**2", "2*x1**2"], "1")
    assert cert.status is Status.UNKNOWN and "vanishes identically" in cert.error


def test_relation_with_phase_variables_needs_a_cited_integral():
    rel = Relation([Frac.parse(R, "x1"), Frac(R, 1), Frac(R, 0)], Frac(R, 0))
    cert = run(["x1**2", "x2**2", "x3**2"], "1", relations=[rel])
    assert cert.status is Status.REFUTED and "no proof that it is an integral" in cert.error


def test_relation_with_odd_coefficient_is_refused():
    rel = Relation([Frac.parse(R, "eps"), Frac(R, 1), Frac(R, 0)], Frac(R, 0))
    cert = run(["x1**2", "x2**2", "x3**2"], "1", relations=[rel])
    assert cert.status is Status.REFUTED and "not even" in cert.error


def test_a_single_iterate_is_not_a_range():
    rel = Relation([Frac(R, 1), Frac(R, -1)], Frac(R, 0))
    cert = run(["x1**2", "x2**2"], "1", iterates=(0,), relations=[rel])
    assert cert.status is Status.REFUTED and "non-symmetric" in cert.error


def test_kernel_coordinates_are_integrals_at_an_exact_point():
    point = {"x1": flint.fmpq(1, 2), "x2": 3, "x3": -2, "eps": flint.fmpq(1, 5), "a1": 2, "a2": -1, "a3": 3}
    basis = [Frac.parse(R, t) for t in ("x1**2", "x2**2", "1")]
    c = kernel_coordinates(F, [basis], point)
    assert c is not None and len(c) == 2
    assert kernel_coordinates(F, [basis], {**point, **F.orbit_exact(point, 1)[1]}) == c
    assert sum((a * phi.evaluate(point) for a, phi in zip(c, basis)), flint.fmpq(0)) == 1
    assert kernel_coordinates(F, [[Frac.parse(R, t) for t in ("x1**2", "x1*x2", "1")]], point) is None


def test_block_rows_at_puts_each_basis_in_its_own_block():
    first = [Frac.parse(R, t) for t in ("x1**2", "x2**2", "1")]
    second = [Frac.parse(R, t) for t in ("x3", "x1*x3")]
    y = {"x1": 2, "x2": 3, "x3": 5, "eps": flint.fmpq(1, 7), "a1": 1, "a2": 1, "a3": 1}
    z = {**y, "x1": -1}
    rows, rhs = block_rows_at([first, second], [y, z])
    assert rows == [[4, 9, 0], [1, 9, 0], [0, 0, 5], [0, 0, 5]]
    assert rhs == [1, 1, 10, -5]


def test_system_at_stacks_the_rows_of_every_iterate_and_the_relations():
    from hkproof.hk.reduced import orbit_points, system_at
    first = [Frac.parse(R, t) for t in ("x1**2", "x2**2", "1")]
    second = [Frac.parse(R, t) for t in ("x3", "x1*x3")]
    point = {"x1": 2, "x2": 3, "x3": 5, "eps": flint.fmpq(1, 7), "a1": 1, "a2": 2, "a3": -3}
    rel = Relation([Frac.parse(R, "eps"), Frac(R, 1), Frac(R, 0)], Frac.parse(R, "a1"))
    rows, rhs = system_at(F, [first, second], (0, 1), [rel], point)
    orbit = orbit_points(F, point, (0, 1))
    expected, expected_rhs = block_rows_at([first, second], [orbit[0], orbit[1]])
    assert rows == expected + [[flint.fmpq(1, 7), 1, 0]] and rhs == expected_rhs + [1]


def test_linear_combination_over_a_given_common_denominator():
    """Values put over one common denominator once (as for the relations of one candidate) give the same verdicts
    as when each check does it; numerators of other values are refused."""
    r = kahan_map("euler-top").ring
    values = [Frac.parse(r, t) for t in ("x1/(x2 + x3)", "x2/((x2 + x3)*(1 + eps))", "1/(1 + eps)")]
    coefficients = [Frac.parse(r, t) for t in ("1 + eps", "-(x2 + x3)", "a1")]
    rhs = Frac.parse(r, "(1 + eps)*x1/(x2 + x3) + (a1 - x2)/(1 + eps)")
    common = OverCommonDenominator.of(values)
    for claimed, holds in ((rhs, True), (rhs + 1, False)):
        assert linear_combination_equals(coefficients, values, claimed) is holds
        assert linear_combination_equals(coefficients, values, claimed, common) is holds
    with pytest.raises(ShapeError):
        linear_combination_equals(coefficients, values, rhs, OverCommonDenominator.of(values[:2]))
