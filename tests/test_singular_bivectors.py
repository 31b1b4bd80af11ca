"""The bivector steps in Singular (docs/certificates.md, "A second opinion"): `check --export singular` writes
bivector-invariance, jacobi, casimir and involution steps that Singular re-checks on its own and verifies for the
Euler top and Lotka-Volterra; a changed matrix entry, Casimir or involution is refuted there; exclusions are not
exported, and the script says why."""
from __future__ import annotations

import copy
import json
import shutil
import subprocess
from pathlib import Path

import pytest

from hkproof.cli import main
from hkproof.proof.singular import singular_script

pytestmark = pytest.mark.skipif(shutil.which("Singular") is None, reason="Singular is not installed")

BIVECTOR_KINDS = {"bivector-invariance", "jacobi", "casimir", "involution"}
SYSTEMS = {"euler-top": "3", "lotka-volterra": "2"}


@pytest.fixture(scope="module")
def exported(tmp_path_factory) -> dict[str, tuple[dict, str]]:
    """Per system: the poisson certificate and the output of Singular on the script `check --export` wrote."""
    out = {}
    for system, degree in SYSTEMS.items():
        where = tmp_path_factory.mktemp(system)
        cert, script = where / "pi.json", where / "pi.sing"
        assert main(["poisson", system, "--degree", degree, "--no-progress", "--certificate", str(cert)]) == 0
        assert main(["check", str(cert), "--export", "singular", str(script)]) == 0
        out[system] = json.loads(cert.read_text()), singular(script.read_text(), where)
    return out


def singular(script: str, where: Path) -> str:
    """Singular's output on the script; no error line."""
    path = where / "run.sing"
    path.write_text(script)
    run = subprocess.run(["Singular", "-q", str(path)], capture_output=True, text=True, timeout=60,
                         stdin=subprocess.DEVNULL)
    assert "?" not in run.stdout + run.stderr, run.stdout + run.stderr
    return run.stdout


def step(doc: dict, kind: str, **data: object) -> int:
    """The number (from 1) of the first step of that kind with that data."""
    found = (k for k, s in enumerate(doc["steps"], 1) if s["kind"] == kind and all(s[a] == v for a, v in data.items()))
    return next(found)


@pytest.mark.parametrize("system", sorted(SYSTEMS))
def test_singular_verifies_every_bivector_step(exported, system):
    doc, out = exported[system]
    kinds = [s["kind"] for s in doc["steps"]]
    assert {"bivector-invariance", "jacobi", "exclusion"} <= set(kinds)
    for k, kind in enumerate(kinds, 1):
        if kind in BIVECTOR_KINDS:
            assert f"verified: step {k}," in out, out
        elif kind == "exclusion":
            assert f"step {k} (exclusion): not exported: a rank mod p" in out
    assert "refuted" not in out


def test_singular_covers_casimirs_involutions_and_compatible_pairs(exported):
    doc, out = exported["euler-top"]
    assert {s["kind"] for s in doc["steps"]} >= BIVECTOR_KINDS
    assert f"verified: step {step(doc, 'jacobi', bivectors=['Pi1', 'Pi2'])}, [Pi1, Pi2] = 0" in out
    assert f"verified: step {step(doc, 'casimir', bivector='Pi1')}, Pi1 grad C = 0 for C in I1/I2" in out


def test_singular_refutes_a_changed_matrix_entry(exported, tmp_path):
    """One coefficient of Pi2's (x1, x2) entry doubled (and its mirror, so Pi2 stays antisymmetric): Singular refutes
    its invariance and its Jacobi identity, and still verifies Pi1's."""
    doc = copy.deepcopy(exported["euler-top"][0])
    k = step(doc, "bivector-invariance", name="Pi2")
    matrix = doc["steps"][k - 1]["matrix"]
    assert matrix[0][1] == "x2**2*x3*a1 - x1**2*x3*a2"
    matrix[0][1], matrix[1][0] = "2*x2**2*x3*a1 - x1**2*x3*a2", "-2*x2**2*x3*a1 + x1**2*x3*a2"
    out = singular(singular_script(doc), tmp_path)
    assert f"refuted: step {k}, Pi2(f(x)) = Df Pi2(x) Df^T fails" in out
    assert f"refuted: step {step(doc, 'jacobi', bivectors=['Pi2'])}, [Pi2, Pi2] = 0" in out
    assert f"verified: step {step(doc, 'bivector-invariance', name='Pi1')}, Pi1(f(x))" in out


def test_singular_refutes_a_changed_casimir_and_involution(exported, tmp_path):
    """I2 is no Casimir of Pi2 (I1 is), and x1 is not in involution with I1 for Pi1."""
    doc = copy.deepcopy(exported["euler-top"][0])
    casimir, involution = step(doc, "casimir", bivector="Pi2"), step(doc, "involution", bivector="Pi1")
    doc["steps"][casimir - 1]["functions"] = ["I2"]
    doc["steps"][involution - 1]["functions"] = ["I1", "x1"]
    out = singular(singular_script(doc), tmp_path)
    assert f"refuted: step {casimir}, Pi2 grad C = 0 for C in I2 fails" in out
    assert f"refuted: step {involution}, {{I, J}} = 0 for Pi1, I, J in I1, x1 fails" in out
    assert out.count("refuted") == 2
