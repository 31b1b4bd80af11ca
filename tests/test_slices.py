"""Parameter translations found in the field (hkproof.hk.translation.field_translations), discover's search on their
slice and the lift of what it finds (hkproof.pipelines.slices), and the certificate step that carries the
slice's integrals to the whole field (kind "reparametrization", version 5). Each piece is checked against sympy or
refused when its data is perturbed."""
from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest
import sympy

from hkproof.checker import check_document
from hkproof.pipelines.discover.certificate import discover_document
from hkproof.dynamics.catalogue import SYSTEMS, get_system
from hkproof.dynamics.field import QuadraticField
from hkproof.hk.translation import field_translations
from hkproof.pipelines.discover import discover
from hkproof.proof.status import Status
from hkproof.proof.export import VERSION
from tests.sympy_bridge import constant_along_sympy_orbit

SCHEMA = Path(__file__).resolve().parents[1] / "docs" / "certificate.schema.json"


def _invariant_by_sympy(field: QuadraticField, shift) -> bool:
    """F(a + c velocity) == F(a), with the right-hand sides read by sympy from their printed text."""
    c = sympy.Symbol("c_shift")
    moves = {sympy.Symbol(n): sympy.Symbol(n) + c for n in shift.names}
    moves.update({sympy.Symbol(v): sympy.Symbol(v) + sympy.Rational(t) * c for v, t in shift.velocity})
    return all(sympy.simplify(sympy.sympify(str(f)).xreplace(moves) - sympy.sympify(str(f))) == 0 for f in field.rhs)


@pytest.mark.parametrize("system, pivots", [("so4-euler-top", ["a4"]), ("clebsch", ["w3"]),
                                            ("zhukovsky-volterra-1", ["a3"]), ("clebsch-general", ["w3", "b3"]),
                                            ("euler-top", []), ("so4-euler-top-flow2", []), ("lotka-volterra", [])])
def test_translations_of_the_catalogue(system, pivots):
    """The pivots of the translations found (one slice after the other); fields without one get none."""
    assert [s.pivot for s in field_translations(get_system(system))] == pivots


def test_a_translation_with_another_velocity_and_none_without_a_unit_entry():
    """F depending on a - 2 b only: the direction (2, 1) has the unit entry at b (a moves with velocity 2); on
    a + b and 2 a - 3 b jointly there is no translation at all."""
    field = QuadraticField("t", ("x", "y"), ("a", "b"), ("(a - 2*b)*x*y", "x**2 - (a - 2*b)*y"))
    (shift,) = field_translations(field)
    assert shift.pivot == "b" and dict(shift.velocity) == {"a": "2"} and _invariant_by_sympy(field, shift)
    none = QuadraticField("u", ("x", "y"), ("a", "b"), ("(a + b)*x*y", "(2*a - 3*b)*y**2"))
    assert field_translations(none) == []


@pytest.fixture(scope="module")
def gyrostat():
    return discover("zhukovsky-volterra-1")


def test_discover_lifts_the_slice_integrals_to_every_parameter(gyrostat):
    """zhukovsky-volterra-1 is searched at a3 = 0; both integrals come back with a3 symbolic, verified, and are
    constant along an orbit sympy computes from the printed field (a3 != 0)."""
    report = gyrostat
    assert report.on_slice is not None and [s.pivot for s in report.on_slice.shifts] == ["a3"]
    lifted = [i for i in report.integrals if i.independent]
    assert len(lifted) == 2 and all(i.status is Status.VERIFIED for i in lifted)
    assert all("a3" in i.frac.variables() and "a3" not in i.searched.variables() for i in lifted)
    assert all(any(s.name == "lifted from the slice" for s in i.certificate.steps) for i in lifted)
    assert constant_along_sympy_orbit(get_system("zhukovsky-volterra-1"), lifted) == []


@pytest.fixture(scope="module")
def gyrostat_doc(gyrostat) -> dict:
    return json.loads(json.dumps(discover_document(gyrostat)))


def test_the_reparametrization_certificate_verifies(gyrostat_doc):
    doc = gyrostat_doc
    last = doc["steps"][-1]
    assert doc["version"] == VERSION and last["kind"] == "reparametrization" and last["source"] != last["field"]
    assert last["parameters"] == {"a1": "a1 - a3", "a2": "a2 - a3", "b1": "b1"}
    assert [c["name"] for c in doc["claim"]["integrals"]] == [e["name"] for e in last["integrals"]] == ["I1", "I2"]
    assert {c["field"] for c in doc["claim"]["integrals"]} == {last["field"]}
    assert [e["from"] for e in last["integrals"]] == ["I1_slice", "I2_slice"]
    assert check_document(doc).verdict == "verified"


def _mutated(doc: dict, change) -> dict:
    out = copy.deepcopy(doc)
    change(out)
    return out


def _image(name: str, text: str):
    return lambda d: d["steps"][-1]["parameters"].__setitem__(name, text)


@pytest.mark.parametrize("change, verdict", [
    (_image("a1", "a1 + a3"), "refuted"),                       # does not carry the slice's field to the field
    (_image("a1", "a2 - a3"), "malformed"),                     # images not independent (a1, a2 -> the same)
    (_image("a1", "1/(a1 - a3)"), "malformed"),                 # not a polynomial
    (_image("a1", "x1 + a1 - a3"), "malformed"),                # moves a phase variable
    (lambda d: d["steps"][-1]["parameters"].pop("b1"), "malformed"),
    (lambda d: d["steps"][-1].__setitem__("source", d["steps"][-1]["field"]), "malformed"),
    (lambda d: d["steps"][-1]["integrals"][0].__setitem__(
        "formula", "2*" + d["steps"][-1]["integrals"][0]["formula"]), "refuted"),
])
def test_every_reparametrization_mutation_is_refused(gyrostat_doc, change, verdict):
    assert check_document(_mutated(gyrostat_doc, change)).verdict == verdict


def test_version_5_documents_follow_the_schema(gyrostat_doc):
    jsonschema = pytest.importorskip("jsonschema")
    schema = json.loads(SCHEMA.read_text())
    jsonschema.validate(gyrostat_doc, schema)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(_mutated(gyrostat_doc, lambda d: d["steps"][-1].pop("source")), schema)


def test_every_catalogue_field_with_a_translation_is_invariant_under_it():
    """The whole catalogue: each translation found is an exact symmetry of its field, by sympy."""
    for name, field in SYSTEMS.items():
        for shift in field_translations(field):
            assert _invariant_by_sympy(field, shift), name
            field = field.specialize({shift.pivot: 0})


def test_a_conclusion_without_formula_is_sigma_of_its_source(gyrostat_doc):
    """hkproof leaves out a lifted formula longer than a formula may be (so(4): 5 million characters); the conclusion
    is then sigma(from), and the file still checks and follows the schema."""
    short = _mutated(gyrostat_doc, lambda d: [e.pop("formula") for e in d["steps"][-1]["integrals"]])
    assert check_document(short).verdict == "verified"
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.validate(short, json.loads(SCHEMA.read_text()))


def test_the_gyrostat_with_two_moments_is_proven_on_its_slice():
    """docs/examples/zhukovsky-volterra-2.toml: the one integral its quadratic kernel carries, found at a3 = 0 and
    lifted (five parameters symbolic), is constant along a sympy orbit of the printed field."""
    path = Path(__file__).resolve().parents[1] / "docs" / "examples" / "zhukovsky-volterra-2.toml"
    field = QuadraticField.from_toml(path)
    report = discover(field)
    proven = [i for i in report.integrals if i.independent]
    assert len(proven) == 1 == report.expected_independent and proven[0].status is Status.VERIFIED
    assert {"a1", "a2", "a3", "b1", "b2"} <= proven[0].frac.variables()
    assert constant_along_sympy_orbit(field, proven) == []


@pytest.mark.slow
def test_so4_in_m_is_proven_on_its_slice():
    """so4-euler-top in the coordinates m_ij, no input beyond the field: 4 of 4 independent integrals with a1..a4
    symbolic (searched at a4 = 0, lifted; about 3 minutes), each constant along a sympy orbit of the printed field."""
    report = discover("so4-euler-top")
    proven = [i for i in report.integrals if i.independent]
    assert len(proven) == 4 and all(i.status is Status.VERIFIED for i in proven)
    assert all("a4" in i.frac.variables() for i in proven if i.frac.variables() & {"a1", "a2", "a3"})
    assert constant_along_sympy_orbit(get_system("so4-euler-top"), proven) == []


def test_measure_searches_the_slice_and_its_lifts_are_darboux_polynomials_of_the_whole_map():
    """measure on zhukovsky-volterra-1 runs at a3 = 0 and lifts: every Darboux polynomial, with its lifted cofactor,
    satisfies P o f = K P on the whole map (a3 symbolic), checked there again from scratch; the certificate of the
    lifted search verifies on the whole field; a polynomial lifted wrongly (a3 -> a3 + 1) is refuted."""
    from hkproof.algebra.fraction import Frac
    from hkproof.commands._certificates import measure_document
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.hk.darboux import check_darboux
    from hkproof.pipelines.darboux import search_darboux
    kmap = kahan_map("zhukovsky-volterra-1")
    found = search_darboux(kmap, 2)
    assert found.on_slice and found.darboux and all(d.status is Status.VERIFIED for d in found.darboux)
    assert all("a3" in Frac(kmap.ring, d.poly).variables() for d in found.darboux)
    for d in found.darboux:
        assert check_darboux(kmap, found.atoms, d.cofactor, d.poly)[0] is Status.VERIFIED
    wrong = kmap.ring.substitute(found.darboux[0].poly, {"a3": kmap.ring.gen("a3") + 1})
    assert check_darboux(kmap, found.atoms, found.darboux[0].cofactor, wrong)[0] is Status.REFUTED
    assert check_document(json.loads(json.dumps(measure_document(kmap, found)))).verdict == "verified"
