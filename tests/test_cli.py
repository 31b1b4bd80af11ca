"""The command line as a user runs it: exit codes, --json objects, clear errors and no tracebacks."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parent.parent / "docs" / "examples"


def hk(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "hkproof.cli", *args], capture_output=True, text=True, timeout=300)


def test_list_json():
    out = hk("list", "--json")
    assert out.returncode == 0
    ids = {c["id"] for c in json.loads(out.stdout)}
    assert {"lv-explicit-map", "et-full-basis"} <= ids


def test_prove_json_has_formulas():
    out = hk("prove", "et-first-hk-basis", "et-second-hk-basis", "--json")
    assert out.returncode == 0, out.stderr
    document = json.loads(out.stdout)
    assert document["interrupted"] is False and document["exit_code"] == 0 and document["finished"] == 2
    certs = {c["id"]: c for c in document["certificates"]}
    assert certs["et-first-hk-basis"]["status"] == "verified"
    import sympy
    c1 = sympy.sympify(certs["et-first-hk-basis"]["formulas"]["c1"])
    assert {str(s) for s in c1.free_symbols} <= {"x1", "x2", "x3", "a1", "a2", "a3"}
    assert "d1" in certs["et-second-hk-basis"]["formulas"]


def test_integral_of_a_users_toml_system():
    rigid = str(EXAMPLES / "rigid-body.toml")
    ok = hk("integral", rigid, "(r*v**2 - q*w**2)/(p*v**2 - q*u**2)", "--json")
    assert ok.returncode == 0
    assert json.loads(ok.stdout)["verdict"] == "verified"
    bad = hk("integral", rigid, "(r*v**2 - q*w**2)/(p*v**2 + q*u**2)", "--json")
    assert bad.returncode == 1
    assert json.loads(bad.stdout)["verdict"] == "refuted"
    osc = str(EXAMPLES / "oscillator.toml")
    assert hk("integral", osc, "x**2 + y**2").returncode == 0
    assert hk("integral", osc, "x**2 + 2*y**2").returncode == 1


def test_map_command():
    out = hk("map", "euler-top", "--json")
    data = json.loads(out.stdout)
    assert out.returncode == 0 and set(data["components"]) == {"x1_tilde", "x2_tilde", "x3_tilde"}


@pytest.mark.parametrize("args,message", [
    (("integral", "euler-top", "x1 + zz"), "unknown name 'zz'"),
    (("integral", "no-such-system", "x"), "unknown system"),
    (("map", "does-not-exist.toml"), "no such file"),
    (("prove", "no-such-theorem"), "no theorem"),
    (("integral", "euler-top", "x1 +* 2"), "cannot read"),
])
def test_bad_input_gives_a_clear_error(args, message):
    out = hk(*args)
    assert out.returncode == 2
    assert message in out.stderr
    assert "Traceback" not in out.stderr


def test_non_quadratic_toml(tmp_path):
    path = tmp_path / "cubic.toml"
    path.write_text('variables = ["x", "y"]\n[rhs]\nx = "x**3"\ny = "y"\n')
    out = hk("map", str(path), "--json")
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert json.loads(out.stdout)["error"] == "NotQuadraticError"
