"""The step kinds of certificate versions 2 and 3 (docs/certificates.md): darboux (measure's Darboux polynomials,
integrals and densities; hamiltonian's density; a cofactor "det Df" the checker computes), recipe-g (recipe (G)'s
cofactors) and degrees (deg f^n of exact iterates). Each round-trips through `hkproof check`,
and each mutation (a changed coefficient, a dropped or swapped element, a wrong convention, a truncated file, a
conclusion of the wrong degree) is refused with its exit code."""
from __future__ import annotations

import copy
import json
import shutil
import subprocess
from pathlib import Path

import pytest

from hkproof.checker import check_document
from hkproof.cli import main
from hkproof.commands._certificates import hamiltonian_document, measure_document
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.modified_hamiltonian import parse_matrix, verify
from hkproof.hk.recipe_g import recipe_g
from hkproof.pipelines.darboux import search_darboux
from hkproof.proof.export import VERSION, document, recipe_g_step
from hkproof.proof.singular import singular_script

C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"
CUBIC = str(Path(__file__).resolve().parents[1] / "docs" / "examples" / "cubic-oscillator.toml")


def verdict(doc: dict) -> str:
    return check_document(json.loads(json.dumps(doc))).verdict


def mutated(doc: dict, change) -> dict:
    out = copy.deepcopy(doc)
    change(out)
    return out


@pytest.fixture(scope="module")
def lotka() -> dict:
    """measure lotka-volterra: x, y and xy are Darboux polynomials; 1/(xy) is the density."""
    f = kahan_map("lotka-volterra")
    return measure_document(f, search_darboux(f, 2))


@pytest.fixture(scope="module")
def euler() -> dict:
    """measure euler-top --degree 2: three Darboux polynomials with one cofactor, two integrals as their ratios."""
    f = kahan_map("euler-top")
    return measure_document(f, search_darboux(f, 2))


@pytest.fixture(scope="module")
def groebner() -> dict:
    f = kahan_map("euler-top")
    h = f.field.parse(C1)
    cert = recipe_g(f, h).certificate
    assert cert is not None
    step = recipe_g_step(f.field, "c1", h, cert.generators, cert.cofactors, cert.multiplier ** cert.power)
    return document("c1", "c1 by recipe (G)", [step])


def test_measure_certificates_verify(lotka, euler):
    assert verdict(lotka) == "verified" and [c["name"] for c in lotka["claim"]["densities"]] == ["rho1"]
    assert [len(s["polynomials"]) for s in lotka["steps"]] == [1, 1, 1]
    assert verdict(euler) == "verified" and [c["name"] for c in euler["claim"]["integrals"]] == ["I1", "I2"]


def test_measure_command_writes_a_certificate_check_verifies(capsys, tmp_path):
    target = tmp_path / "lv.json"
    assert main(["measure", "lotka-volterra", "--no-progress", "--certificate", str(target)]) == 0
    assert "certificate:" in capsys.readouterr().out
    assert main(["check", str(target)]) == 0 and capsys.readouterr().out.startswith("verified")


def test_hamiltonian_certificate(capsys, tmp_path):
    target = tmp_path / "ham.json"
    args = ["hamiltonian", CUBIC, "--hamiltonian", "p**2/2 + q**2/2 + a*q**3/3", "--poisson", "[[0, 1], [-1, 0]]"]
    assert main([*args, "--certificate", str(target)]) == 0
    doc = json.loads(target.read_text())
    assert [s["kind"] for s in doc["steps"]] == ["substitution", "darboux"] and verdict(doc) == "verified"
    assert verdict(mutated(doc, lambda d: d["steps"][1].__setitem__("cofactor", "1"))) == "refuted"
    f = kahan_map(CUBIC)
    res = verify(f, f.field.parse("p**2/2 + q**2/2 + a*q**3/3"), parse_matrix(f, "[[0, 1], [-1, 0]]"))
    assert [c["name"] for c in hamiltonian_document(f, res, {})["claim"]["densities"]] == ["rho"]


def test_recipe_g_certificate_verifies(groebner, capsys, tmp_path):
    assert verdict(groebner) == "verified"
    target = tmp_path / "g.json"
    assert main(["integral", "euler-top", C1, "--method", "groebner", "--certificate", str(target)]) == 0
    assert main(["check", str(target)]) == 0


def _first(key: str, change):
    return lambda d: d["steps"][0].__setitem__(key, change(d["steps"][0][key]))


def _swap(key: str, i: int = 0, j: int = 1):
    def change(d: dict) -> None:
        items = d["steps"][0][key]
        items[i], items[j] = items[j], items[i]
    return change


def _swap_polynomials_of_two_steps(d: dict) -> None:
    a, b = d["steps"][0]["polynomials"], d["steps"][1]["polynomials"]
    a[0], b[0] = b[0], a[0]


DARBOUX = {   # on measure lotka-volterra (steps: x, y, xy with its density) or euler-top (one step, two integrals)
    "lv: a changed coefficient of P": ("lotka", _first("polynomials", lambda p: [f"2*{p[0]} + 1"]), "refuted"),
    "lv: a changed cofactor": ("lotka", _first("cofactor", lambda k: f"({k})*(1 + eps)"), "refuted"),
    "lv: polynomials swapped between steps": ("lotka", _swap_polynomials_of_two_steps, "refuted"),
    "lv: a density whose cofactor is not det Df": ("lotka", lambda d: d["steps"][0].__setitem__(
        "densities", [{"name": "rho9", "formula": f"1/({d['steps'][0]['polynomials'][0]})", "from": "1/(P1)"}]),
        "refuted"),
    "lv: a density of degree -2": ("lotka", lambda d: d["steps"][2]["densities"][0].update(
        formula=f"1/({d['steps'][2]['polynomials'][0]})**2", **{"from": "1/(P1)**2"}), "malformed"),
    "lv: a changed field": ("lotka", lambda d: d["fields"]["lotka-volterra"]["rhs"].__setitem__(0, "-x*y + 2*x"),
                            "refuted"),
    "lv: a claimed density no step concludes": ("lotka", lambda d: d["claim"]["densities"].append({"name": "rho7", "field": "lotka-volterra"}),
                                                "malformed"),
    "lv: a wrong convention": ("lotka", lambda d: d.__setitem__("convention", "eps = h"), "malformed"),
    "lv: the density's cofactor 'det Df' replaced by 1": ("lotka", lambda d: d["steps"][2].__setitem__("cofactor", "1"),
                                                           "refuted"),
    "lv: 'det Df' misspelled": ("lotka", lambda d: d["steps"][2].__setitem__("cofactor", "det df"), "malformed"),
    "et: an integral that is not of degree 0": ("euler", lambda d: d["steps"][0]["integrals"][0].update(
        formula=d["steps"][0]["polynomials"][1], **{"from": "P2"}), "malformed"),
    "et: a dropped polynomial": ("euler", _first("polynomials", lambda p: p[:-1]), "malformed"),
    "et: swapped polynomials": ("euler", _swap("polynomials", 0, 2), "refuted"),
    "et: a conclusion in the phase variables": ("euler", lambda d: d["steps"][0]["integrals"][0].__setitem__(
        "from", "x1/P1"), "malformed"),
    "et: a name taken by a variable": ("euler", _first("names", lambda n: ["x1", *n[1:]]), "malformed"),
}

RECIPE_G = {
    "a changed coefficient of a cofactor": (_first("cofactors", lambda c: [f"2*({c[0]})", *c[1:]]), "refuted"),
    "a dropped cofactor": (_first("cofactors", lambda c: c[:-1]), "malformed"),
    "swapped cofactors": (_swap("cofactors"), "refuted"),
    "a changed multiplier": (_first("multiplier", lambda m: f"({m})*(1 + eps**2)"), "refuted"),
    "a zero multiplier": (_first("multiplier", lambda m: "0"), "malformed"),
    "generators for eps = h (wrong convention)": (_first("generators", lambda g: [
        e.replace("eps", "2*eps") for e in g]), "refuted"),
    "swapped generators": (_swap("generators"), "refuted"),
    "another target": (lambda d: (d["steps"][0].update(function="x1**2/x2**2"),
                                  d["steps"][0]["integrals"][0].update(formula="x1**2/x2**2")), "refuted"),
    "a tilde name taken by a variable": (_first("tilde", lambda t: ["x2", *t[1:]]), "malformed"),
}


@pytest.mark.parametrize("name", DARBOUX)
def test_every_darboux_mutation_is_refused(lotka, euler, name):
    which, change, expected = DARBOUX[name]
    doc = {"lotka": lotka, "euler": euler}[which]
    assert verdict(mutated(doc, change)) == expected, name


def test_a_density_step_writes_det_df_for_the_checker_to_compute(lotka):
    assert lotka["steps"][2]["cofactor"] == "det Df" and lotka["steps"][2]["densities"]
    assert lotka["version"] == VERSION


@pytest.fixture(scope="module")
def degrees_doc(tmp_path_factory) -> dict:
    """degrees euler-top --iterates 3 --symbolic-up-to 3 --certificate FILE: deg f^n = 3, 9, 19, exact."""
    path = tmp_path_factory.mktemp("deg") / "deg.json"
    assert main(["degrees", "euler-top", "--iterates", "3", "--symbolic-up-to", "3", "--certificate", str(path)]) == 0
    return json.loads(path.read_text())


DEGREES = {
    "a wrong degree": (lambda d: d["steps"][0]["degrees"].__setitem__(2, 20), "refuted"),
    "a fourth degree that is not 2*4**2 + 1 = 33": (lambda d: d["steps"][0]["degrees"].append(34), "refuted"),
    "a degree as text": (lambda d: d["steps"][0]["degrees"].__setitem__(0, "3"), "malformed"),
    "no degrees": (lambda d: d["steps"][0].__setitem__("degrees", []), "malformed"),
    "another field": (lambda d: d["fields"]["euler-top"]["rhs"].__setitem__(0, "a1*x2*x3 + x1**2"), "refuted"),
}


def test_degrees_certificate_verifies(degrees_doc, capsys, tmp_path):
    assert degrees_doc["steps"][0]["degrees"] == [3, 9, 19] and verdict(degrees_doc) == "verified"
    assert main(["degrees", "euler-top", "--iterates", "3", "--certificate", str(tmp_path / "no.json")]) == 2
    out = capsys.readouterr()
    assert "degrees --symbolic-up-to" in out.err      # mod p degrees are evidence: no certificate
    assert "3, 9, 19" in out.out and not (tmp_path / "no.json").exists()    # the report is printed all the same
    assert main(["degrees", "euler-top", "--iterates", "3", "--json", "--certificate", str(tmp_path / "no.json")]) == 2
    assert "no certificate written" in json.loads(capsys.readouterr().out)["certificate_error"]


@pytest.mark.parametrize("name", DEGREES)
def test_every_degrees_mutation_is_refused(degrees_doc, name):
    change, expected = DEGREES[name]
    assert verdict(mutated(degrees_doc, change)) == expected, name


@pytest.mark.parametrize("name", RECIPE_G)
def test_every_recipe_g_mutation_is_refused(groebner, name):
    change, expected = RECIPE_G[name]
    assert verdict(mutated(groebner, change)) == expected, name


def test_truncated_files_are_malformed(lotka, groebner, capsys, tmp_path):
    for k, doc in enumerate((lotka, groebner)):
        text = json.dumps(doc)
        (tmp_path / f"t{k}.json").write_text(text[: len(text) * 2 // 3])
        assert main(["check", str(tmp_path / f"t{k}.json")]) == 2


def test_version_3_documents_follow_the_schema(lotka, euler, groebner, degrees_doc):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((Path(__file__).resolve().parents[1] / "docs" / "certificate.schema.json").read_text())
    for doc in (lotka, euler, groebner, degrees_doc):
        jsonschema.validate(doc, schema)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(mutated(groebner, lambda d: d["steps"][0].pop("cofactors")), schema)


@pytest.mark.skipif(shutil.which("Singular") is None, reason="Singular is not installed")
def test_singular_rechecks_darboux_steps(lotka, euler, tmp_path):
    """The exported Singular script re-checks P o f = K P (and K = det Df for the density) of measure lotka-volterra
    and euler-top; with a changed cofactor it says refuted."""
    bad = mutated(lotka, _first("cofactor", lambda k: f"({k})*(1 + eps)"))
    for doc, expected in ((lotka, ["verified: step 3"]), (euler, ["verified: step 1"]), (bad, ["refuted: step 1"])):
        script = tmp_path / "check.sing"
        script.write_text(singular_script(doc))
        out = subprocess.run(["Singular", "-q", str(script)], capture_output=True, text=True, timeout=300,
                             stdin=subprocess.DEVNULL)
        assert all(e in out.stdout for e in expected) and "?" not in out.stdout + out.stderr, out.stdout + out.stderr
        assert "K = det Df" in out.stdout or doc is not lotka
