"""The input layer cannot be fooled: exact decimals, no code from formulas or TOML files, exit codes 0/1/2/3 and one
JSON object per error, validated options (the reliability issue, case by case)."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hkproof.cli import main
from hkproof.dynamics.field import QuadraticField
from hkproof.errors import NotQuadraticError, ParseError, UnknownSystemError

C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"


def run(capsys, *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def run_json(capsys, *args: str) -> tuple[int, dict]:
    code, out, _ = run(capsys, *args, "--json")
    return code, json.loads(out)


def toml(tmp_path: Path, text: str, name: str = "user.toml") -> str:
    path = tmp_path / name
    path.write_text(text)
    return str(path)


# ---- decimals are the numbers they write ---------------------------------------------------------------
def test_decimal_close_to_one_is_not_one(capsys):
    assert run(capsys, "integral", "euler-top", C1)[0] == 0
    code, payload = run_json(capsys, "integral", "euler-top", C1.replace("a1*x2", "1.00000000000000001*a1*x2"))
    assert code == 1 and payload["verdict"] == "refuted" and payload["witness"]["prime"] > 2**61


def test_toml_decimal_coefficient_is_exact(capsys, tmp_path):
    """A field with 0.3333333333333333 v w is not the field with v w / 3: the integral built for 1/3 is refuted."""
    third = toml(tmp_path, 'variables = ["u", "v", "w"]\n[rhs]\nu = "v*w/3"\nv = "w*u"\nw = "-u*v"\n', "third.toml")
    decimal = toml(tmp_path, 'variables = ["u", "v", "w"]\n[rhs]\nu = "0.3333333333333333*v*w"\nv = "w*u"\n'
                   'w = "-u*v"\n', "decimal.toml")
    h = "(-v**2 - w**2)/(v**2/3 - u**2)"   # c1 of eq. "dET c1 c2" with a1 = 1/3, a2 = 1, a3 = -1
    assert run(capsys, "integral", third, h)[0] == 0
    assert run(capsys, "integral", decimal, h)[0] == 1


def test_overrides_read_decimals_exactly():
    from hkproof.orchestration.registry import get_claim
    claim = get_claim("et-first-hk-basis")
    perturbed = claim.claimed["c1"].replace("a3*x2**2", "1.00000000000000001*a3*x2**2")
    assert claim.prove({"c1": perturbed}).status.label == "refuted"


# ---- formulas and TOML files never run code ------------------------------------------------------------
def test_formula_cannot_run_code(capsys, tmp_path):
    marker = tmp_path / "pwned"
    expr = f"x1 + 0*__import__('os').system('touch {marker}')"
    code, payload = run_json(capsys, "integral", "euler-top", expr)
    assert code == 2 and payload["error"] == "ParseError"
    assert not marker.exists()


def test_toml_cannot_run_code(capsys, tmp_path):
    marker = tmp_path / "pwned"
    path = toml(tmp_path, f'variables = ["x"]\n[rhs]\nx = "x + 0*__import__(\'os\').system(\'touch {marker}\')"\n')
    code, payload = run_json(capsys, "map", path)
    assert code == 2 and "unexpected character" in payload["message"]
    assert not marker.exists()


# ---- bad input is exit 2 with one line, or one JSON object ----------------------------------------------
BAD_FORMULAS = ["sin(x1)", "sqrt(2)*x1", "x1**a1", "x1**2.5", "Abs(x1)", "x\u00e91", "10**10**9*x1", "pi*x1",
                " + ".join(["x1"] * 3000) + " +", "x1 +", "(x1"]


@pytest.mark.parametrize("expr", BAD_FORMULAS)
def test_bad_formulas_exit_2(capsys, expr):
    code, out, err = run(capsys, "integral", "euler-top", expr)
    assert code == 2 and out == "" and err.startswith("hkproof: error: ") and err.count("\n") == 1
    code, payload = run_json(capsys, "integral", "euler-top", expr)
    assert code == 2 and set(payload) == {"error", "message"}


def test_power_of_x_is_refuted_fast(capsys):
    import time
    start = time.perf_counter()
    code, payload = run_json(capsys, "integral", "euler-top", "x1**100000")
    assert code == 1 and payload["method"].startswith("evaluation mod p")
    assert time.perf_counter() - start < 30  # seconds, on a loaded machine; typically 0.05


def test_long_sum_is_read(capsys):
    code, payload = run_json(capsys, "integral", "euler-top", " + ".join(["x1**2"] * 3000))
    assert code == 1 and payload["verdict"] == "refuted"


@pytest.mark.parametrize("args", [
    ["integral", "no-such-system", "x1"],
    ["map", "."],                                             # a directory given as SYSTEM
    ["scan", "euler-top", "--basis", "x1**2, x2**2, x3**2, 1", "--eps", "abc"],
    ["scan", "euler-top", "--basis", "x1**2, x2**2, x3**2, 1", "--eps", "0"],
    ["scan", "euler-top", "--basis", "x1**2, x2**2, x3**2, 1", "--points", "-3"],
    ["scan", "euler-top", "--basis", "x1**2, x2**2, x3**2, 1", "--digits", "0"],
    ["scan", "euler-top", "--basis", "x1**2, x2**2, x3**2, 1", "--param", "b1=2"],
    ["scan", "clebsch-general", "--basis", "p1**2, p2**2, p3**2, 1", "--param", "w1=1", "--param", "w2=1"],
    ["relations", "euler-top", "--basis", "x1**2, x2**2, x3**2", "--pslq", "0"],
    ["relations", "euler-top", "--basis", "x1**2, x2**2, x3**2", "--names", "c1, c 2, c3"],
    ["depend", "euler-top", "--target", "T=x1", "--on", "U=x2", "--cap", "V=1"],
    ["integral", "euler-top", "x1", "--param", "a1=1/0"],
    ["integral", "euler-top", "x1", "--param", "eps=1"],
    ["prove", "no-such-claim"],
    ["no-such-command"],
    ["integral", "euler-top"],                                # a missing argument
])
def test_cli_errors_exit_2_with_json(capsys, args):
    code, out, err = run(capsys, *args)
    assert code == 2 and "Traceback" not in err and err.startswith("hkproof: error: ")
    code, out, err = run(capsys, *args, "--json")
    assert code == 2 and "usage:" not in out
    payload = json.loads(out)
    assert set(payload) == {"error", "message"} and payload["message"]


def test_internal_error_is_exit_3(capsys, monkeypatch):
    import hkproof.commands.maps as maps
    monkeypatch.setattr(maps, "kahan_map", lambda name: 1 / 0)
    code, out, err = run(capsys, "map", "euler-top")
    assert code == 3 and "internal error" in err and "report" in err and "Traceback" not in err
    code, payload = run_json(capsys, "map", "euler-top")
    assert code == 3 and payload["error"] == "InternalError"
    code, out, err = run(capsys, "--debug", "map", "euler-top")
    assert code == 3 and "Traceback" in err


# ---- systems: names and TOML structure ----------------------------------------------------------------
@pytest.mark.parametrize("variables, parameters, error", [
    ((), (), "at least one phase variable"), (("x y",), (), "ASCII identifier"), (("x", "x"), (), "distinct"),
    (("lambda",), (), "keyword"), (("eps",), (), "reserved"), (("x_t", "x"), (), "reserved for x-tilde"),
    (("x",), ("x",), "distinct"), (("\u00e9",), (), "ASCII"), (("_x",), (), "ASCII identifier")])
def test_names_are_checked(variables, parameters, error):
    with pytest.raises(ParseError, match=error):
        QuadraticField("bad", variables, parameters, ("1",) * len(variables))


@pytest.mark.parametrize("body, error", [
    ('variables = []\n[rhs]\n', ParseError), ('variables = ["x"]\n[rhs]\nx = 0.5\n', ParseError),
    ('variables = "x"\n[rhs]\nx = "x"\n', ParseError), ('variables = ["x"]\nrhs = "x"\n', ParseError),
    ('variables = ["x"]\n[rhs]\nx = "x**3"\n', NotQuadraticError), ('variables = [\n', ParseError),
    ('variables = ["x"]\nstep = "dt"\n[rhs]\nx = "x"\n', ParseError)])
def test_toml_structure_is_checked(tmp_path, body, error):
    with pytest.raises(error):
        QuadraticField.from_toml(toml(tmp_path, body))


def test_directory_and_binary_files(tmp_path):
    with pytest.raises(UnknownSystemError, match="directory"):
        QuadraticField.from_toml(tmp_path)
    binary = tmp_path / "b.toml"
    binary.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(UnknownSystemError):
        QuadraticField.from_toml(binary)


def test_toml_step_h_means_twice_eps(capsys, tmp_path):
    """With step = "h", formulas may use the full step h = 2 eps."""
    body = 'variables = ["x", "y"]\nstep = "h"\n[rhs]\nx = "y"\ny = "-x"\n'
    path = toml(tmp_path, body)
    # the Kahan map of the harmonic oscillator conserves x^2 + y^2 (it is the Cayley transform)
    assert run(capsys, "integral", path, "x**2 + y**2 + 0*h")[0] == 0
    field = QuadraticField.from_toml(path)
    assert field.parse("h") == 2 * field.parse("eps")
    with pytest.raises(ParseError, match="reserved"):
        QuadraticField.from_toml(toml(tmp_path, 'variables = ["h"]\nstep = "h"\n[rhs]\nh = "h"\n', "h.toml"))


def test_parameter_values_off_the_poles():
    from hkproof.dynamics.catalogue import get_system
    general = get_system("clebsch-general")
    with pytest.raises(ParseError, match="pole"):
        general.check_values({"w1": 1, "w2": 1})
    with pytest.raises(ParseError, match="identity"):
        general.check_values({"eps": "0"})
    assert general.check_values({"w1": "0.5"})["w1"] == general.check_values({"w1": "1/2"})["w1"]


def test_integral_at_special_parameters(capsys):
    code, payload = run_json(capsys, "integral", "euler-top", "x1**2 - x2**2", "--param", "a1=1", "--param", "a2=1")
    assert code == 1
    code, payload = run_json(capsys, "integral", "euler-top", C1, "--param", "a1=2")
    assert code == 0 and payload["verdict"] == "verified(specialized: a1=2)" and payload["fixed"] == {"a1": "2"}


def test_constant_integral_is_noted(capsys):
    code, payload = run_json(capsys, "integral", "euler-top", "a1*eps")
    assert code == 0 and payload["notes"]


@settings(max_examples=40, deadline=None)
@given(st.text(alphabet="x123a+-*/^() .e", min_size=1, max_size=12))
def test_random_formulas_give_an_answer_or_exit_2(expr):
    import contextlib
    import io
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(io.StringIO()):
        code = main(["integral", "euler-top", expr, "--json"])
    assert code in (0, 1, 2)
    payload = json.loads(buf.getvalue())
    assert ("error" in payload) == (code == 2)

