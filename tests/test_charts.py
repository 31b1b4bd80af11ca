"""Affine changes of coordinates (hk.affine_chart, hk.normal_form, pipelines.charts): `discover` proves as many
independent integrals in a random affine chart as in the catalogue's, each integral constant along an orbit sympy
computes from the printed field, and the `affine-change` step of the certificate is checked (and refutes a mutation)."""
from __future__ import annotations

import json
import random

import pytest

from hkproof.checker import check_document
from hkproof.pipelines.discover.certificate import discover_document
from hkproof.dynamics.catalogue import get_system
from hkproof.dynamics.field import QuadraticField
from hkproof.errors import HKProofError
from hkproof.hk.affine_chart import AffineChange, field_mismatches, random_change, transformed
from hkproof.hk.normal_form import field_size, homogenizing_translation, normal_form
from hkproof.pipelines.discover import discover
from tests.sympy_bridge import constant_along_sympy_orbit

_COUNTS: dict[str, int] = {}


def _catalogue_count(name: str) -> int:
    """The independent proven integrals in the catalogue's chart (computed, not written down)."""
    if name not in _COUNTS:
        _COUNTS[name] = discover(name, 2).independent
    return _COUNTS[name]


def _in_chart(name: str, kind: str, seed: int) -> QuadraticField:
    field = get_system(name)
    change = random_change(len(field.variables), random.Random(seed), kind)
    return transformed(field, change, f"{name}-{kind}-{seed}")


def test_transformed_field_satisfies_the_identity_and_a_mutation_does_not():
    field = get_system("euler-top")
    change = random_change(3, random.Random(5), "affine")
    moved = transformed(field, change)
    assert field_mismatches(field, moved, change) == []
    bad = AffineChange(change.matrix, ("1",) + change.shift[1:])
    assert field_mismatches(field, moved, bad) != []
    with pytest.raises(HKProofError, match="singular"):
        transformed(field, AffineChange((("1", "1", "0"), ("1", "1", "0"), ("0", "0", "1")), ("0", "0", "0")))
    with pytest.raises(HKProofError, match="constant along the flow"):
        AffineChange.translation(("x1", "0", "0")).entries(field)


def test_homogenizing_translation_is_exact_with_symbolic_parameters():
    """x -> x + (a, 0, 0): the linear part vanishes again at x0 = (-a, 0, 0), solved with a symbolic."""
    field = get_system("euler-top")
    moved = transformed(field, AffineChange.translation(("a1", "0", "0")))
    shift = homogenizing_translation(moved)
    assert shift is not None
    back = transformed(moved, AffineChange.translation(shift))
    assert [str(f) for f in back.rhs] == [str(f) for f in field.rhs]
    assert homogenizing_translation(field) is None


def test_catalogue_charts_are_kept():
    for name in ("euler-top", "lotka-volterra", "volterra-4", "gaudin-2"):
        assert normal_form(get_system(name)) is None


def test_translated_euler_top_two_of_two_with_a_certificate_the_checker_verifies():
    field = _in_chart("euler-top", "translation", 3)
    report = discover(field, 2)
    assert report.chart is not None and report.independent == 2
    assert constant_along_sympy_orbit(field, report.verified) == []
    doc = json.loads(json.dumps(discover_document(report)))
    assert doc["steps"][-1]["kind"] == "affine-change"
    assert check_document(doc).verdict == "verified"
    for mutate in (lambda s: s["shift"].__setitem__(0, str(int(s["shift"][0]) + 1)),
                   lambda s: s["matrix"][0].__setitem__(1, "1")):
        bad = json.loads(json.dumps(doc))
        mutate(bad["steps"][-1])
        assert check_document(bad).verdict == "refuted"
    singular = json.loads(json.dumps(doc))
    singular["steps"][-1]["matrix"] = [["0"] * 3] * 3
    assert check_document(singular).verdict == "malformed"


@pytest.mark.parametrize("name, kind, seed", [
    ("euler-top", "dense", 1), ("euler-top", "affine", 2), ("zhukovsky-volterra-1", "dense", 1),
    ("zhukovsky-volterra-1", "signed-permutation", 4), ("volterra-4", "signed-permutation", 2),
    ("volterra-3", "signed-permutation", 1), ("gaudin-2", "dense", 1)])
def test_same_count_in_a_random_chart(name, kind, seed):
    """Metamorphic: a random affine change does not change the number of independent integrals proven."""
    field = _in_chart(name, kind, seed)
    report = discover(field, 2)
    assert report.independent == _catalogue_count(name)
    assert constant_along_sympy_orbit(field, report.verified) == []


@pytest.mark.slow
@pytest.mark.parametrize("name", ["euler-top", "clebsch", "zhukovsky-volterra-1", "gaudin-2", "lagrange-top",
                                  "kirchhoff", "volterra-4", "toda-3", "so4-euler-top-split"])
@pytest.mark.parametrize("kind", ["dense", "signed-permutation", "translation", "affine"])
def test_same_count_in_every_kind_of_chart(name, kind):
    field = _in_chart(name, kind, 7)
    assert discover(field, 2).independent == _catalogue_count(name)


def test_normal_form_is_sparser_and_can_be_switched_off():
    field = _in_chart("euler-top", "dense", 1)
    change, searched = normal_form(field)
    assert field_size(searched) < field_size(field) and field_mismatches(field, searched, change) == []
    assert discover(field, 2, charts=False).chart is None


def test_centring_translation_and_diagonal_scaling_recover_the_catalogue_size():
    """A field with a linear part of its own (Gaudin: b s2 in s1') translated, and a field stretched along its axes:
    the normal form is as short as the catalogue's field (up to signs)."""
    gaudin = get_system("gaudin-2")
    moved = _in_chart("gaudin-2", "translation", 7)
    change, searched = normal_form(moved)
    assert change.is_translation() and field_size(searched) == field_size(gaudin)
    stretched = transformed(get_system("euler-top"), AffineChange((("2", "0", "0"), ("0", "3", "0"), ("0", "0", "-5")),
                                                                  ("0", "0", "0")))
    _, searched = normal_form(stretched)
    assert field_size(searched) <= field_size(get_system("euler-top")) + 3


def test_scaling_derivations_find_the_weights_and_the_centre_in_any_chart():
    """The Lagrange top is weighted-homogeneous (m of weight 1, p of weight 2): the derivation with c = 1 has these
    eigenvalues in a dense affine chart too, its centre is the translation back, and a field whose constant term
    breaks every scaling has no centre."""
    from hkproof.hk.scaling_derivations import scaling_centre, scaling_derivations
    lagrange = get_system("lagrange-top")
    change = random_change(6, random.Random(7), "affine")
    field = transformed(lagrange, change)
    scaled = [d for d in scaling_derivations(field) if d.time != 0]
    assert scaled
    roots = {str(r) for d in scaled for r, _ in d.linear.charpoly().roots()}
    assert roots >= {str(1 * scaled[0].time), str(2 * scaled[0].time)}
    shift = scaling_centre(field)
    assert shift is not None
    centred = transformed(field, AffineChange.translation(shift))
    linear_only = transformed(lagrange, AffineChange(change.matrix, ("0",) * 6))
    assert [str(f) for f in centred.rhs] == [str(f) for f in linear_only.rhs]
    broken = QuadraticField("broken", field.variables, field.parameters,
                            (field.rhs_text[0] + " + 1",) + field.rhs_text[1:], "")
    assert scaling_centre(broken) is None


@pytest.mark.parametrize("name, kind", [("lagrange-top", "dense"), ("lagrange-top", "affine"),
                                        ("kirchhoff", "dense"), ("kirchhoff", "affine"), ("clebsch", "dense"),
                                        ("so4-euler-top", "affine")])
def test_dense_charts_of_the_tops_are_undone(name, kind):
    """The frames from the field's weights (Lagrange: m from p), its trace form (Kirchhoff: equal weights), the
    pencils restricted to a block (Clebsch) and the forms vanishing on one block (so(4): the integrals span every
    form on each 2-dimensional block) bring a dense chart back to the catalogue's size (up to signs and order)."""
    field = _in_chart(name, kind, 7)
    found = normal_form(field)
    assert found is not None
    change, searched = found
    assert field_mismatches(field, searched, change) == []
    assert field_size(searched) <= field_size(get_system(name)) + 3
