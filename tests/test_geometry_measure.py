"""hkproof measure: Darboux polynomials, measures and integrals, each verified exactly and refuted when perturbed."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.darboux import Cofactor, check_darboux, cofactor_value, jacobian_atoms
from hkproof.pipelines.darboux import search_darboux
from hkproof.hk.integrals import check_integral
from hkproof.hk.jacobian import jacobian_determinant, matrix_identity_holds
from hkproof.proof.status import Status

RIGID = str(Path(__file__).resolve().parent.parent / "docs" / "examples" / "rigid-body.toml")


def test_jacobian_formula_against_the_direct_jacobian():
    f = kahan_map("lotka-volterra")
    xt, yt = f.components()
    direct = xt.derivative("x") * yt.derivative("y") - xt.derivative("y") * yt.derivative("x")
    num, den, _ = jacobian_determinant(f)
    assert direct == Frac(f.ring, num, den)


class WrongSign(KahanMap):
    """f(x, -eps) in place of f: the Jacobian identity must fail for it."""

    @property
    def explicit(self):
        nums, delta = KahanMap.explicit.func(self)
        return tuple(self.negate_eps(q) for q in nums), self.negate_eps(delta)


def test_jacobian_identity_holds_and_fails_when_perturbed():
    f = kahan_map("euler-top")
    assert matrix_identity_holds(f)
    assert not matrix_identity_holds(WrongSign(f.field))


def test_lotka_volterra_measure_dxdy_over_xy(capsys):
    assert main(["measure", "lotka-volterra", "--degree", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["densities"] == [{"expr": "1/(x*y)", "status": "verified"}]
    assert {d["expr"] for d in out["darboux"]} == {"x", "y", "x*y"}
    assert "HALF" in out["eps_convention"]


def test_euler_top_darboux_and_integrals_verified():
    f = kahan_map("euler-top")
    res = search_darboux(f, 4)
    quadratics = [d for d in res.darboux if d.cofactor != res.jacobian]
    assert len(quadratics) == 3 and all(d.status is Status.VERIFIED for d in res.darboux)
    assert len(res.densities()) == 6
    for text, status in res.integrals()[:2]:
        assert status is Status.VERIFIED
        assert check_integral(f, Frac.parse(f.ring, text)).status is Status.VERIFIED


def test_a_perturbed_darboux_polynomial_or_cofactor_is_refuted():
    f = kahan_map("euler-top")
    atoms, jac = jacobian_atoms(f)
    p = Frac.parse(f.ring, "a1*x2**2 - a2*x1**2").num
    good = Cofactor((1, -2))
    assert check_darboux(f, atoms, good, p, cofactor_value(f, atoms, good))[0] is Status.VERIFIED
    wrong_p = Frac.parse(f.ring, "a1*x2**2 - a2*x1**2 + eps").num
    assert check_darboux(f, atoms, good, wrong_p, cofactor_value(f, atoms, good))[0] is Status.REFUTED
    assert check_darboux(f, atoms, jac, p, cofactor_value(f, atoms, jac))[0] is Status.REFUTED
    assert check_darboux(f, atoms, jac, p)[0] is Status.REFUTED          # at exact points, too


def test_users_toml_system(capsys):
    assert main(["measure", RIGID, "--degree", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["darboux"]) == 3 and all(d["status"] == "verified" for d in out["darboux"])


@pytest.mark.parametrize("args", [("euler-top", "--degree", "0"), ("nope",)])
def test_bad_input_exit_2(capsys, args):
    assert main(["measure", *args]) == 2


@pytest.mark.parametrize("system", ["lotka-volterra", "euler-top"])
def test_densities_hold_by_an_independent_route(system, capsys):
    """rho(f(x)) det Df(x) = rho(x) for every verified density, with f and its Jacobian built by sympy from the
    printed map and evaluated at random rational points (no hkproof algebra on this side)."""
    import random

    import sympy

    assert main(["measure", system, "--json"]) == 0
    densities = [d["expr"] for d in json.loads(capsys.readouterr().out)["densities"] if d["status"] == "verified"]
    assert densities
    f = kahan_map(system)
    symbols = {n: sympy.Symbol(n) for n in f.ring.names}
    xs = [symbols[v] for v in f.variables]
    comps = sympy.Matrix([sympy.sympify(str(c), locals=symbols) for c in f.components()])
    jac = comps.jacobian(xs)
    rng = random.Random(3)
    for _ in range(2):
        at = {s: sympy.Rational(rng.randint(-9, 9) or 1, rng.randint(1, 9)) for s in symbols.values()}
        image = {x: comps[k].subs(at) for k, x in enumerate(xs)}
        det = jac.subs(at).det()
        for text in densities:
            rho = sympy.sympify(text, locals=symbols)
            assert sympy.simplify(rho.subs({**at, **image}) * det - rho.subs(at)) == 0, text
