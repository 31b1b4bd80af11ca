"""Recipe (G): cofactor certificates Delta^k delta = sum lambda_i E_i, refutation of non-integrals, Groebner route."""
from __future__ import annotations

import json
from dataclasses import replace

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.algebra.groebner import MembershipCertificate
from hkproof.cli import main
from hkproof.proof.status import Status
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.integrals import check_integral
from hkproof.hk.recipe_g import delta_polynomial, eliminate, groebner_membership, recipe_g

C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"          # Prop. "dET first HK basis"
D1 = "a2*(1 - eps**2*a3*a1*x2**2)/(a2*x1**2 - a1*x2**2)"     # Prop. "dET second HK basis"


@pytest.fixture(scope="module")
def euler():
    return kahan_map("euler-top")


@pytest.mark.parametrize("expr", [C1, D1])
def test_integrals_certified(euler, expr):
    h = Frac.parse(euler.ring, expr)
    res = recipe_g(euler, h)
    assert res.status is Status.VERIFIED and res.power == 2
    assert check_integral(euler, h).status is Status.VERIFIED


@pytest.mark.parametrize("expr", ["a3*x2**2 - a2*x3**2", "x1**2", C1.replace("a3*x2**2", "2*a3*x2**2"),
                                  D1.replace("eps**2", "2*eps**2")])
def test_non_integrals_refuted(euler, expr):
    """The continuous integral H1, a monomial, and perturbed c1, d1 are not integrals of the map."""
    assert recipe_g(euler, Frac.parse(euler.ring, expr)).status is Status.REFUTED


def test_certificate_is_checked_by_expansion(euler):
    cert, residual = eliminate(euler, delta_polynomial(euler, Frac.parse(euler.ring, C1)))
    assert residual.is_zero() and cert.check() and cert.combination is not None
    flat = MembershipCertificate(cert.target, cert.generators, cert.cofactors, cert.multiplier, cert.power)
    assert flat.check()                                     # lambda = adj(M)^T q expanded: the same identity
    bad = list(cert.cofactors)
    bad[0] = bad[0] + 1
    assert not MembershipCertificate(cert.target, cert.generators, bad, cert.multiplier, cert.power).check()
    assert not MembershipCertificate(cert.target, cert.generators, cert.cofactors, cert.multiplier,
                                     cert.power + 1).check()
    weights = list(cert.weights)
    weights[1] = weights[1] + 1
    assert not replace(cert, weights=weights).check()
    combination = [list(row) for row in cert.combination]
    combination[2][0] = combination[2][0] + 1
    assert not replace(cert, combination=combination).check()


def test_residual_is_the_substitution_defect(euler):
    """For a non-integral the residual is Delta^d delta(x, N/Delta): non-zero exactly when c o f != c."""
    _, residual = eliminate(euler, delta_polynomial(euler, Frac.parse(euler.ring, "x1**2")))
    assert not residual.is_zero()


def test_groebner_route_agrees_at_fixed_parameters(euler):
    g = kahan_map(euler.field.specialize({"a1": 2, "a2": 3, "a3": -5}))
    c1 = Frac.parse(g.ring, "(-5*x2**2 - 3*x3**2)/(2*x2**2 - 3*x1**2)")
    assert groebner_membership(g, c1) is True
    assert groebner_membership(g, Frac.parse(g.ring, "x1**2")) is False
    assert groebner_membership(g, Frac.parse(g.ring, "x1**2"), limits=(1, 1, 1)) is None


def test_cli_method_groebner(capsys):
    assert main(["integral", "euler-top", C1, "--method", "groebner", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "verified" and out["multiplier"] == "det M ^ 2"
    assert main(["integral", "euler-top", "x1**2", "--method", "groebner"]) == 1
    assert main(["integral", "euler-top", C1]) == 0          # default: substitution


def test_second_flow_perturbed_integral_refuted():
    """Recipe (G) refutes the second-flow L with one coefficient changed."""
    f = kahan_map("clebsch-flow2")
    bad = Frac.parse(f.ring, "(w1*m1**2 + w2*w3*p1**2 + w2*m2**2)/(1 + eps**2*w1*(w1*m1**2 + w2*w3*p1**2))")
    assert recipe_g(f, bad).status is Status.REFUTED
