"""`discover`: integrals found from the field alone, certified exactly; nothing unproven is called verified."""
from __future__ import annotations

import json
import random
from pathlib import Path

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.budget import Budget
from hkproof.experiments.weights import Weights
from hkproof.pipelines.discover import discover
from hkproof.pipelines.discover.circuits import circuits
from hkproof.pipelines.discover.screen import without_conserved
from hkproof.hk.certified_integrals import certify
from hkproof.hk.integrals import check_integral
from hkproof.proof.status import Status

PLANAR = QuadraticField("generic-planar", ("x", "y"), (),
                        ("1 + 2*x - 3*y + x**2 - 5*x*y + 7*y**2", "-2 + x + 4*y - 3*x**2 + x*y + 2*y**2"))
RANDOM_3D = QuadraticField("random-3d", ("u", "v", "w"), (),
                           ("3*u*v - 2*w**2 + u - 1", "-u**2 + 5*v*w + 2*v + 3", "4*u*w - v**2 + 7*u*v - w"))


def test_euler_top_two_independent_verified_integrals():
    r = discover("euler-top", 2)
    assert r.complete
    assert r.independent == 2 and r.expected_independent == 2
    f = kahan_map("euler-top")
    for i in r.verified:
        assert i.status == Status.VERIFIED
        assert check_integral(f, Frac.parse(f.ring, str(i.frac))).status == Status.VERIFIED   # expr re-parses
    assert {b["dimension"] for b in r.bases} == {1}
    assert ["x1**2", "x2**2", "x3**2"] in [b["basis"] for b in r.bases]
    assert r.kernels[-1]["dimension"] == 2


@pytest.mark.parametrize("field", [PLANAR, RANDOM_3D])
def test_non_integrable_fields_report_no_integral(field):
    r = discover(field, 2, budget=Budget(60))
    assert r.complete and not r.integrals and r.independent == 0
    assert "evidence(exact)" in r.negative
    assert all(k["dimension"] == 0 for k in r.kernels)


def test_lotka_volterra_has_no_integral_up_to_degree_three():
    r = discover("lotka-volterra", 3)
    assert not r.integrals and r.negative


def test_forged_candidate_is_refuted_not_verified(monkeypatch):
    """A reconstruction that returns a wrong formula must come out refuted."""
    real = Weights.restore_frac

    def forged(self, h, weight):
        good = real(self, h, weight)
        return None if good is None else good + Frac.parse(good.ring, "eps*x1")
    monkeypatch.setattr(Weights, "restore_frac", forged)
    r = discover("euler-top", 2)
    assert r.integrals and all(i.status == Status.REFUTED for i in r.integrals)
    assert r.independent == 0 and not r.verified


def test_certify_perturbed_integral():
    f = kahan_map("euler-top")
    good = Frac.parse(f.ring, "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)")
    assert certify(f, good).status == Status.VERIFIED
    assert certify(f, good + Frac.parse(f.ring, "eps**2*x1")).status == Status.REFUTED


def test_conserved_coordinate_becomes_parameter():
    field = QuadraticField("rot", ("x", "y", "z"), (), ("z*y", "-z*x", "0"))
    moving, conserved = without_conserved(field)
    assert conserved == ["z"] and moving.variables == ("x", "y") and "z" in moving.parameters
    r = discover(field, 2)
    names = {i.name: i for i in r.integrals}
    assert names["z"].status == Status.VERIFIED and names["z"].kind == "conserved coordinate"
    assert r.independent == 2          # z and a quadric in x, y with z-dependent coefficients


def test_circuits_minimal_supports():
    p = 101
    kernel = [[1, 1, 0, 0], [0, 1, 1, 0]]     # supports {0,1}, {1,2}, {0,2}
    supports, complete = circuits(kernel, p)
    assert complete and sorted(supports) == [(0, 1), (0, 2), (1, 2)]


def test_cli_json_and_latex(capsys):
    assert main(["discover", "euler-top", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["independent"] == 2 and out["dimension"] == 3
    assert {"name", "expr", "status", "basis", "seconds"} <= set(out["integrals"][0])
    assert main(["discover", "euler-top", "--latex", "--param", "a1=2"]) == 0
    text = capsys.readouterr().out
    assert "\\frac" in text and "verified(specialized)" in text


@pytest.mark.parametrize("argv", [["discover", "no-such-system"], ["discover", "euler-top", "--param", "b=1"],
                                  ["discover", "euler-top", "--param", "a1=x"],
                                  ["discover", "euler-top", "--param", "a1"],
                                  ["discover", "euler-top", "--degree", "0"]])
def test_bad_input_exit_2(argv, capsys):
    assert main(argv) == 2
    assert "error" in capsys.readouterr().err


def test_user_toml_example():
    path = Path(__file__).resolve().parents[1] / "docs" / "examples" / "discover-example.toml"
    assert discover(QuadraticField.from_toml(path), 2).negative          # nothing of degree 2
    r = discover(QuadraticField.from_toml(path), 3)                   # the modified energy, a cubic pencil
    assert r.independent == 1 and [i.status for i in r.integrals] == [Status.VERIFIED]


def test_budget_reports_what_was_covered(capsys):
    r = discover("volterra-4", 2, budget=Budget(0.0))
    assert not r.complete and any("budget" in c for c in r.covered)
    assert [k["new"] for k in r.kernels] == [1, 2]    # screening always runs before the budget is checked
    assert not r.integrals
    assert main(["discover", "euler-top", "--seconds", "0.001"]) == 0
    assert "budget ran out" in capsys.readouterr().out


def test_all_coordinates_conserved():
    r = discover(QuadraticField("still", ("x", "y"), (), ("0", "0")), 2)
    assert r.conserved == ["x", "y"] and r.independent == 2 and r.complete


def test_discovered_integrals_hold_by_an_independent_route():
    """The printed integrals, read by sympy, take equal values at x and at f(x), f(x) solved exactly over Q at random
    rational points (no symbolic composition, no hkproof parser)."""
    import random
    from fractions import Fraction

    import sympy

    f = kahan_map("euler-top")
    r = discover("euler-top", 2)
    rng = random.Random(5)
    for _ in range(3):
        point = {n: Fraction(rng.randint(-9, 9) or 1, rng.randint(1, 9)) for n in f.ring.names}
        image = f.step_exact(point)
        symbols = {n: sympy.Symbol(n) for n in f.ring.names}
        for i in r.verified:
            h = sympy.sympify(str(i.frac), locals=symbols)
            at_x = h.subs({symbols[n]: sympy.Rational(v.numerator, v.denominator) for n, v in point.items()})
            at_fx = h.subs({**{symbols[n]: sympy.Rational(v.numerator, v.denominator) for n, v in point.items()},
                            **{symbols[n]: sympy.Rational(int(v.p), int(v.q)) for n, v in image.items()}})
            assert at_x == at_fx, i.name


_PSI = [(1, 0, 0, 1, 0, 0), (0, 1, 0, 0, 1, 0), (0, 0, 1, 0, 0, 1), (0, 0, 0, 2, 0, 0), (0, 0, 0, 0, 2, 0),
        (0, 0, 0, 0, 0, 2)]          # m1 p1, m2 p2, m3 p3, p1^2, p2^2, p3^2 in (m1, m2, m3, p1, p2, p3)


def _psi_proof():
    """The HK-basis Psi = (m1 p1, m2 p2, m3 p3, p1^2, p2^2, p3^2) of the first Clebsch flow, proven whole from the
    integral of (p1^2, p2^2, p3^2, 1) alone (as discover does it)."""
    from hkproof.algebra.fraction import Frac
    from hkproof.pipelines.discover.context import SearchContext
    from hkproof.pipelines.discover.solve import prove_basis
    f = kahan_map("clebsch")
    known = {"I1": Frac.parse(f.ring, "(-p2**2*eps**2*w1 - p3**2*eps**2*w1 + p2**2*eps**2*w2 + p3**2*eps**2*w3 - 1)"
                                      "/(p1**2 + p2**2 + p3**2)")}
    basis = _PSI
    ctx = SearchContext.for_maps(f, budget=Budget(600))
    return f, known, prove_basis(ctx, basis, known, random.Random(1))


def _refuted(kmap, proof, candidate) -> bool:
    """Prop. "prop: even" on a candidate for the coordinates of `proof`'s basis stops with a refuted step."""
    from hkproof.pipelines.discover.solve import verify_candidate
    from hkproof.proof.certificate import Certificate, ProofStopped
    cert = Certificate("perturbed", "perturbed", "test", "a perturbed candidate")
    with pytest.raises(ProofStopped):
        verify_candidate(cert, kmap, proof.basis, proof.relations, candidate)
    return cert.status is Status.REFUTED


def test_prove_basis_proves_the_psi_basis_and_refutes_a_perturbed_coordinate():
    from hkproof.pipelines.discover.solve import BasisProof
    f, known, proof = _psi_proof()
    assert isinstance(proof, BasisProof) and proof.status is Status.VERIFIED, proof
    assert max(len(c.num) for c in proof.coordinates) > 100        # d7, d8, d9 of Th. "dC basis 2" (normalized)
    for bad in (Frac.parse(f.ring, "eps**2*p1*m2"), Frac.parse(f.ring, "1/1000")):
        assert _refuted(f, proof, [c + bad if k == 0 else c for k, c in enumerate(proof.coordinates)])


def test_prove_basis_waits_for_integrals_it_does_not_have():
    from hkproof.pipelines.discover.context import SearchContext
    from hkproof.pipelines.discover.solve import Postponed, prove_basis
    f = kahan_map("clebsch")
    basis = _PSI
    result = prove_basis(SearchContext.for_maps(f), basis, {}, random.Random(1))
    assert isinstance(result, Postponed) and "rank" in result.reason


@pytest.fixture(scope="module")
def clebsch_report():
    return discover("clebsch", 2, budget=Budget(600))


def test_discover_first_clebsch_flow_proves_four_independent_integrals(clebsch_report):
    report = clebsch_report
    proven = [i for i in report.integrals if i.status is Status.VERIFIED and i.independent]
    assert len(proven) == 4 == report.expected_independent and report.complete
    assert sum('Prop. "prop: even"' in i.method for i in proven) >= 2
    # independent route: each proven integral is constant along an orbit that sympy computes from the printed field
    from hkproof.dynamics.catalogue import get_system
    from tests.sympy_bridge import constant_along_sympy_orbit
    assert not constant_along_sympy_orbit(get_system("clebsch"), proven)


def test_discovered_clebsch_integrals_span_the_field_of_the_theorem_modules(clebsch_report):
    """J (Th. "dC basis 1"), d_k (Th. "dC basis 2"), A, B, C, D and the alpha coordinates (Th. "dC bases 345"), as
    the theorem modules prove them, and the four integrals discover proves have Jacobian rank 4 together and each set alone (exact ranks at
    random rational points: evidence that they generate the same field of integrals)."""
    from hkproof.api import prove
    from hkproof.hk.certified_integrals import jacobian_points
    from hkproof.hk.independence import max_jacobian_rank
    f = kahan_map("clebsch")
    wanted = {"J", "d7", "d8", "d9", "A", "B", "C", "D", "a1", "a2", "a3"}
    theorems = {k: v for cert in prove("dc-basis1-relations", "dc-basis2", "dc345-abcd", "dc345-alpha")
                for k, v in cert.values.items() if k in wanted}
    assert set(theorems) == wanted
    theorems = list(theorems.values())
    found = [i.frac for i in clebsch_report.integrals if i.independent]
    points = jacobian_points(f.ring.names)
    assert max_jacobian_rank(theorems, f.variables, points) == 4
    assert max_jacobian_rank(found, f.variables, points) == 4
    assert max_jacobian_rank(found + theorems, f.variables, points) == 4


def test_a_perturbed_coefficient_in_a_10000_term_numerator_is_refuted(clebsch_report):
    """The largest basis discover proves, its largest coordinate written over a larger denominator (a numerator of more
    than 10 000 terms) with one coefficient changed: Prop. "prop: even" refutes it (on the slice w3 = 0, where the
    proof ran)."""
    assert clebsch_report.on_slice is not None
    f = kahan_map(clebsch_report.on_slice.searched)
    proof = max((i.proof for i in clebsch_report.integrals if i.proof is not None),
                key=lambda p: sum(len(c.num) + len(c.den) for c in p.coordinates))
    k = max(range(len(proof.coordinates)), key=lambda j: len(proof.coordinates[j].num))
    c = proof.coordinates[k]
    factor = Frac.parse(f.ring, "(1 + eps**2*w1*m1*p2 - eps**2*w2*m3**2 + eps**4*w2*p1*p2*m2*m3 + eps**2*m1*m2)**3").num
    num, den = c.num * factor, c.den * factor
    assert len(num) > 10_000
    exps, coeff = num.monoms()[len(num) // 2], num.coeffs()[len(num) // 2]
    changed = num + f.ring.ctx.from_dict({tuple(exps): 1})         # one coefficient, coeff -> coeff + 1
    candidate = list(proof.coordinates)
    candidate[k] = Frac(f.ring, changed, den)
    assert len(candidate[k].num) > 10_000 and coeff != 0
    assert _refuted(f, proof, candidate)


@pytest.mark.parametrize("system", ["euler-top", "volterra-3", "volterra-4", "gaudin-2", "zhukovsky-volterra-1", "lagrange-top",
                                    pytest.param("kirchhoff", marks=pytest.mark.slow)])
def test_integrals_discover_proves_are_constant_along_sympy_orbits(system):
    """Independent route for every atlas system discover completes: the proven integrals, evaluated term by term,
    take one value along an orbit sympy computes from the printed field; a perturbed integral does not."""
    from hkproof.dynamics.catalogue import get_system
    from tests.sympy_bridge import constant_along_sympy_orbit
    report = discover(system, 3 if system == "volterra-3" else 2, budget=Budget(600))
    proven = [i for i in report.integrals if i.status is Status.VERIFIED and i.frac is not None]
    assert len([i for i in proven if i.independent]) == report.expected_independent + len(report.conserved)
    assert not constant_along_sympy_orbit(get_system(system), proven)
    from types import SimpleNamespace
    eps = Frac.parse(proven[-1].frac.ring, "eps**2*" + report.variables[0])
    assert constant_along_sympy_orbit(get_system(system), [SimpleNamespace(name="bad", frac=proven[-1].frac + eps)])


def test_probes_run_on_a_process_pool_with_the_same_result():
    """--jobs: the batches of probes of the sparse reconstruction run in worker processes (the black box travels as
    data: the field as text, its Kahan map rebuilt there); the integrals are the same as in one process."""
    import pickle
    from concurrent.futures import ProcessPoolExecutor

    from hkproof.dynamics.catalogue import get_system
    field = get_system("gaudin-2")
    assert pickle.loads(pickle.dumps(field)) == field
    calls: list[int] = []
    with ProcessPoolExecutor(2) as pool:
        def mapper(fn, jobs):
            calls.append(len(jobs))
            return pool.map(fn, jobs)
        pooled = discover("gaudin-2", 2, budget=Budget(300), mapper=mapper)
    alone = discover("gaudin-2", 2, budget=Budget(300))
    assert calls, "no batch of probes went to the pool"
    assert [str(i.frac) for i in pooled.integrals] == [str(i.frac) for i in alone.integrals]
    assert pooled.independent == alone.independent == 4


def test_henon_heiles_modified_energy_by_sparse_reconstruction_and_substitution():
    """No square system proves the 17-monomial basis of Henon-Heiles (no integral is known to make relations with),
    and its ratio needs 4 290 dense unknowns: the last resort rebuilds it by sparse reconstruction and proves it by
    substitution. It is the modified energy of Celledoni-McLachlan-Owren-Quispel (hkproof.hk.modified_hamiltonian
    builds that from H): the two are functionally dependent, and both are constant along a sympy orbit."""
    from types import SimpleNamespace

    from hkproof.dynamics.catalogue import get_system
    from hkproof.hk.independence import jacobian_rank_at, sample_point
    from hkproof.hk.modified_hamiltonian import modified_hamiltonian
    from tests.sympy_bridge import constant_along_sympy_orbit

    path = str(Path(__file__).resolve().parents[1] / "docs" / "examples" / "henon-heiles.toml")
    report = discover(get_system(path), 4, budget=Budget(300), hamiltonian=False)
    proven = [i for i in report.integrals if i.status is Status.VERIFIED and i.frac is not None]
    assert len(proven) == 1 and proven[0].independent and report.complete
    assert any("sparse reconstruction over prime fields" in n for n in proven[0].notes)
    assert report.skipped == []              # the postponed basis is not listed as left out: its integral is proven
    f = kahan_map(get_system(path))
    h = Frac.parse(f.ring, "(p1**2 + p2**2)/2 + (q1**2 + q2**2)/2 + q1**2*q2 - q2**3/3")
    ht = modified_hamiltonian(f, h)
    assert jacobian_rank_at([proven[0].frac, ht], list(f.variables), sample_point(list(f.ring.names), 2)) == 1
    assert jacobian_rank_at([proven[0].frac, h], list(f.variables), sample_point(list(f.ring.names), 2)) == 2
    assert constant_along_sympy_orbit(get_system(path), proven) == []
    bad = SimpleNamespace(name="bad", frac=proven[0].frac + Frac.parse(f.ring, "eps**2*q1"))
    assert constant_along_sympy_orbit(get_system(path), [bad]) == ["bad"]


def test_a_formula_too_large_to_read_is_summarized_in_the_text_and_latex_reports():
    """A person's report prints small integrals whole and summarizes large ones (term counts and degrees; the whole
    formula stays in --json and the certificate), and --latex does not try to factor them."""
    from hkproof.algebra.fraction import Frac
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.algebra.printing import SHOWN_TERMS
    from hkproof.pipelines.discover.report import DiscoveryReport, FoundIntegral
    from hkproof.proof.status import Status
    ring = kahan_map("euler-top").ring
    big = Frac(ring, (ring.gen("x1") + ring.gen("x2") + 2 * ring.gen("x3") + 1) ** 40, ring.gen("x1") + 3)
    assert len(big.num) + len(big.den) > SHOWN_TERMS
    small = Frac.parse(ring, "x1**2 + x2**2")
    report = DiscoveryReport("euler-top", ["x1", "x2", "x3"], ["a1", "a2", "a3"], 2, {})
    report.integrals = [FoundIntegral("I1", small, Status.VERIFIED, "kernel coordinate"),
                        FoundIntegral("I2", big, Status.EVIDENCE_EXACT, "kernel coordinate")]
    text = report.text()
    assert "I1 = x1**2 + x2**2: verified" in text
    assert f"I2 = <a rational function of {len(big.num)} + {len(big.den)} terms, total degrees 40 / 1" in text
    assert str(big) not in text
    latex = report.latex()
    assert "\\mathrm{I1}" in latex and "\\mathrm{I2}" not in latex and f"{len(big.num)} + 2 terms" in latex
    assert report.to_dict()["integrals"][1]["expr"] == str(big)
    from hkproof.pipelines.display import discovery_markdown
    markdown = discovery_markdown(report)                       # how Jupyter shows the report: summarized too
    assert f"a rational function of {len(big.num)} + 2 terms" in markdown and "x_{1}^{2} + x_{2}^{2}" in markdown


def test_independent_subset_skips_dependent_functions_and_evaluates_each_gradient_once_per_point(monkeypatch):
    """h3 = h1 + h2 is left out, h4 kept; every gradient is evaluated at most once per point, however many trials
    reuse it (sympy gives the same rank of the Jacobian of the chosen ones)."""
    import sympy

    from hkproof.algebra.fraction import Frac
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.hk import certified_integrals as exact
    ring = kahan_map("euler-top").ring
    texts = ["x1**2 + x2**2", "x2**2 + x3**2", "x1**2 + 2*x2**2 + x3**2", "x1*x2*x3"]
    functions = [Frac.parse(ring, t) for t in texts]
    calls: list[int] = []
    honest = exact.gradient_at

    def counted(h, variables, point):
        calls.append(1)
        return honest(h, variables, point)
    monkeypatch.setattr(exact, "gradient_at", counted)
    points = exact.jacobian_points(ring.names)
    chosen = exact.independent_subset(functions, ["x1", "x2", "x3"], points)
    assert chosen == [0, 1, 3]
    assert len(calls) <= len(functions) * len(points)
    xs = sympy.symbols("x1 x2 x3")
    jac = sympy.Matrix([[sympy.diff(sympy.sympify(texts[i]), x) for x in xs] for i in chosen])
    assert jac.rank() == 3


def test_henon_heiles_seeded_modified_hamiltonian_is_not_proven_twice():
    """With the seed (the default) H~ is proven first, and the kernel coordinate it makes dependent is not proven
    again: one verified integral, found by the modified-Hamiltonian route."""
    from hkproof.dynamics.catalogue import get_system
    path = str(Path(__file__).resolve().parents[1] / "docs" / "examples" / "henon-heiles.toml")
    report = discover(get_system(path), 4, budget=Budget(300))
    [proven] = report.verified
    assert proven.kind == "modified Hamiltonian" and proven.independent


def test_the_screen_is_not_fooled_by_special_parameter_values(monkeypatch):
    """The screening values are drawn per probe: a draw that hits a special value (a4 = a3 = 3 makes m34 conserved
    for the so(4) top) shows a larger kernel than the generic one, and the smallest kernel wins. With one draw for
    every probe, all of them saw the kernel of degree 1 of the special system."""
    import flint

    from hkproof.pipelines.discover import run

    draws: list[int] = []

    def special_first(rng, names, size=9, **kwargs):
        draws.append(1)
        return {n: flint.fmpq(3) if len(draws) == 1 else flint.fmpq(17, 5) for n in names}

    monkeypatch.setattr(run, "random_point", special_first)
    report = run.discover("so4-euler-top", 1, params={"a1": 1, "a2": 2, "a3": 3})
    assert report.probes[0]["values"]["a4"] == "3" and report.probes[0]["dimensions"][1] == 1
    assert report.kernels[0]["dimension"] == 0 and not report.integrals
