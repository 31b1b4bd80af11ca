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
    assert check_darboux(f, atoms, good, p)[0] is Status.VERIFIED
    wrong_p = Frac.parse(f.ring, "a1*x2**2 - a2*x1**2 + eps").num
    assert check_darboux(f, atoms, good, wrong_p)[0] is Status.REFUTED
    assert check_darboux(f, atoms, jac, p)[0] is Status.REFUTED
    assert check_darboux(f, atoms, jac, p, exact=False)[0] is Status.REFUTED          # at exact points, too


@pytest.mark.parametrize("system,degree", [("euler-top", 2), ("lotka-volterra", 2), ("zhukovsky-volterra-1", 2)])
def test_the_polynomial_identity_agrees_with_the_fractions(system, degree):
    """darboux_identity_checks (products, no gcd) against P o f == K P in lowest terms (cofactor_value), for every
    Darboux polynomial found and for each one perturbed: the two exact routes give the same verdicts."""
    from hkproof.hk.darboux import darboux_identity_checks
    f = kahan_map(system)
    found = search_darboux(f, degree)
    assert found.darboux
    for d in found.darboux:
        polys = [d.poly, d.poly + f.ring.gen(f.variables[0]) ** 2 + 1]
        by_fractions = [f.pullback(Frac(f.ring, q)) == cofactor_value(f, found.atoms, d.cofactor) * Frac(f.ring, q)
                        for q in polys]
        checks = darboux_identity_checks(f, found.atoms, d.cofactor, polys)
        assert [c.holds for c in checks] == by_fractions == [True, False]


@pytest.mark.parametrize("route", ["horner", "lattice", "modular"])
def test_pulled_atoms_on_both_sides_are_folded_into_one_identity(route):
    """K = K0 (q o f) / (q o f) with q pulled on both sides: (D q) o f B = A D (q o f) is one sum over (N, Delta)
    that holds for a Darboux polynomial D of cofactor K0 and fails for D perturbed, by every route."""
    from dataclasses import replace
    from hkproof.hk.darboux import Atom, darboux_identity_checks
    f = kahan_map("euler-top")
    found = search_darboux(f, 2)
    d = found.darboux[0]
    x, y, _ = (f.ring.gen(v) for v in f.variables)
    q = x * y + 3 * x + 1
    atoms = [*found.atoms, Atom("q+", q, pulled=True), Atom("q-", q, pulled=True)]
    cofactor = replace(d.cofactor, exponents=(*d.cofactor.exponents, 1, -1))
    checks = darboux_identity_checks(f, atoms, cofactor, [d.poly, d.poly + x ** 2 + 1], route=route)
    assert [c.holds for c in checks] == [True, False] and {c.by for c in checks} == {route}


def test_large_polynomials_are_shown_by_their_size_in_the_text_and_whole_in_the_json(capsys):
    """The so(4) top's det M(x, eps) has 850 terms: the text report gives its size, --json the formula."""
    assert main(["measure", "so4-euler-top", "--degree", "2", "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "B1 = <a polynomial of 850 terms, total degree 15>" in text and "--json prints every formula" in text
    assert main(["measure", "so4-euler-top", "--degree", "2", "--json", "--no-progress"]) == 0
    atoms = json.loads(capsys.readouterr().out)["atoms"]
    assert len(atoms["B1"]) > 10_000 and "<" not in atoms["B1"]
    assert main(["measure", "euler-top", "--degree", "2", "--no-progress"]) == 0
    assert "<a polynomial" not in capsys.readouterr().out


def test_users_toml_system(capsys):
    assert main(["measure", RIGID, "--degree", "2", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["darboux"]) == 3 and all(d["status"] == "verified" for d in out["darboux"])


@pytest.mark.parametrize("args", [("euler-top", "--degree", "0"), ("nope",)])
def test_bad_input_exit_2(capsys, args):
    assert main(["measure", *args]) == 2


@pytest.mark.parametrize("system", ["lotka-volterra", "euler-top", "zhukovsky-volterra-1"])
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


def test_four_symbolic_parameters_answer_in_seconds_with_integrals_checked_by_sympy(capsys):
    """The gyrostat with one moment (a1, a2, a3, b1 and eps symbolic) once ran past every budget in a fraction-free
    Cramer solve; the coefficients are now rebuilt from kernels mod primes (weights normalizing eps and a1) and
    proven exactly. Its integrals are constant along an orbit sympy computes from the printed field."""
    from types import SimpleNamespace

    from hkproof.algebra.fraction import Frac
    from hkproof.dynamics.catalogue import get_system
    from tests.sympy_bridge import constant_along_sympy_orbit

    assert main(["measure", "zhukovsky-volterra-1", "--seconds", "120", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["complete"] is True and out["unverified"] == []
    assert len(out["darboux"]) >= 5 and all(d["status"] == "verified" for d in out["darboux"])
    ring = kahan_map("zhukovsky-volterra-1").ring
    integrals = [SimpleNamespace(name=i["expr"], frac=Frac.parse(ring, i["expr"])) for i in out["integrals"]]
    assert len(integrals) >= 2 and all(i["status"] == "verified" for i in out["integrals"])
    assert constant_along_sympy_orbit(get_system("zhukovsky-volterra-1"), integrals) == []


def test_weighted_reconstruction_agrees_with_the_plain_one():
    """Normalizing names by a scaling symmetry changes how a Darboux polynomial is sampled, not what it is."""
    import random

    from hkproof.algebra.monomials import exponents_upto
    from hkproof.experiments.weights import scaling_weights
    from hkproof.hk.darboux import candidate_cofactors
    from hkproof.pipelines.darboux import ModularScene, modular_kernels, reconstruct

    f = kahan_map("euler-top")
    atoms, jac = jacobian_atoms(f)
    cofactors = candidate_cofactors(jac)
    monos = exponents_upto(3, 2)
    scene = ModularScene(f, atoms, {n: 7 + k for k, n in enumerate(f.field.control_names)}, 1000003)
    kernels = modular_kernels(scene, cofactors, monos, random.Random(1))
    k, basis = next((k, b) for k, b in kernels.items() if any(cofactors[k].exponents))
    free, vec = basis[0]
    plain = reconstruct(f, atoms, cofactors[k], monos, free, vec, random.Random(2))
    weighted = reconstruct(f, atoms, cofactors[k], monos, free, vec, random.Random(2), scaling_weights(f))
    assert plain == weighted


def test_above_the_symbolic_limit_darboux_polynomials_are_evidence_at_the_search_values():
    """With more phase variables than symbolic_limit, P is rebuilt at the search's eps and parameters and checked at
    exact points there: evidence(exact), and the method names those values."""
    found = search_darboux(kahan_map("lotka-volterra"), 2, symbolic_limit=1)
    assert found.darboux and not found.symbolic
    for d in found.darboux:
        assert d.status is Status.EVIDENCE_EXACT
        assert "only: P(f(x)) = K(x) P(x) at 3 random exact points x" in d.certificate.render()
