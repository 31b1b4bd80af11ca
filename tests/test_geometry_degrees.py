"""hkproof degrees: deg f^n on random lines mod p (evidence), growth fits, bad input refused."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.degrees import degree_growth, fit_growth

RIGID = str(Path(__file__).resolve().parent.parent / "docs" / "examples" / "rigid-body.toml")


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
    res = degree_growth(kahan_map("lotka-volterra"), 40, runs=1)
    assert len(res.degrees) == 15 and res.degrees[-1] == 2 ** 15


def test_symbolic_iterates_make_small_degrees_exact(capsys):
    code, out = run(capsys, "degrees", "lotka-volterra", "--iterates", "3", "--symbolic-up-to", "3")
    assert code == 0 and out["symbolic_degrees"] == [2, 4, 8] and out["status"] == "verified"
    code, out = run(capsys, "degrees", "lotka-volterra", "--iterates", "5", "--symbolic-up-to", "2")
    assert out["status"] == "evidence(exact)" and out["symbolic_agree"]
