"""Certificate files (docs/certificates.md): what `--certificate` writes, `hkproof check` verifies, and every mutation of
a certificate (a coefficient, a relation, a basis element, the step convention, the version, a truncated file) is
refused with its exit code; the checker stays small and imports only the parser and FLINT types."""
from __future__ import annotations

import ast
import copy
import json
import shutil
import subprocess
from pathlib import Path

import pytest

from hkproof.checker import KahanData, check_document
from hkproof.cli import main
from hkproof.commands._certificates import theorem_document
from hkproof.dynamics.catalogue import kahan_map
from hkproof.orchestration.registry import proven
from hkproof.proof.export import document, field_data, substitution_step
from hkproof.proof.singular import singular_script

C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"
CHECKER = Path(__file__).resolve().parents[1] / "hkproof" / "checker"


def run(capsys, *args: str) -> tuple[int, str]:
    code = main(list(args))
    return code, capsys.readouterr().out


def verdict(doc: dict) -> str:
    return check_document(json.loads(json.dumps(doc))).verdict


@pytest.fixture(scope="module")
def theorems() -> dict:
    """The recorded steps of three Prop. "prop: even" theorems (Euler top's two bases, Clebsch's basis 1 with a
    relation)."""
    return theorem_document([proven(c) for c in ("et-first-hk-basis", "et-second-hk-basis", "dc-basis1-even")])


def test_the_checkers_kahan_map_is_hkprofs(capsys):
    """The checker's own Cramer rule gives the same map N/Delta as hkproof's KahanMap (up to a common factor)."""
    from hkproof.algebra.fraction import Frac
    for name in ("lotka-volterra", "euler-top", "clebsch", "volterra-3"):
        kmap = kahan_map(name)
        mine = KahanData(name, field_data(kmap.field))
        nums, delta = kmap.explicit
        assert all(Frac(kmap.ring, a, delta) == Frac(kmap.ring, b, mine.delta) for a, b in zip(nums, mine.nums))


def test_integral_certificate_round_trip(capsys, tmp_path):
    target = tmp_path / "c1.json"
    code, out = run(capsys, "integral", "euler-top", C1, "--certificate", str(target))
    assert code == 0 and "certificate:" in out
    code, out = run(capsys, "check", str(target))
    assert code == 0 and out.startswith("verified")
    doc = json.loads(target.read_text())
    doc["steps"][0]["function"] = C1.replace("a3*x2**2", "2*a3*x2**2")          # a changed coefficient
    doc["steps"][0]["integrals"][0]["formula"] = doc["steps"][0]["function"]
    target.write_text(json.dumps(doc))
    assert run(capsys, "check", str(target))[0] == 1


def test_a_refuted_integral_writes_no_certificate(capsys, tmp_path):
    target = tmp_path / "no.json"
    assert run(capsys, "integral", "euler-top", "x1**2 + x2**2", "--certificate", str(target))[0] == 1
    assert not target.exists()


def test_unknown_step_kinds_are_refused_not_verified(capsys, tmp_path):
    kmap = kahan_map("lotka-volterra")
    step = {"kind": "series", "field": field_data(kmap.field), "function": "x",
            "integrals": [{"name": "h", "formula": "x", "from": "h"}]}
    report = check_document(document("g", "g", [step]))
    assert report.verdict == "malformed" and "cannot check this step kind 'series'" in report.lines[-1]


def test_discover_certificate_round_trip(capsys, tmp_path):
    target = tmp_path / "et.json"
    code, _ = run(capsys, "discover", "euler-top", "--no-progress", "--certificate", str(target))
    assert code == 0
    doc = json.loads(target.read_text())
    assert len(doc["claim"]["integrals"]) == 2
    assert run(capsys, "check", str(target))[0] == 0


def test_a_discover_certificate_with_a_conserved_coordinate_verifies(capsys, tmp_path):
    """lagrange-top (m3' = 0): the conserved coordinate is concluded as conserved_m3 (not as the variable's name), the
    bases proven with m3 as a parameter are checked on the field itself, their relations citing m3 as that integral;
    all four integrals verify, and without the step proving conserved_m3 the file is malformed."""
    target = tmp_path / "lagrange.json"
    assert run(capsys, "discover", "lagrange-top", "--no-progress", "--certificate", str(target))[0] == 0
    doc = json.loads(target.read_text())
    assert doc["claim"]["integrals"][0] == {"name": "conserved_m3", "field": "lagrange-top"} and len(doc["claim"]["integrals"]) == 4
    assert len(doc["fields"]) == 1
    assert any("conserved_m3" in r["uses"] for s in doc["steps"] for r in s.get("relations", []))
    assert run(capsys, "check", str(target))[0] == 0
    assert check_document(_mutated(doc, lambda d: d["steps"].pop(0))).verdict == "malformed"


def test_theorem_certificates_verify(theorems, capsys, tmp_path):
    assert [s["kind"] for s in theorems["steps"]] == ["prop-even"] * 3
    assert verdict(theorems) == "verified"
    target = tmp_path / "prove.json"
    assert run(capsys, "prove", "et-first-hk-basis", "--jobs", "1", "--certificate", str(target))[0] == 0
    assert run(capsys, "check", str(target))[0] == 0


def _mutated(doc: dict, change) -> dict:
    out = copy.deepcopy(doc)
    change(out)
    return out


def _swap_basis(d: dict) -> None:
    b = d["steps"][0]["basis"]
    b[0], b[1] = b[1], b[0]


MUTATIONS = {
    "a changed coefficient of the field": (lambda d: d["fields"]["euler-top"]["rhs"].__setitem__(0, "2*x2*x3*a1"),
                                           "refuted"),
    "a changed coefficient of the solution": (lambda d: d["steps"][0]["solution"].__setitem__(
        0, f"({d['steps'][0]['solution'][0]}) + eps**2"), "refuted"),
    "a component that is not even": (lambda d: d["steps"][0]["solution"].__setitem__(
        0, f"({d['steps'][0]['solution'][0]}) + eps"), "refuted"),
    "a swapped basis element": (_swap_basis, "refuted"),
    "a basis function odd in eps": (lambda d: d["steps"][0]["basis"].__setitem__(0, "eps*x1**2"), "malformed"),
    "a changed relation": (lambda d: d["steps"][2]["relations"][0].__setitem__("rhs", "eps**2*w1 + eps**2*w2"),
                           "refuted"),
    "a dropped relation": (lambda d: d["steps"][2].__setitem__("relations", []), "malformed"),
    "a relation in the phase variables": (lambda d: d["steps"][2]["relations"][0].__setitem__("rhs", "p1 - p1"),
                                          "malformed"),
    "a relation citing no proven integral": (lambda d: d["steps"][2]["relations"][0].__setitem__("uses", ["J"]),
                                             "malformed"),
    "a wrong step convention (eps = h)": (lambda d: d.__setitem__("convention", "eps = h"), "malformed"),
    "another version": (lambda d: d.__setitem__("version", 11), "malformed"),
    "another format": (lambda d: d.__setitem__("format", "drat"), "malformed"),
    "a claimed integral no step concludes": (lambda d: d["claim"]["integrals"].append({"name": "c9", "field": "euler-top"}), "malformed"),
    "a symmetric range of rows": (lambda d: d["steps"][0].__setitem__("iterates", [-1, 1]), "malformed"),
    "a conclusion that is not the stated formula": (lambda d: d["steps"][0]["integrals"][0].__setitem__(
        "from", "c2"), "refuted"),
    "a point where the determinant vanishes": (lambda d: d["steps"][0]["point"].update(x1="0", x2="0", x3="0"),
                                               "malformed"),
}


@pytest.mark.parametrize("name", MUTATIONS)
def test_every_mutation_is_refused(theorems, name):
    change, expected = MUTATIONS[name]
    assert verdict(_mutated(theorems, change)) == expected, name


def test_bad_files_are_malformed(theorems, capsys, tmp_path):
    """A truncated file, a JSON float, a missing file: exit 2, never a traceback."""
    text = json.dumps(theorems)
    version = f'"version": {theorems["version"]}'
    cases = {"truncated.json": text[: len(text) // 2], "float.json": text.replace(version, version + ".0"),
             "list.json": "[1, 2]"}
    assert cases["float.json"] != text
    for name, content in cases.items():
        (tmp_path / name).write_text(content)
        assert run(capsys, "check", str(tmp_path / name))[0] == 2, name
    assert run(capsys, "check", str(tmp_path / "missing.json"))[0] == 2


def test_certificate_targets_are_checked_first(capsys, tmp_path):
    """--certificate refuses a directory before any work (exit 2), like report --write."""
    assert run(capsys, "integral", "euler-top", C1, "--certificate", str(tmp_path))[0] == 2


def test_prove_with_nothing_to_write_says_so(capsys, tmp_path):
    """`prove ID --certificate F` for a claim whose steps a file cannot record prints its report, writes nothing and
    exits 2 with the reason (it exited 0 silently), as the other commands do; with --json the reason is in the
    document."""
    target = tmp_path / "none.json"
    assert main(["prove", "lv-explicit-map", "--jobs", "1", "--certificate", str(target)]) == 2
    out = capsys.readouterr()
    assert "1 of 1 theorems verified" in out.out and "no certificate written" in out.err and not target.exists()
    assert main(["prove", "lv-explicit-map", "--jobs", "1", "--json", "--certificate", str(target)]) == 2
    assert "no certificate written" in json.loads(capsys.readouterr().out)["certificate_error"]


def test_the_checker_is_small_and_trusts_only_the_parser():
    """The checker package imports of hkproof only the parser, Frac, Ring, the error classes and its own modules, and
    stays short enough to read in an afternoon."""
    lines = 0
    for module in sorted(CHECKER.glob("*.py")):
        tree = ast.parse(module.read_text())
        imported = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom) and n.module}
        imported |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
        ours = {m for m in imported if m.startswith("hkproof") and not m.startswith("hkproof.checker")}
        assert ours <= {"hkproof.algebra.formula", "hkproof.algebra.fraction", "hkproof.algebra.ring",
                        "hkproof.errors"}, module
        lines += len(module.read_text().splitlines())
    assert lines < 1480          # 1 212 with the torus of exclusion steps (checker/torus.py), 1 387 with no-poisson,
    #                              1 416 with nambu (its rank checked: 24 lines), 1 474 with nambu's universal
    #                              identities expanded by the checker (58 lines)


@pytest.mark.skipif(shutil.which("Singular") is None, reason="Singular is not installed")
@pytest.mark.parametrize("system, h", [("euler-top", C1), ("euler-top", "(a1*x2**2 - a2*x1**2)/(a3*x1**2 - a1*x3**2)")])
def test_singular_rechecks_the_substitution(tmp_path, system, h):
    """The exported Singular script rebuilds the map and re-checks h o f = h; with a changed coefficient it says
    refuted."""
    kmap = kahan_map(system)
    good = document("h", "h", [substitution_step(kmap.field, "h", kmap.field.parse(h))])
    bad = _mutated(good, lambda d: d["fields"][system]["rhs"].__setitem__(0, "2*" + d["fields"][system]["rhs"][0]))
    for doc, expected in ((good, "verified: step 1"), (bad, "refuted: step 1")):
        script = tmp_path / "check.sing"
        script.write_text(singular_script(doc))
        out = subprocess.run(["Singular", "-q", str(script)], capture_output=True, text=True, timeout=120,
                             stdin=subprocess.DEVNULL)
        assert expected in out.stdout and "?" not in out.stdout + out.stderr, out.stdout + out.stderr


def test_a_discovered_basis_with_relations_in_proven_integrals_round_trips():
    """Prop. "prop: even" on Psi (discover's route): its relation's right-hand side is written in the proven
    integral I1, and the checker re-verifies it; citing an integral the file does not prove is refused."""
    from tests.test_discover import _psi_proof
    f, known, proof = _psi_proof()
    doc = document("psi", "psi", [substitution_step(f.field, "I1", known["I1"])], certificates=[proof.certificate])
    assert any("I1" in r["uses"] for r in doc["steps"][1]["relations"])
    assert verdict(doc) == "verified"
    assert verdict(_mutated(doc, lambda d: d["steps"].pop(0))) == "malformed"


def test_documents_follow_the_schema(theorems):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads((CHECKER.parents[1] / "docs" / "certificate.schema.json").read_text())
    kmap = kahan_map("euler-top")
    jsonschema.validate(theorems, schema)
    jsonschema.validate(document("c1", "c1", [substitution_step(kmap.field, "c1", kmap.field.parse(C1))]), schema)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(_mutated(theorems, lambda d: d.__setitem__("convention", "eps = h")), schema)


@pytest.mark.slow
def test_theorems_citing_other_claims_are_exported_and_verify():
    """dc-theta's relation uses d7, d8 of dc-basis2: its right-hand side is proven in the same file by a substitution
    step (about 80 s in the checker), named, and used by the prop-even step; without that step it is malformed."""
    doc = theorem_document([proven("dc-theta")])
    assert [s["kind"] for s in doc["steps"]] == ["substitution", "prop-even"]
    assert doc["steps"][1]["relations"][0]["uses"] == [doc["steps"][0]["integrals"][0]["name"]]
    assert verdict(doc) == "verified"
    assert verdict(_mutated(doc, lambda d: d["steps"].pop(0))) == "malformed"


@pytest.mark.slow
def test_check_verifies_every_certificate_of_prove_all(capsys, tmp_path):
    """`prove --all --certificate FILE` exports every verified theorem that records a re-checkable step (the four
    that cite other claims' integrals included) and `check FILE` verifies it (tens of minutes)."""
    target = tmp_path / "all.json"
    assert run(capsys, "prove", "--all", "--jobs", "2", "--certificate", str(target))[0] == 0
    doc = json.loads(target.read_text())
    title = doc["claim"]["title"]
    assert all(c in title for c in ("dc-theta", "dc345-alpha", "dc345-step5", "flow-second-theta"))
    assert run(capsys, "check", str(target), "--seconds", "20000", "--memory-mb", "16000")[0] == 0
