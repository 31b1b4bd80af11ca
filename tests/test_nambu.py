"""Nambu structures P W(grad I) (hkproof.hk.nambu): the universal identities, the proof, and an independent sympy check
of invariance and Jacobi at rational points."""
from __future__ import annotations

import itertools

import pytest
import sympy

from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk import nambu
from hkproof.hk.nambu import UNIVERSAL_IDENTITIES, nambu_bivector, prove_nambu, universal_identity
from hkproof.hk.poisson import Bivector, invariance_holds, is_poisson, pairs
from hkproof.pipelines.darboux import search_darboux
from hkproof.pipelines.discover import discover
from hkproof.orchestration.registry import get_claim, proven
from hkproof.pipelines.poisson import nambu_densities, with_integrals
from hkproof.proof.status import Status


@pytest.mark.parametrize("n", [3, 4, 5, 6])
def test_universal_identities_hold(n: int) -> None:
    assert all(universal_identity(key, n) for key in UNIVERSAL_IDENTITIES)


def test_universal_identities_fail_when_w_is_perturbed(monkeypatch: pytest.MonkeyPatch) -> None:
    """A sign error in W (one entry negated) breaks every identity: the checks are not vacuous."""
    right = nambu.nambu_dual

    def wrong(rows):  # type: ignore[no-untyped-def]
        out = right(rows)
        return [-out[0]] + out[1:]
    universal_identity.cache_clear()
    monkeypatch.setattr(nambu, "nambu_dual", wrong)
    try:
        assert not any(universal_identity(key, 4) for key in UNIVERSAL_IDENTITIES)
    finally:
        universal_identity.cache_clear()


def _sources(system: str, degree: int):  # type: ignore[no-untyped-def]
    kmap = kahan_map(system)
    ints = [(i.name, i.frac, i.status) for i in discover(kmap.field, 2).integrals if i.frac is not None]
    return kmap, ints, nambu_densities(kmap, search_darboux(kmap, degree))


@pytest.fixture(scope="module")
def euler() -> tuple:
    return _sources("euler-top", 4)


def test_euler_top_nambu_is_liouville_arnold_and_agrees_with_the_direct_proofs(euler: tuple) -> None:
    kmap, ints, dens = euler
    out = prove_nambu(kmap, ints, dens[0])
    assert out.status is Status.VERIFIED and out.rank == 2 and out.liouville_arnold
    assert [n for n, _ in out.casimirs] == ["I1"] and [n for n, _ in out.hamiltonians] == ["I2"]
    # the lemma route against the direct ones: the substitution identity and the Schouten bracket, expanded
    assert invariance_holds(kmap, out.bivector) and is_poisson(out.bivector)


def test_a_wrong_density_or_an_unproven_integral_is_not_verified(euler: tuple) -> None:
    kmap, ints, dens = euler
    name, p, _ = dens[0]
    wrong = p * (kmap.ring.gen("x1") + 1)
    pi = nambu_bivector(kmap.ring, kmap.variables, [ints[0][1]], wrong)
    assert not invariance_holds(kmap, pi)
    assert not prove_nambu(kmap, ints, (name + " (x1 + 1)", wrong, Status.UNKNOWN)).status.is_verified
    unproven = [(a, h, Status.EVIDENCE_EXACT) for a, h, _ in ints]
    assert not prove_nambu(kmap, unproven, dens[0]).status.is_verified


def test_a_perturbed_nambu_bivector_is_refuted(euler: tuple) -> None:
    kmap, ints, dens = euler
    pi = prove_nambu(kmap, ints, dens[0]).bivector
    upper = list(pi.upper)
    upper[0] = upper[0] + kmap.ring.gen("x3")
    assert not invariance_holds(kmap, Bivector(pi.ring, pi.variables, tuple(upper), pi.denominator))


def _kahan_step_and_jacobian(kmap, x: list[sympy.Rational], values: dict) -> tuple:  # type: ignore[no-untyped-def]
    """f(x) and Df(x) at a rational point by sympy alone: y - x = 2 eps fbar(x, y), fbar(x, y) = 2 F((x + y)/2) -
    (F(x) + F(y))/2, solved for y, and Df = -F_y^-1 F_x from the implicit function theorem."""
    n = len(kmap.variables)
    xs, ys = sympy.symbols(f"u0:{n}"), sympy.symbols(f"v0:{n}")
    rhs = [c.to_sympy().subs(values) for c in kmap.field.rhs]
    sym = [sympy.Symbol(v) for v in kmap.variables]
    at = lambda e, p: e.subs(dict(zip(sym, p)), simultaneous=True)  # noqa: E731
    eps = values[sympy.Symbol("eps")]
    eqs = [ys[i] - xs[i] - 2 * eps * (2 * at(rhs[i], [(a + b) / 2 for a, b in zip(xs, ys)])
                                      - (at(rhs[i], xs) + at(rhs[i], ys)) / 2) for i in range(n)]
    fx, fy = sympy.Matrix(eqs).jacobian(xs), sympy.Matrix(eqs).jacobian(ys)
    lin = [sympy.expand(e.subs(dict(zip(xs, x)))) for e in eqs]
    y = sympy.linsolve(lin, ys).args[0]
    point = {**dict(zip(xs, x)), **dict(zip(ys, y))}
    return list(y), -(fy.subs(point).inv() * fx.subs(point))


def _sympy_nambu(kmap, integrals, density, values, point=None):  # type: ignore[no-untyped-def]
    """Pi = P W(grad I) by sympy from the integrals' own formulas: symbolic in the phase variables, or its value at
    `point` (the gradients evaluated first: the minors of big integrals stay numbers)."""
    n = len(kmap.variables)
    sym = [sympy.Symbol(v) for v in kmap.variables]
    at = (lambda e: e.subs(dict(zip(sym, point)), simultaneous=True)) if point is not None else (lambda e: e)  # noqa
    grads = sympy.Matrix([[at(sympy.diff(h.to_sympy().subs(values), v)) for v in sym] for h in integrals])
    p = at(density.subs(values))
    pi = sympy.zeros(n, n)
    for i, j in pairs(n):
        rest = [c for c in range(n) if c not in (i, j)]
        sign = sympy.combinatorics.Permutation([i, j, *rest]).signature()
        pi[i, j] = sign * p * grads[:, rest].det()
        pi[j, i] = -pi[i, j]
    return sym, pi


@pytest.mark.parametrize("system, degree, check_jacobi", [("euler-top", 4, True), ("volterra-4", 4, True),
                                                            pytest.param("gaudin-2", 4, False,
                                                                         marks=pytest.mark.slow)])
def test_nambu_invariance_and_jacobi_by_sympy_at_rational_points(system: str, degree: int,
                                                                 check_jacobi: bool) -> None:
    kmap, ints, dens = _sources(system, degree)
    out = prove_nambu(kmap, ints, dens[0])
    assert out.status is Status.VERIFIED
    values = {sympy.Symbol(k): sympy.Rational(v) for k, v in
              zip((name for name in kmap.ring.names if name not in kmap.variables),
                  ("1/7", "2/3", "-5/4", "3/11", "7/5", "-2/9"))}
    poly, casimirs = kmap.ring.to_sympy(dens[0][1]), [h for _, h in out.casimirs]
    n = len(kmap.variables)
    for x in ([sympy.Rational(k + 2, 3 + k) for k in range(n)], [sympy.Rational(1 - 2 * k, 5) for k in range(n)]):
        y, df = _kahan_step_and_jacobian(kmap, x, values)
        left = _sympy_nambu(kmap, casimirs, poly, values, y)[1]
        right = df * _sympy_nambu(kmap, casimirs, poly, values, x)[1] * df.T
        assert sympy.simplify(left - right) == sympy.zeros(n, n)
    if check_jacobi:
        sym, pi = _sympy_nambu(kmap, casimirs, poly, values)
        x0 = {v: sympy.Rational(2 * k + 1, 7) for k, v in enumerate(sym)}
        for i, j, k in itertools.combinations(range(n), 3):
            cyc = sum(pi[a, l] * sympy.diff(pi[b, c], sym[l]) for a, b, c in ((i, j, k), (j, k, i), (k, i, j))
                      for l in range(n))
            assert cyc.subs(x0) == 0


def test_nambu_needs_enough_independent_integrals(euler: tuple) -> None:
    kmap, ints, dens = euler
    out = prove_nambu(kmap, [], dens[0])
    assert not out.status.is_verified and out.rank is None


@pytest.mark.parametrize("claim_id", ["atlas-volterra-3-liouville-arnold", "atlas-volterra-4-liouville-arnold"])
def test_volterra_lattices_are_liouville_arnold_integrable_by_a_nambu_structure(claim_id: str) -> None:
    assert proven(claim_id).status is Status.VERIFIED
    assert get_claim(claim_id).prove({"casimirs": "3"}).status is Status.REFUTED


def test_poisson_reports_the_nambu_structure() -> None:
    """`hkproof poisson euler-top --json`: a "nambu" entry with its matrix (small), rank, Casimirs and verdict."""
    report = with_integrals(kahan_map("euler-top"), 2)
    entry = report.to_dict()["nambu"][0]
    assert entry["status"] == "verified" and entry["rank"] == 2 and entry["liouville_arnold"]
    assert entry["casimirs"] == ["I1"] and entry["hamiltonians"] == ["I2"] and len(entry["matrix"]) == 3
    assert "Nambu structure P * W(grad I1)" in report.text()


@pytest.mark.slow          # about 3 minutes: measure's Darboux search in a dense chart (0.1 s in the catalogue's)
def test_euler_top_nambu_in_a_random_affine_chart() -> None:
    """Metamorphic: in a random affine chart y = T x + c the Euler top's Kahan map is still Liouville-Arnold
    integrable by a Nambu structure (the construction and its proof do not depend on the chart)."""
    import random

    from hkproof.dynamics.catalogue import get_system
    from hkproof.hk.affine_chart import random_change, transformed

    field = transformed(get_system("euler-top"), random_change(3, random.Random(3), "affine"), "euler-top-affine")
    kmap = kahan_map(field)
    ints = [(i.name, i.frac, i.status) for i in discover(field, 2).integrals if i.frac is not None]
    out = prove_nambu(kmap, ints, nambu_densities(kmap, search_darboux(kmap, 4))[0])
    assert out.status is Status.VERIFIED and out.rank == 2 and out.liouville_arnold


def test_the_volterra_liouville_arnold_claim_is_rechecked_by_the_checker() -> None:
    """The claim's certificate carries its integrals and the expanded Nambu bivector (invariance, Jacobi, Casimirs):
    `hkproof check` verifies them on its own; a Casimir that is not one is refuted."""
    import copy
    import json
    from hkproof.checker import check_document
    from hkproof.commands._certificates import theorem_document
    doc = json.loads(json.dumps(theorem_document([proven("atlas-volterra-3-liouville-arnold")])))
    assert check_document(doc).verdict == "verified"
    assert [s["kind"] for s in doc["steps"]][-3:] == ["bivector-invariance", "jacobi", "casimir"]
    wrong = copy.deepcopy(doc)
    wrong["steps"][-1]["functions"] = ["I2"]
    assert check_document(wrong).verdict == "refuted"
