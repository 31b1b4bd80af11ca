"""hkproof hamiltonian: H~ and dx/det(I - eps F') verified exactly, refuted when perturbed; bad J or H refused."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from hkproof.proof.status import Status
from hkproof.algebra.fraction import Frac
from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.hk.hamiltonian_structure import hamiltonian_structure
from hkproof.hk.integrals import check_integral
from hkproof.hk.jacobian import jacobian_determinant
from hkproof.hk.modified_hamiltonian import measure_denominator, modified_hamiltonian

EXAMPLES = Path(__file__).resolve().parent.parent / "docs" / "examples"
CUBIC = str(EXAMPLES / "cubic-oscillator.toml")
HENON = str(EXAMPLES / "henon-heiles.toml")
H_CUBIC = "p**2/2 + q**2/2 + a*q**3/3"
J2 = "[[0, 1], [-1, 0]]"


def test_cubic_oscillator_verified(capsys):
    assert main(["hamiltonian", CUBIC, "--hamiltonian", H_CUBIC, "--poisson", J2, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["modified_hamiltonian"]["status"] == "verified" and out["density"]["status"] == "verified"
    assert "h = 2 eps" in out["formula"] and "HALF" in out["eps_convention"]


def test_henon_heiles_verified(capsys):
    h = "(p1**2 + p2**2)/2 + (q1**2 + q2**2)/2 + q1**2*q2 - q2**3/3"
    assert main(["hamiltonian", HENON, "--hamiltonian", h, "--poisson", "0,0,1,0; 0,0,0,1; -1,0,0,0; 0,-1,0,0"]) == 0


def test_perturbed_modified_hamiltonian_and_measure_are_refuted():
    f = kahan_map(CUBIC)
    r = f.ring
    h = Frac.parse(r, H_CUBIC)
    ht = modified_hamiltonian(f, h)
    assert check_integral(f, ht).status is Status.VERIFIED
    assert check_integral(f, h).status is Status.REFUTED                              # H itself is not preserved
    assert check_integral(f, h + (ht - h) / 2).status is Status.REFUTED              # the correction with h = eps
    assert check_integral(f, ht + Frac.parse(r, "eps**2*q")).status is Status.REFUTED
    num, den, _ = jacobian_determinant(f)
    jac = Frac(r, num, den)
    p = measure_denominator(f)
    assert f.pullback(p) == jac * p
    wrong = p + Frac.parse(r, "eps**2*q")
    assert f.pullback(wrong) != jac * wrong


@pytest.mark.parametrize("h, j", [(H_CUBIC, "[[0, 1], [1, 0]]"),            # not skew
                                  (H_CUBIC, "[[0, q], [-q, 0]]"),            # not constant
                                  (H_CUBIC, "[[0, eps], [-eps, 0]]"),        # eps is not a constant of the field
                                  (H_CUBIC, "[[0, 1, 0], [-1, 0, 0]]"),      # wrong size
                                  (H_CUBIC, "[[0, 1], [-1, 0]"),             # unreadable
                                  ("p**2/2 + q**2/2 + q**3/3", J2),          # does not generate F
                                  ("p**2/2 + q**4", J2),                     # not cubic
                                  ("p**2/(2*q)", J2)])                       # not a polynomial
def test_bad_input_exit_2(capsys, h, j):
    assert main(["hamiltonian", CUBIC, "--hamiltonian", h, "--poisson", j]) == 2
    assert "error" in capsys.readouterr().err


def test_non_constant_poisson_structure_is_refused_for_the_euler_top(capsys):
    j = "[[0,1,0],[-1,0,0],[0,0,0]]"
    assert main(["hamiltonian", "euler-top", "--hamiltonian", "x1*x2*x3", "--poisson", j]) == 2


def test_fixed_parameters_give_specialized_status(capsys):
    assert main(["hamiltonian", CUBIC, "--hamiltonian", H_CUBIC, "--poisson", J2, "--param", "a=3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["modified_hamiltonian"]["status"] == "verified(specialized: a=3)"
    assert main(["hamiltonian", CUBIC, "--hamiltonian", H_CUBIC, "--poisson", J2, "--param", "eps=3"]) == 2


def test_modified_hamiltonian_and_density_by_an_independent_route(capsys):
    """H~(f(x)) = H~(x) and rho(f(x)) det Df(x) = rho(x) with f, Df built by sympy from the printed map and evaluated
    at random rational points (no hkproof algebra on this side)."""
    import random

    import sympy

    assert main(["hamiltonian", CUBIC, "--hamiltonian", H_CUBIC, "--poisson", J2, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    f = kahan_map(CUBIC)
    symbols = {n: sympy.Symbol(n) for n in f.ring.names}
    xs = [symbols[v] for v in f.variables]
    comps = sympy.Matrix([sympy.sympify(str(c), locals=symbols) for c in f.components()])
    jac = comps.jacobian(xs)
    ht = sympy.sympify(out["modified_hamiltonian"]["expr"], locals=symbols)
    rho = sympy.sympify(out["density"]["expr"], locals=symbols)
    rng = random.Random(7)
    for _ in range(3):
        at = {s: sympy.Rational(rng.randint(-9, 9) or 1, rng.randint(1, 9)) for s in symbols.values()}
        moved = {**at, **{x: comps[k].subs(at) for k, x in enumerate(xs)}}
        assert sympy.simplify(ht.subs(moved) - ht.subs(at)) == 0
        assert sympy.simplify(rho.subs(moved) * jac.subs(at).det() - rho.subs(at)) == 0


def test_the_structure_found_from_the_field_is_accepted_by_the_command(capsys):
    """hk.hamiltonian_structure on the Henon-Heiles field: its J and H, as text, verify through `hkproof hamiltonian`
    (and a wrong sign of J is refused: it does not generate the field)."""
    found = hamiltonian_structure(QuadraticField.from_toml(HENON))
    assert found is not None
    h, j = str(found.hamiltonian), found.poisson_text()
    assert main(["hamiltonian", HENON, "--hamiltonian", h, "--poisson", j]) == 0
    capsys.readouterr()
    assert main(["hamiltonian", HENON, "--hamiltonian", h, "--poisson", j.replace("-1", "X").replace("1", "-1")
                 .replace("X", "1")]) == 2
