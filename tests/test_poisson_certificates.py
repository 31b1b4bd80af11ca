"""Certificates of invariant bivectors (version 7): `hkproof poisson --certificate` round trips through `hkproof
check`; a changed coefficient, Casimir or involution is refuted; a forged exclusion is refused, since the checker
computes the rows itself from the field at the stated values and points."""
from __future__ import annotations

import copy
import json
from functools import lru_cache

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.checker import check_document
from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.pipelines.poisson import search_poisson, with_integrals
from hkproof.pipelines.poisson_certificate import poisson_document


@lru_cache(maxsize=None)
def _doc(system: str, degree: int, integrals: bool) -> str:
    f = kahan_map(system)
    report = with_integrals(f, degree) if integrals else search_poisson(f, degree)
    return json.dumps(poisson_document(f, report))


def doc(system: str, degree: int, integrals: bool = True) -> dict:
    return json.loads(_doc(system, degree, integrals))


def verdict(d: dict) -> str:
    return check_document(json.loads(json.dumps(d))).verdict


def kind(d: dict, name: str, k: int = 0) -> dict:
    return [s for s in d["steps"] if s["kind"] == name][k]


def test_lotka_volterra_round_trip_through_the_command(tmp_path, capsys):
    out = tmp_path / "lv.json"
    assert main(["poisson", "lotka-volterra", "--integrals-degree", "0", "--no-progress", "--certificate", str(out)]) == 0
    capsys.readouterr()
    assert main(["check", str(out)]) == 0
    assert "bivector Pi1 of field lotka-volterra: [[0, x*y], [-x*y, 0]]" in capsys.readouterr().out
    d = json.loads(out.read_text())
    assert d["version"] == 10 and d["claim"]["bivectors"] == [{"name": "Pi1", "field": "lotka-volterra"}]
    assert [s["kind"] for s in d["steps"]] == ["bivector-invariance", "jacobi"] + ["exclusion"] * 3    # x^2, xy, y^2
    assert {s["denominator"] for s in d["steps"][2:]} == {"(x)**2", "(y)*(x)", "(y)**2"}     # as products of factors


def test_a_changed_coefficient_is_refuted():
    d = doc("lotka-volterra", 3, integrals=False)
    m = kind(d, "bivector-invariance")["matrix"]
    m[0][1], m[1][0] = "x*y + x", "-x*y - x"
    assert verdict(d) == "refuted"
    m[0][1] = "x*y"                                           # not antisymmetric any more
    assert verdict(d) == "malformed"


def test_euler_top_pencil_casimirs_and_involution_round_trip():
    d = doc("euler-top", 3)
    kinds = [s["kind"] for s in d["steps"]]
    assert kinds.count("bivector-invariance") == 4 and kinds.count("jacobi") == 7 and "involution" in kinds
    assert "exclusion" in kinds and len(d["claim"]["bivectors"]) == 4            # the pencil's three, the Nambu one
    assert verdict(d) == "verified"


@pytest.mark.parametrize("change", ["coefficient", "casimir", "involution"])
def test_euler_top_mutations_are_refuted(change):
    d = doc("euler-top", 3)
    if change == "coefficient":
        m = kind(d, "bivector-invariance", 1)["matrix"]
        m[1][2], m[2][1] = m[1][2].replace("x1*x3**2*a2", "2*x1*x3**2*a2"), m[2][1].replace("x1*x3**2*a2", "2*x1*x3**2*a2")
        assert "2*x1*x3**2*a2" in m[1][2]
    elif change == "casimir":
        kind(d, "casimir", 1)["functions"] = ["I2"]
    elif change == "involution":
        kind(d, "involution")["functions"] = ["I1", "x1"]
    assert verdict(d) == "refuted", change


def test_an_invariant_bivector_that_is_not_poisson_fails_jacobi():
    """For the field 0 the Kahan map is the identity, so every bivector is invariant; v = (x2, 0, 1) has
    v . curl v = -1, so Pi^23 = x2, Pi^31 = 0, Pi^12 = 1 is not Poisson: the jacobi step is refuted."""
    matrix = [["0", "1", "0"], ["-1", "0", "x2"], ["0", "-x2", "0"]]
    d = {"format": "hkproof-certificate", "version": 7, "convention": "eps = h/2",
         "claim": {"title": "t", "statement": "s", "fixed": {}, "integrals": [],
                   "bivectors": [{"name": "Pi", "field": "zero"}]},
         "fields": {"zero": {"variables": ["x1", "x2", "x3"], "parameters": [], "rhs": ["0", "0", "0"]}},
         "steps": [{"field": "zero", "kind": "bivector-invariance", "name": "Pi", "matrix": matrix, "integrals": []}]}
    assert verdict(d) == "verified"
    d["steps"].append({"field": "zero", "kind": "jacobi", "bivectors": ["Pi"], "integrals": []})
    assert verdict(d) == "refuted"


def test_a_forged_exclusion_is_refused():
    """An exclusion of a class that holds an invariant bivector (Q = xy for Lotka-Volterra, degree 2) cannot be
    certified: the checker computes the rows from the field, and they have a kernel; rows in the file are refused."""
    d = doc("lotka-volterra", 1, integrals=False)
    assert verdict(d) == "verified"
    step = kind(d, "exclusion")
    forged = copy.deepcopy(d)
    kind(forged, "exclusion")["degree"] = 2
    for x in range(3, 13):                                     # more points: still no full rank
        kind(forged, "exclusion")["blocks"][0]["points"].append([x, x + 5])
    report = check_document(forged)
    assert report.verdict == "malformed" and "do not have full column rank" in report.lines[-1]
    with_rows = copy.deepcopy(d)
    kind(with_rows, "exclusion")["rows"] = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    assert verdict(with_rows) == "malformed"
    for key, value in (("prime", 1277389331 * 3), ("prime", 2), ("symmetries", [[1, 1]]), ("blocks", [])):
        bad = copy.deepcopy(d)
        kind(bad, "exclusion")[key] = value
        assert verdict(bad) == "malformed", key
    bad = copy.deepcopy(d)
    kind(bad, "exclusion")["values"]["eps"] = f"1/{step['prime']}"
    assert verdict(bad) == "malformed"


def test_a_false_symmetry_of_an_exclusion_is_refuted():
    d = doc("euler-top", 2, integrals=False)
    step = kind(d, "exclusion")
    assert step["symmetries"] and verdict(d) == "verified"
    step["symmetries"][0] = [1, 1, -1] if step["symmetries"][0] != [1, 1, -1] else [1, -1, -1]
    assert verdict(d) in ("refuted", "malformed")


def test_bivector_claims_are_bound_to_their_steps():
    d = doc("lotka-volterra", 3, integrals=False)
    old = copy.deepcopy(d)
    old["version"] = 6
    old["claim"].pop("bivectors")
    assert "feature of version 7" in check_document(old).lines[-1]
    d["claim"]["bivectors"].append({"name": "Pi9", "field": "lotka-volterra"})
    assert verdict(d) == "malformed"


def test_poisson_documents_follow_the_schema():
    jsonschema = pytest.importorskip("jsonschema")
    from pathlib import Path
    schema = json.loads((Path(__file__).resolve().parents[1] / "docs" / "certificate.schema.json").read_text())
    jsonschema.validate(doc("euler-top", 3), schema)
    forged = doc("lotka-volterra", 1, integrals=False)
    kind(forged, "exclusion")["rows"] = [[1]]
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(forged, schema)


def test_the_euler_top_liouville_arnold_claim_and_its_perturbation():
    from hkproof.orchestration.registry import get_claim
    from hkproof.proof.status import Status
    c = get_claim("atlas-euler-top-liouville-arnold")
    cert = c.prove()
    # 2 integrals, 3 structures (invariance, Jacobi, Casimir), 3 compatible pairs, 2 involutions, the Nambu structure
    # (invariance, Jacobi, Casimir), and the 9 classes D != 1 of the factors of den(I1), den(I2) and of measure's
    # Darboux polynomials excluded at degree 3
    assert cert.status is Status.VERIFIED and len(cert.checks) == 28
    assert sum(s["kind"] == "exclusion" for s in cert.checks) == 9
    assert c.prove({"rank": "4"}).status is Status.REFUTED
    assert c.prove({"structures": "2"}).status is Status.REFUTED


@pytest.mark.slow           # about 40 s per proof
def test_the_zhukovsky_volterra_liouville_arnold_claim_checked_by_sympy_and_perturbed():
    """Four rank-2 Poisson structures Q/den(I_k) of degree 5 (none with D = 1): each structure of the certificate is
    invariant and Poisson by an independent sympy computation at a random rational point; one coefficient changed is
    refuted there; a claim of rank 4 is refuted by the proof."""
    from types import SimpleNamespace

    from hkproof.orchestration.registry import get_claim
    from hkproof.proof.status import Status
    from tests.test_poisson import sympy_check
    c = get_claim("atlas-zhukovsky-volterra-1-liouville-arnold")
    cert = c.prove()
    assert cert.status is Status.VERIFIED
    matrices = [s["matrix"] for s in cert.checks if s["kind"] == "bivector-invariance"]
    assert len(matrices) == 4
    for m in matrices:
        assert sympy_check("zhukovsky-volterra-1", SimpleNamespace(texts=lambda m=m: m)) == (True, True)
    changed = [row[:] for row in matrices[0]]
    changed[0][1], changed[1][0] = f"2*({changed[0][1]})", f"2*({changed[1][0]})"
    assert sympy_check("zhukovsky-volterra-1", SimpleNamespace(texts=lambda: changed))[0] is False
    assert c.prove({"rank": "4"}).status is Status.REFUTED


def test_a_small_nambu_structure_is_written_out_and_rechecked():
    """The Nambu structure of the Euler top (its matrix small) goes into the file as bivector-invariance, jacobi and
    casimir steps that the checker verifies by substitution into its own map; a changed entry is refuted."""
    d = doc("euler-top", 1)
    nambu = [s for s in d["steps"] if s.get("bivector") == "Nambu1" or s.get("name") == "Nambu1"
             or s.get("bivectors") == ["Nambu1"]]
    assert [s["kind"] for s in nambu] == ["bivector-invariance", "jacobi", "casimir"]
    assert verdict(d) == "verified"
    m = nambu[0]["matrix"]
    m[0][2], m[2][0] = f"({m[0][2]}) + x1", f"-({m[0][2]}) - x1"      # antisymmetric still, not invariant
    assert verdict(d) == "refuted"


def test_a_nambu_step_is_checked_on_proven_integrals_and_a_proven_density():
    """A Nambu structure too large to write out goes into the file as a darboux step (its density, K = det Df) and a
    nambu step (version 10): the checker draws the construction from what the steps before it proved, and
    refuses it on an integral that is not proven, a 'density' that is an integral, or a point of dependent gradients."""
    import dataclasses
    from hkproof.hk.nambu import bivector_steps
    from hkproof.proof.export import document, substitution_step
    f = kahan_map("euler-top")
    structure = dataclasses.replace(with_integrals(f, 1).nambu[0], bivector=None)       # as if it were too large
    steps = [substitution_step(f.field, n, h) for n, h in [*structure.casimirs, *structure.hamiltonians]]
    d = json.loads(json.dumps(document("t", "s", steps + bivector_steps(f.field, structure, "N"))))
    assert [s["kind"] for s in d["steps"]][-2:] == ["darboux", "nambu"] and verdict(d) == "verified"
    nambu = kind(d, "nambu")
    for key, value in (("casimirs", ["I9"]), ("casimirs", ["I1", "I1"]), ("density", "I2"),
                       ("point", {**nambu["point"], "x1": "0", "x2": "0", "x3": "0"})):
        bad = copy.deepcopy(d)
        kind(bad, "nambu")[key] = value
        assert verdict(bad) == "malformed", (key, value)
    old = copy.deepcopy(d)
    old["version"] = 9
    assert "feature of version" in check_document(old).lines[-1]


@pytest.mark.parametrize("written_out", [True, False])
def test_nambu_file_steps_hold_in_a_random_affine_chart(written_out):
    """Metamorphic: the Euler top's integrals and density carried to a random affine chart y = T x + c (I o C^-1,
    P o C^-1 over its constant denominator) make a Nambu structure there that the checker verifies from its own map
    of the transformed field, written out (bivector steps) or as a darboux and a nambu step; a density off by a
    constant term is refuted at its darboux step."""
    import dataclasses
    import random

    from hkproof.dynamics.catalogue import get_system
    from hkproof.hk.affine_chart import _substitution, random_change, transformed
    from hkproof.hk.nambu import bivector_steps, prove_nambu
    from hkproof.proof.export import document, substitution_step
    from hkproof.proof.status import Status
    base = with_integrals(kahan_map("euler-top"), 1).nambu[0]
    change = random_change(3, random.Random(5), "affine")
    field = transformed(get_system("euler-top"), change, "euler-top-affine")
    f = kahan_map(field)
    moved = _substitution(f.ring, change.inverse_images(field))
    integrals = [(n, moved.apply(h.to_ring(f.ring)), Status.VERIFIED) for n, h in [*base.casimirs, *base.hamiltonians]]
    density = moved.apply(Frac(f.ring, base.density_poly.project_to_context(f.ring.ctx))).num
    structure = prove_nambu(f, integrals, ("P", density, Status.VERIFIED))
    assert structure.status is Status.VERIFIED and structure.rank == 2
    if not written_out:
        structure = dataclasses.replace(structure, bivector=None)
    steps = [substitution_step(field, n, h) for n, h, _ in integrals] + bivector_steps(field, structure, "N")
    d = json.loads(json.dumps(document("t", "s", steps)))
    assert [s["kind"] for s in d["steps"]][2:] == (["bivector-invariance", "jacobi", "casimir"] if written_out
                                                   else ["darboux", "nambu"])
    assert verdict(d) == "verified"
    if not written_out:
        wrong = copy.deepcopy(d)
        kind(wrong, "darboux")["polynomials"] = [f"({kind(d, 'darboux')['polynomials'][0]}) + 1"]
        assert verdict(wrong) == "refuted"


def test_the_checker_expands_the_universal_nambu_identities_itself(monkeypatch):
    """The identities behind a nambu step hold in the checker's own rings for n = 3 ... 6 (about 1 s), and a sign
    error in its W (the dual of dI_1 ^ ... ^ dI_(n-2)) makes them fail, so the nambu step is not accepted."""
    from hkproof.checker import bivectors
    assert all(bivectors._nambu_identities(n) for n in (3, 4, 5, 6))
    right = bivectors._dual

    def unsigned(rows):     # the minors without their signs (-1)^(i + j - 1), still antisymmetric
        return [[e * (1 - 2 * ((i + j + 1) % 2)) for j, e in enumerate(row)] for i, row in enumerate(right(rows))]
    monkeypatch.setattr(bivectors, "_dual", unsigned)
    bivectors._nambu_identities.cache_clear()
    try:
        assert not any(bivectors._nambu_identities(n) for n in (3, 4, 5))
    finally:
        monkeypatch.undo()
        bivectors._nambu_identities.cache_clear()


@pytest.mark.slow           # about 40 s: the poisson run and the checker's substitutions and det Df
def test_the_gaudin_nambu_structure_is_rechecked_as_a_nambu_step():
    d = doc("gaudin-2", 1)
    assert [s["kind"] for s in d["steps"]][:6] == ["substitution"] * 4 + ["darboux", "nambu"]
    assert verdict(d) == "verified"
