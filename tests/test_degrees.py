"""hkproof degrees: deg f^n on random lines mod p (evidence), growth fits, bad input refused."""
from __future__ import annotations

import json
import math
import random
from pathlib import Path

import flint
import pytest

from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.algebra.modular import random_prime
from hkproof.dynamics.degree_growth import degree_growth, fit_growth
from hkproof.dynamics.line_iterates import LineKahanMap, degree

EXAMPLES = Path(__file__).resolve().parent.parent / "docs" / "examples"
RIGID = str(EXAMPLES / "rigid-body.toml")


def run(capsys, *args: str) -> tuple[int, dict]:
    code = main([*args, "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_euler_top_degrees_are_2n2_plus_1(capsys):
    code, out = run(capsys, "degrees", "euler-top", "--iterates", "8")
    assert code == 0
    assert out["degrees"] == [2 * n * n + 1 for n in range(1, 9)]
    assert out["growth"] == "quadratic" and out["formula"] == "2*n^2 + 1"
    assert out["status"] == "evidence(exact)" and out["agree"]
    assert "HALF the time step" in out["eps_convention"]


def test_lotka_volterra_degrees_double():
    res = degree_growth(kahan_map("lotka-volterra"), 10, seed=3)
    assert res.degrees == [2 ** n for n in range(1, 11)]
    assert res.growth.kind == "exponential" and res.growth.lam == 2.0


def test_toml_system_and_fixed_parameters(capsys):
    code, out = run(capsys, "degrees", RIGID, "--iterates", "5", "--param", "p=1", "--param", "q=-2", "--eps", "1/3")
    assert code == 0 and out["degrees"] == [3, 9, 19, 33, 51]


def test_clebsch_second_differences_are_periodic():
    res = degree_growth(kahan_map("clebsch"), 8)
    assert res.degrees == [6, 19, 42, 73, 114, 163, 222, 289]
    assert res.growth.kind == "quadratic" and res.growth.period == 2


def test_growth_fit_is_not_fooled():
    assert fit_growth([3, 9, 19, 33, 51, 73]).polynomial == [1, 0, 2]
    assert fit_growth([3, 9, 19, 33, 51, 74]).kind != "quadratic"     # a perturbed sequence is not 2 n^2 + 1
    assert fit_growth([6, 21, 46, 81, 126]).kind == "undecided"       # too few terms for any verdict
    assert fit_growth([1, 2, 3, 5, 8, 13, 21, 34, 55]).kind == "exponential"


def _period5_quadratic(terms: int) -> list[int]:
    """2, 4, 7, 11, 16, 23, ...: second differences 1, 1, 1, 2, 1 repeated (period 5: quadratic growth)."""
    seq, step = [2], 2
    for i in range(terms - 1):
        seq.append(seq[-1] + step)
        step += (1, 1, 1, 2, 1)[i % 5]
    return seq


def test_the_period_5_sequence_is_the_issues():
    assert _period5_quadratic(6) == [2, 4, 7, 11, 16, 23]


@pytest.mark.parametrize("seq, kind, order, period", [
    (_period5_quadratic(15), "quadratic", 2, 5),
    (_period5_quadratic(12), "quadratic", 2, 5),                    # each value of the period seen twice
    ([2 * n * n + 1 for n in range(1, 9)], "quadratic", 2, 1),
    ([3 * n + 1 for n in range(1, 7)], "linear", 1, 1),
    ([7] * 6, "bounded", 0, 1),
    ([6, 19, 42, 73, 114, 163, 222, 289], "quadratic", 2, 2),        # the first Clebsch flow
])
def test_polynomial_growth_with_periodic_differences(seq, kind, order, period):
    g = fit_growth(seq)
    assert (g.kind, g.order, g.period) == (kind, order, period)
    assert g.entropy == 0 and "differences" in g.evidence or "degrees themselves" in g.evidence


def test_constant_differences_give_the_exact_polynomial():
    assert fit_growth([2 * n * n + 1 for n in range(1, 9)]).formula() == "2*n^2 + 1"
    assert fit_growth([3 * n + 1 for n in range(1, 7)]).formula() == "3*n + 1"
    assert fit_growth(_period5_quadratic(15)).formula().startswith("3/5 n^2 + O(n^1)")


@pytest.mark.parametrize("seq, lam", [
    ([2 ** n for n in range(1, 7)], 2), ([3 ** n for n in range(1, 6)], 3),
    ([(4 ** (n + 1) - 1) // 3 for n in range(1, 8)], 4), ([1, 2, 3, 5, 8, 13, 21, 34, 55], (1 + 5 ** 0.5) / 2)])
def test_exponential_growth_only_with_converged_ratios(seq, lam):
    g = fit_growth(seq)
    assert g.kind == "exponential" and "ratios d_n/d_(n-1)" in g.evidence
    assert abs(g.lam - lam) <= g.lam_error + 1e-12 and g.lam_error < 1e-2
    assert g.entropy == pytest.approx(math.log(g.lam))


@pytest.mark.parametrize("seq", [
    [2, 4, 8, 16],                                   # too short even for a geometric run
    [6, 21, 46, 81, 126],                            # 5 n^2 + 1, too short to see its differences repeat
    *[_period5_quadratic(n) for n in range(5, 12)],  # the period-5 quadratic before its period shows twice
    [3, 9, 19, 33, 51, 74],                          # 2 n^2 + 1 perturbed
    [], [5],
])
def test_too_little_evidence_is_undecided_with_a_reason(seq):
    g = fit_growth(seq)
    assert g.kind == "undecided" and g.evidence and g.lam is None and g.entropy is None


def test_degrees_prints_lambda_with_its_evidence(capsys):
    assert main(["degrees", "lotka-volterra", "--iterates", "6"]) == 0
    out = capsys.readouterr().out
    assert "growth: exponential, deg f^n ~ lambda^n with lambda = 2 +- 0" in out
    assert "the last 4 ratios d_n/d_(n-1) are all 2" in out
    code, payload = run(capsys, "degrees", "lotka-volterra", "--iterates", "4")
    assert payload["growth"] == "undecided" and "7 positive terms" in payload["growth_evidence"]


@pytest.mark.parametrize("args", [("--param", "a1=x"), ("--param", "zz=1"), ("--iterates", "0"),
                                  ("--param", "a1=1/0")])
def test_bad_input_exit_2(capsys, args):
    assert main(["degrees", "euler-top", *args]) == 2
    assert "error" in capsys.readouterr().err


@pytest.mark.parametrize("command", ["degrees", "orbit", "measure", "hamiltonian"])
def test_help_states_the_eps_convention(capsys, command):
    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "HALF the time step" in text and "h = 2 eps" in text


def test_iterates_stop_before_the_degree_explodes():
    res = degree_growth(kahan_map("lotka-volterra"), 40, runs=1, max_degree=5000)
    assert len(res.degrees) == 12 and res.degrees[-1] == 2 ** 12
    assert res.stopped == "the step to f^13 works with polynomials in t of degree up to 8192 > 5000"


def test_symbolic_iterates_make_small_degrees_exact(capsys):
    code, out = run(capsys, "degrees", "lotka-volterra", "--iterates", "3", "--symbolic-up-to", "3")
    assert code == 0 and out["symbolic_degrees"] == [2, 4, 8] and out["status"] == "verified"
    code, out = run(capsys, "degrees", "lotka-volterra", "--iterates", "5", "--symbolic-up-to", "2")
    assert out["status"] == "evidence(exact)" and out["symbolic_agree"]


CUBIC_5D = str(EXAMPLES / "cubic-hamiltonian-5d.toml")
VOLTERRA_6 = str(EXAMPLES / "volterra-6.toml")
CUBIC_5D_DEGREES = [5, 21, 85, 321, 1205, 4501, 16805, 62721]       # d_n = 4 d_(n-1) - d_(n-2) + 4 + 2 (-1)^n


@pytest.mark.slow
def test_cubic_hamiltonian_5d_is_exponential_with_the_default_options(capsys):
    code, out = run(capsys, "degrees", CUBIC_5D)
    assert code == 0 and out["degrees"] == CUBIC_5D_DEGREES and out["agree"] and not out["stopped"]
    assert out["growth"] == "exponential" and "every 2 steps (the ratios alternate)" in out["growth_evidence"]
    assert abs(out["lambda"] - (2 + 3 ** 0.5)) <= out["lambda_error"] < 0.01


@pytest.mark.slow
def test_volterra_6_is_exponential_with_the_default_options(capsys):
    code, out = run(capsys, "degrees", VOLTERRA_6)
    assert code == 0 and out["degrees"] == [(5 ** (n + 1) - 1) // 4 for n in range(1, 8)] and out["agree"]
    assert out["growth"] == "exponential" and abs(out["lambda"] - 5) <= out["lambda_error"] < 0.01
    assert out["stopped"] and "585936 > 200000" in out["stopped_because"]


def test_a_budget_keeps_the_degrees_found_so_far(capsys):
    """--seconds 1 on a run of about a minute: the degrees computed before the deadline, the reason, exit 4."""
    code, out = run(capsys, "degrees", CUBIC_5D, "--iterates", "9", "--seconds", "1")
    assert code == 4 and out["stopped"] and "time budget of 1 s ran out" in out["stopped_because"]
    assert len(out["degrees"]) < 9 and out["degrees"] == CUBIC_5D_DEGREES[:len(out["degrees"])]


def test_volterra_6_first_degrees_and_their_growth():
    res = degree_growth(kahan_map(VOLTERRA_6), 6, runs=1)
    assert res.degrees == [(5 ** (n + 1) - 1) // 4 for n in range(1, 7)] and res.growth.kind == "undecided"
    assert fit_growth([*res.degrees, 97656]).kind == "exponential"


def test_alternating_ratios_need_the_stride_and_a_perturbation_is_not_exponential():
    assert fit_growth(CUBIC_5D_DEGREES).kind == "exponential"
    assert fit_growth(CUBIC_5D_DEGREES, strides=1).kind == "undecided"       # stride 1: the ratios alternate
    assert fit_growth(CUBIC_5D_DEGREES[:-1]).kind == "undecided"             # 7 terms show no stride-2 window
    assert fit_growth([*CUBIC_5D_DEGREES[:-1], 63500]).kind == "undecided"   # the last term perturbed


@pytest.mark.parametrize("system, steps", [("euler-top", 4), ("clebsch", 3), ("volterra-4", 3), ("lotka-volterra", 5)])
def test_line_iterates_are_the_homogenized_composition(system, steps):
    """The Bareiss step on polynomials in t gives the same reduced projective vectors as composing the explicit map
    N/Delta, homogenized, with the vector (nmod_mpoly compose) and cancelling the gcd: an independent route."""
    kmap = kahan_map(system)
    rng = random.Random(7)
    p = random_prime(rng)
    values = {name: rng.randrange(1, p) for name in kmap.field.control_names}
    line_map = LineKahanMap(kmap.mod(p, values))
    hom, _ = kmap.mod(p, values).homogenized()
    tctx = flint.nmod_mpoly_ctx.get(("t",), p, "lex")
    ours = line_map.line(rng)
    theirs = [tctx.from_dict({(k,): int(c) for k, c in enumerate(q.coeffs()) if int(c)}) for q in ours]
    for _ in range(steps):
        ours = line_map.next(ours, rng)
        theirs = [h.compose(*theirs, ctx=tctx) for h in hom]
        g = theirs[0]
        for q in theirs[1:]:
            g = g.gcd(q)
        theirs = [q / g for q in theirs]
        flat = [_univariate(q, p) for q in theirs]
        assert all(a * flat[j] == b * ours[j] for a, b in zip(ours, flat) for j in range(len(ours)))
        assert degree(ours) == max(q.total_degree() for q in theirs)


def _univariate(q: flint.nmod_mpoly, p: int) -> flint.nmod_poly:
    coeffs = [0] * (int(q.total_degree()) + 1 if not q.is_zero() else 0)
    for (k,), c in q.to_dict().items():
        coeffs[k] = int(c)
    return flint.nmod_poly(coeffs, p)
