"""The checker as a trust base (docs/certificates.md, "Threat model"; issue 36): forged recipe-g cofactors, claims
proven for another field, look-alike keys, duplicate keys, version laxity, a corpus of malformed files (exit 2, never
3), budgets (exit 4, never an abort) and the facts `check` shows. Every forgery here was accepted by the checker
before version 6; each test builds it and asserts refusal."""
from __future__ import annotations

import copy
import json
import os
import resource
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.checker import KahanData, check_document
from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.hk.recipe_g import recipe_g
from hkproof.proof.export import document, field_data, prop_even_step, recipe_g_step, substitution_step
from hkproof.proof.singular import singular_script

ROOT = Path(__file__).resolve().parents[1]
RIGID = ROOT / "docs" / "examples" / "rigid-body.toml"
C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"


def check(doc: dict):
    return check_document(json.loads(json.dumps(doc)))


def run(capsys, *args: str) -> tuple[int, str]:
    code = main(list(args))
    return code, capsys.readouterr().out


def forged_recipe_g(field: QuadraticField, h: str, multiplier: str) -> dict:
    """A recipe-g step for any h: lambda_1 = D delta / E_1 (x~ in its denominator), the other cofactors 0."""
    data = field_data(field)
    kd = KahanData("f", data)
    tilde = [f"{v}_t" for v in data["variables"]]
    big, equations = kd.equations(tilde)
    q = Frac.parse(big, h)
    to_y = {v: big.gen(y) for v, y in zip(kd.variables, tilde)}
    p_, q_ = Frac(big, q.num), Frac(big, q.den)
    delta = p_.substitute(to_y) * q_ - p_ * q_.substitute(to_y)
    lam1 = Frac.parse(big, multiplier) * delta / Frac(big, equations[0])
    step = {"kind": "recipe-g", "field": data, "function": h, "tilde": tilde,
            "generators": [str(e) for e in equations], "cofactors": [str(lam1)] + ["0"] * (len(equations) - 1),
            "multiplier": multiplier, "identity": "forged", "integrals": [{"name": "h", "formula": h, "from": "h"}]}
    return document("forged", "forged", [step])


@pytest.mark.parametrize("system, h, multiplier", [
    (RIGID, "u", "1"),                                    # u is no integral of the rigid body's Kahan map
    (RIGID, "q*u**2 - p*v**2", "1"),                      # the continuous energy, refuted by `integral`
    (RIGID, "v/w", "eps"),                                # D = eps
], ids=["h=u", "continuous energy", "h=v/w, D=eps"])
def test_forged_recipe_g_cofactors_are_refused(system, h, multiplier):
    doc = forged_recipe_g(kahan_map(str(system)).field, h, multiplier)
    report = check(doc)
    assert report.verdict == "malformed" and "x~ in its denominator" in report.lines[-1], report.lines
    assert report.facts == []


def test_a_genuine_recipe_g_certificate_verifies_and_singular_agrees(tmp_path):
    f = kahan_map("euler-top")
    h = f.field.parse(C1)
    cert = recipe_g(f, h).certificate
    doc = document("c1", "c1", [recipe_g_step(f.field, "c1", h, cert.generators, cert.cofactors,
                                              cert.multiplier ** cert.power)])
    assert check(doc).verdict == "verified"
    script = singular_script(doc)
    assert "not exported" not in script and "hkLD" in script
    if shutil.which("Singular") is None:
        pytest.skip("Singular is not installed")
    bad = copy.deepcopy(doc)
    bad["steps"][0]["cofactors"][0] = f"({bad['steps'][0]['cofactors'][0]}) + x1"
    for d, expected in ((doc, "verified: step 1"), (bad, "refuted: step 1")):
        (tmp_path / "g.sing").write_text(singular_script(d))
        out = subprocess.run(["Singular", "-q", str(tmp_path / "g.sing")], capture_output=True, text=True,
                             timeout=300, stdin=subprocess.DEVNULL)
        assert expected in out.stdout and "?" not in out.stdout + out.stderr, out.stdout + out.stderr


@pytest.fixture(scope="module")
def c1() -> dict:
    f = kahan_map("euler-top")
    return document("c1", "c1 is an integral", [substitution_step(f.field, "c1", f.field.parse(C1))])


def with_aux(doc: dict, key: str, rhs: list[str]) -> dict:
    """`doc` plus a field `key` with right-hand sides `rhs`, on which a substitution step concludes c1 instead."""
    out = copy.deepcopy(doc)
    out["fields"][key] = {**out["fields"]["euler-top"], "rhs": rhs}
    out["steps"][0]["field"] = key
    return out


def test_a_claim_proven_only_for_another_field_is_refused(c1):
    forged = with_aux(c1, "aux", ["0", "0", "0"])       # the identity map: every h is its integral
    assert forged["claim"]["integrals"] == [{"name": "c1", "field": "euler-top"}]
    report = check(forged)
    assert report.verdict == "malformed" and "speaks of field aux" in report.lines[-1]


def test_a_look_alike_field_key_is_refused(c1):
    forged = with_aux(c1, "euler\u2011top", ["0", "0", "0"])      # a non-breaking hyphen
    forged["claim"]["integrals"] = [{"name": "c1", "field": "euler\u2011top"}]
    report = check(forged)
    assert report.verdict == "malformed" and "not an ASCII identifier" in report.lines[-1]


def test_check_shows_the_field_it_verified_for(c1, capsys, tmp_path):
    """A field keyed euler-top that is the Euler top divided by 2 verifies (true for that field) and the output shows
    its right-hand sides, so that the referee sees what was proven."""
    f = kahan_map("euler-top")
    halved = QuadraticField("euler-top", f.field.variables, f.field.parameters, [f"({t})/2" for t in f.field.rhs_text])
    h = halved.parse(C1)
    doc = document("c1", "c1", [substitution_step(halved, "c1", h)])
    (tmp_path / "half.json").write_text(json.dumps(doc))
    code, out = run(capsys, "check", str(tmp_path / "half.json"))
    assert code == 0
    assert "integral c1 of field euler-top: " + str(h) in out
    assert f"field euler-top: x1' = {halved.rhs[0]}, " in out and "sha256" in out
    code, out = run(capsys, "check", str(tmp_path / "half.json"), "--json")
    payload = json.loads(out)
    assert any(line.startswith("field euler-top: x1' = ") for line in payload["verified"])


def test_old_versions_are_read_only_where_unambiguous(c1):
    old = copy.deepcopy(c1)
    old["version"], old["claim"]["integrals"] = 5, ["c1"]
    assert check(old).verdict == "verified"                 # one field: the name can mean one thing only
    two = with_aux(old, "aux", ["0", "0", "0"])
    report = check(two)
    assert report.verdict == "malformed" and "ambiguous" in report.lines[-1]


@pytest.mark.parametrize("version, change", [
    (1, lambda d: d["steps"][0].update(kind="reparametrization", source="x")),
    (1, lambda d: d["steps"][0].update(kind="darboux")),
    (2, lambda d: d["steps"][0].update(kind="degrees", degrees=[3])),
    (2, lambda d: d["steps"][0].update(cofactor="det Df")),
    (3, lambda d: d["steps"][0].update(blocks=[])),
], ids=["v1 reparametrization", "v1 darboux", "v2 degrees", "v2 det Df", "v3 blocks"])
def test_step_kinds_are_gated_by_the_version(c1, version, change):
    old = copy.deepcopy(c1)
    old["version"], old["claim"]["integrals"] = version, ["c1"]
    change(old)
    report = check(old)
    assert report.verdict == "malformed" and "is a feature of version" in report.lines[-1], report.lines


def test_duplicate_keys_are_refused(c1, capsys, tmp_path):
    text = json.dumps(c1).replace('"rhs": [', '"rhs": ["0", "0", "0"], "rhs": [', 1)
    (tmp_path / "dup.json").write_text(text)
    code, out = run(capsys, "check", str(tmp_path / "dup.json"))
    assert code == 2 and "appears twice" in out


def test_a_degenerate_point_is_not_a_refutation():
    f = kahan_map("euler-top")
    x1, x2, x3 = (f.field.parse(v) for v in ("x1**2", "x2**2", "x3**2"))
    kd = KahanData("euler-top", field_data(f.field))
    solution = [Frac.parse(kd.ring, "(x3**2*a2 - x2**2*a3)/(-x2**2*a1 + x1**2*a2)"),
                Frac.parse(kd.ring, "(-x3**2*a1 + x1**2*a3)/(-x2**2*a1 + x1**2*a2)")]
    point = {"x1": 0, "x2": 0, "x3": 0, "eps": 1, "a1": 1, "a2": 2, "a3": 3}
    doc = document("d", "d", [prop_even_step(f.field, [x1, x2], x3, ["c1", "c2"], solution, [0, 1], [], point)])
    report = check(doc)
    assert report.verdict == "malformed" and "degenerate" in report.lines[-1] and "choose another" in report.lines[-1]
    doc["steps"][0]["point"] = {k: v for k, v in zip(point, ["5/11", "7/20", "1/3", "13/46", "17/63", "19/8", "2"])}
    assert check(doc).verdict == "verified"
    doc["steps"][0]["iterates"] = [0, True]
    assert check(doc).verdict == "malformed"


def test_a_parameter_named_like_the_checkers_own_names_is_fine():
    f = QuadraticField("t", ("x1", "x2"), ("x1_y",), ("x1_y*x2", "-x1"))
    doc = document("t", "t", [substitution_step(f, "H", f.parse("x1**2 + x1_y*x2**2"))])
    assert check(doc).verdict == "verified"         # a linear field: Kahan's map keeps its quadratic energy
    doc["steps"][0]["function"] = doc["steps"][0]["integrals"][0]["formula"] = "x1**2 + 2*x1_y*x2**2"
    assert check(doc).verdict == "refuted"


def _corpus(base: dict) -> dict[str, str]:
    """At least 30 malformed certificate texts: types swapped, numbers as strings, huge integers, deep nesting."""
    def m(change) -> str:
        d = copy.deepcopy(base)
        change(d)
        return json.dumps(d)
    step = lambda d: d["steps"][0]                              # noqa: E731
    field = lambda d: d["fields"]["euler-top"]                  # noqa: E731
    text = json.dumps(base)
    return {
        "empty": "", "not json": "certificate", "a list": "[1, 2]", "a string": '"x"', "null": "null",
        "truncated": text[: len(text) // 2], "nested 200000": "[" * 200_000 + "]" * 200_000,
        "huge integer version": text.replace('"version": 10', '"version": 10' + "0" * 5000),
        "version as string": m(lambda d: d.update(version="6")), "version true": m(lambda d: d.update(version=True)),
        "version float": text.replace('"version": 10', '"version": 10.0'), "NaN": text.replace('"version": 10', '"version": NaN'),
        "format missing": m(lambda d: d.pop("format")), "steps an object": m(lambda d: d.update(steps={})),
        "steps empty": m(lambda d: d.update(steps=[])), "step a string": m(lambda d: d.update(steps=["x"])),
        "fields a list": m(lambda d: d.update(fields=[])), "field a string": m(lambda d: d["fields"].update({"euler-top": "x"})),
        "rhs a string": m(lambda d: field(d).update(rhs="x1")), "rhs numbers": m(lambda d: field(d).update(rhs=[1, 2, 3])),
        "rhs cubic": m(lambda d: field(d)["rhs"].__setitem__(0, "x1**3")), "rhs with eps": m(lambda d: field(d)["rhs"].__setitem__(0, "eps*x1")),
        "variables true": m(lambda d: field(d).update(variables=True)), "variable named _z": m(lambda d: field(d)["variables"].__setitem__(0, "_z")),
        "duplicate variable": m(lambda d: field(d)["variables"].__setitem__(1, "x1")),
        "integrals a number": m(lambda d: step(d).update(integrals=5)), "densities a number": m(lambda d: step(d).update(densities=5)),
        "integral entry a string": m(lambda d: step(d).update(integrals=["c1"])),
        "function a number": m(lambda d: step(d).update(function=7)), "function bad text": m(lambda d: step(d).update(function="x1 +* 2")),
        "function eval attempt": m(lambda d: step(d).update(function="__import__('os')")),
        "kind a list": m(lambda d: step(d).update(kind=["substitution"])), "field key missing": m(lambda d: step(d).pop("field")),
        "claim integrals strings": m(lambda d: d["claim"].update(integrals=["c1"])),
        "claim integral of unknown field": m(lambda d: d["claim"]["integrals"][0].update(field="clebsch")),
        "claim integrals null": m(lambda d: d["claim"].update(integrals=None)),
        "huge literal in a formula": m(lambda d: step(d).update(function="1" * 20_000)),
        "iterates strings": m(lambda d: step(d).update(kind="prop-even", iterates=[0, "1"], basis=[], target="1",
                                                        names=[], solution=[], relations=[], point={})),
        "degrees true": m(lambda d: step(d).update(kind="degrees", degrees=[True], integrals=[])),
        "a non-ASCII key": m(lambda d: d["fields"].update({"\u00e9": field(d)})),
    }


def test_a_corpus_of_malformed_files_exits_2_never_3(c1, tmp_path, capsys):
    """Each file through the command's own entry point (exit code and error stream), and one through a real process
    (the code the shell sees)."""
    corpus = _corpus(c1)
    assert len(corpus) >= 30
    path = tmp_path / "bad.json"
    for name, text in corpus.items():
        path.write_text(text)
        code = main(["check", str(path), "--json"])
        out, err = capsys.readouterr()
        assert code == 2, (name, code, out[-500:], err[-500:])
        assert "Traceback" not in err, name
    path.write_text(corpus["nested 200000"])
    proc = subprocess.run([sys.executable, "-m", "hkproof.cli", "check", str(path), "--json"], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr


def _child_peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024


def test_check_refuses_a_composition_too_large_up_front(c1, tmp_path):
    """function x1**3000: degree 9000 after composition, refused before any work (exit 4, the limit named)."""
    doc = copy.deepcopy(c1)
    doc["steps"][0]["function"] = doc["steps"][0]["integrals"][0]["formula"] = "x1**3000"
    (tmp_path / "big.json").write_text(json.dumps(doc))
    start = time.monotonic()
    proc = subprocess.run([sys.executable, "-m", "hkproof.cli", "check", str(tmp_path / "big.json"), "--seconds", "20",
                           "--json"], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 4, (proc.stdout, proc.stderr)
    error = json.loads(proc.stdout)
    assert error["error"] == "ResourceLimitError" and "degree 1000" in error["limit"]
    assert time.monotonic() - start < 300 and _child_peak_mb() < 2048


def test_check_stops_at_its_deadline_and_its_memory_ceiling(c1, tmp_path):
    """function x1**300 (degree 900: under the up-front limit) composed with the Euler top map: stopped by --seconds
    or by --memory-mb, exit 4, never an abort (134) and never an answer."""
    doc = copy.deepcopy(c1)
    doc["steps"][0]["function"] = doc["steps"][0]["integrals"][0]["formula"] = "x1**300"
    (tmp_path / "slow.json").write_text(json.dumps(doc))
    for option in (["--seconds", "3"], ["--memory-mb", "300"]):
        proc = subprocess.run([sys.executable, "-m", "hkproof.cli", "check", str(tmp_path / "slow.json"), *option,
                               "--json"], cwd=ROOT, capture_output=True, text=True, timeout=900)
        assert proc.returncode == 4, (option, proc.stdout, proc.stderr[-800:])
        assert json.loads(proc.stdout)["error"] in ("BudgetExhausted", "ResourceLimitError")


def test_a_field_of_too_many_variables_is_refused_up_front(tmp_path):
    names = [f"y{k}" for k in range(24)]
    rhs = [" + ".join(f"{a}*{b}" for a in names[:3] for b in names[k:k + 2]) for k in range(24)]
    doc = {"format": "hkproof-certificate", "version": 6, "convention": "eps = h/2",
           "claim": {"title": "t", "statement": "t", "integrals": [{"name": "H", "field": "big"}]},
           "fields": {"big": {"variables": names, "parameters": [], "rhs": rhs}},
           "steps": [{"field": "big", "kind": "substitution", "function": "y0",
                      "integrals": [{"name": "H", "formula": "y0", "from": "H"}]}]}
    (tmp_path / "dense.json").write_text(json.dumps(doc))
    proc = subprocess.run([sys.executable, "-m", "hkproof.cli", "check", str(tmp_path / "dense.json")], cwd=ROOT,
                          capture_output=True, text=True, timeout=300, env={**os.environ})
    assert proc.returncode == 4 and "12 phase variables" in proc.stdout + proc.stderr


def test_sigterm_ends_a_long_check(c1, tmp_path):
    """The check runs in a forked child: a SIGTERM reaches the parent at once (exit 130), and the child is killed."""
    doc = copy.deepcopy(c1)
    doc["steps"][0]["function"] = doc["steps"][0]["integrals"][0]["formula"] = "x1**300"
    (tmp_path / "slow.json").write_text(json.dumps(doc))
    proc = subprocess.Popen([sys.executable, "-c", "import sys; from hkproof.cli import main; sys.exit(main())",
                             "check", str(tmp_path / "slow.json")], cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    children: list[int] = []
    deadline = time.monotonic() + 300
    while not children and proc.poll() is None and time.monotonic() < deadline:     # wait for a state: the child
        try:
            children = [int(c) for c in Path(f"/proc/{proc.pid}/task/{proc.pid}/children").read_text().split()]
        except OSError:
            pass
        time.sleep(0.05)
    assert children, "the check never forked its child"
    sent = time.monotonic()
    proc.terminate()
    out, err = proc.communicate(timeout=120)
    assert proc.returncode == 130 and "Traceback" not in err.decode(), err.decode()[-800:]
    assert time.monotonic() - sent < 60
    time.sleep(0.5)
    assert all(not Path(f"/proc/{c}").exists() or "Z" in Path(f"/proc/{c}/stat").read_text().split()[2]
               for c in children)
