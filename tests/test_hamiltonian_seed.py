"""F = J grad H found from the field alone (hk.hamiltonian_structure), the modified Hamiltonian seeded into discover
and proven by substitution (pipelines.discover.hamiltonian_seed), and bases confirmed mod p when exact heights
explode (pipelines.discover.bases.confirm_basis)."""
from __future__ import annotations

import json
import random
from pathlib import Path

import flint
import pytest

from hkproof.algebra.fraction import Frac
from hkproof.checker import check_document
from hkproof.pipelines.discover.certificate import discover_document
from hkproof.dynamics.catalogue import get_system, kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.experiments.scene import make_scene
from hkproof.hk.certified_integrals import certify, independent_subset, jacobian_points
from hkproof.hk.flow_integrals import continuous_integral_circuits
from hkproof.hk.hamiltonian_structure import hamiltonian_structure, invariant_poisson_matrices
from hkproof.hk.integrals import lie_derivative
from hkproof.hk.modified_hamiltonian import modified_hamiltonian
from hkproof.pipelines.discover import run
from hkproof.pipelines.discover.bases import confirm_basis
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.hamiltonian_seed import KIND, seed_modified_hamiltonian
from hkproof.pipelines.discover.report import DiscoveryReport
from hkproof.pipelines.stages import Stages
from hkproof.proof.status import Status

EXAMPLES = Path(__file__).resolve().parent.parent / "docs" / "examples"
KDV = EXAMPLES / "henon-heiles-kdv.toml"
CUBIC_3D = EXAMPLES / "cubic-hamiltonian-3d.toml"
CUBIC_5D = EXAMPLES / "cubic-hamiltonian-5d.toml"
KDV_H = "(p1**2 + p2**2)/2 + (q1**2 + q2**2)/2 + q1**2*q2 + 2*q2**3"       # the printed H: checked below


def _generates(field: QuadraticField, j: list[list[Frac]], h: Frac) -> bool:
    """J grad H == F, recomputed here entry by entry."""
    grad = [h.derivative(v) for v in field.variables]
    return all(sum((a * g for a, g in zip(row, grad, strict=True)), Frac(field.ring, 0)) == f
               for row, f in zip(j, field.rhs, strict=True))


def _is_skew_constant(field: QuadraticField, j: list[list[Frac]]) -> bool:
    return all(e == -j[b][a] and not (e.variables() & set(field.variables)) for a, row in enumerate(j)
               for b, e in enumerate(row))


def test_the_kdv_case_is_hamiltonian_and_integrable_for_the_flow():
    """The field of the file: the printed H has Lie derivative 0 exactly, the flow has two independent polynomial
    integrals of degree <= 4 (the KdV case; the ordinary Henon-Heiles field has one), and the structure found from
    the field alone generates it."""
    field = QuadraticField.from_toml(KDV)
    kmap = kahan_map(field)
    assert lie_derivative(field, Frac.parse(field.ring, KDV_H)).is_zero()
    assert not lie_derivative(field, Frac.parse(field.ring, KDV_H.replace("2*q2**3", "q2**3"))).is_zero()
    flow = continuous_integral_circuits(kmap, 4, random.Random(1))
    assert len(independent_subset(flow, list(field.variables), jacobian_points(kmap.ring.names))) == 2
    ordinary = kahan_map(QuadraticField.from_toml(EXAMPLES / "henon-heiles.toml"))
    assert len(continuous_integral_circuits(ordinary, 4, random.Random(1))) == 1
    found = hamiltonian_structure(field)
    assert found is not None
    j, h = found
    assert _is_skew_constant(field, j) and _generates(field, j, h)
    assert h == Frac.parse(field.ring, KDV_H)       # J is normalized to the canonical one: H is the printed H


@pytest.mark.parametrize("path, rank", [(CUBIC_3D, 2), (CUBIC_5D, 4)])
def test_odd_dimensions_give_a_degenerate_structure(path, rank):
    field = QuadraticField.from_toml(path)
    found = hamiltonian_structure(field)
    assert found is not None
    j, h = found
    assert _is_skew_constant(field, j) and _generates(field, j, h) and h.degrees_in(field.variables)[0] == 3
    assert flint.fmpq_mat([[e.constant_value() for e in row] for row in j]).rank() == rank


def test_parameters_stay_symbolic():
    field = QuadraticField("param", ("q", "p"), ("a", "b"), ("a*p", "-b*q - q**2"))
    j, h = hamiltonian_structure(field)
    assert _generates(field, j, h) and "a" in str(j) + str(h)


@pytest.mark.parametrize("field", [
    get_system("euler-top"),                         # a Lie-Poisson structure, linear in x: no constant J
    get_system("lotka-volterra"),
    # J = e1 ^ e2 is preserved (L_F J = 0) but x3' = x3^2 leaves its leaves x3 = const: Poisson, not Hamiltonian
    QuadraticField("poisson-only", ("x1", "x2", "x3"), (), ("0", "0", "x3**2")),
    QuadraticField("dissipative", ("q", "p"), (), ("p", "-q - p + q**2")),
])
def test_non_hamiltonian_fields_give_none(field):
    assert hamiltonian_structure(field) is None


def test_poisson_only_field_has_an_invariant_j_but_no_hamiltonian():
    """The case where L_F J = 0 is not enough, which is why H is solved for and checked."""
    field = QuadraticField("poisson-only", ("x1", "x2", "x3"), (), ("0", "0", "x3**2"))
    assert len(invariant_poisson_matrices(field)) == 1 and hamiltonian_structure(field) is None


def _seeded(path: Path) -> tuple[DiscoveryReport, list[str], dict[str, float]]:
    """The seed on the field of a file: the report, the progress messages, the stage times."""
    field = QuadraticField.from_toml(path)
    said: list[str] = []
    ctx = SearchContext.for_maps(kahan_map(field), stages=Stages("discover", said.append))
    report = DiscoveryReport(field.name, list(field.variables), [], 2)
    seed_modified_hamiltonian(ctx, report)
    ctx.stages.stop()
    return report, said, ctx.stages.seconds


@pytest.mark.parametrize("path", [KDV, CUBIC_3D])
def test_the_seed_proves_the_modified_hamiltonian(path):
    report, said, stages = _seeded(path)
    [found] = report.integrals
    assert list(stages) == [KIND]
    assert found.status is Status.VERIFIED and found.kind == KIND
    assert found.method.startswith("modified Hamiltonian of H = ") and "Celledoni" in found.method
    assert found.method.endswith("proven by substitution") and "J = [[" in found.method
    assert any("modified Hamiltonian is verified" in line for line in said)
    kmap = kahan_map(QuadraticField.from_toml(path))
    assert certify(kmap, found.frac).status is Status.VERIFIED        # again, independently of the seed
    assert not lie_derivative(kmap.field, found.frac).is_zero()       # H~ is not the flow's H: it has eps terms
    doc = json.loads(json.dumps(discover_document(report)))
    assert check_document(doc).verdict == "verified"
    doc["steps"][0]["integrals"][0]["formula"] += " + eps**2*" + kmap.variables[0]
    assert check_document(doc).verdict == "refuted"


def test_a_perturbed_modified_hamiltonian_is_refuted():
    field = QuadraticField.from_toml(KDV)
    kmap = kahan_map(field)
    j, h = hamiltonian_structure(field)
    assert certify(kmap, modified_hamiltonian(kmap, h)).status is Status.VERIFIED
    assert certify(kmap, modified_hamiltonian(kmap, h) + Frac.parse(kmap.ring, "eps**2*q1*p1")).status \
        is Status.REFUTED
    assert certify(kmap, modified_hamiltonian(kmap, h + Frac.parse(kmap.ring, "q1**3"))).status is Status.REFUTED


def test_a_field_without_the_structure_seeds_nothing():
    field = get_system("euler-top")
    said: list[str] = []
    ctx = SearchContext.for_maps(kahan_map(field), stages=Stages("discover", said.append))
    report = DiscoveryReport(field.name, list(field.variables), list(field.parameters), 2)
    seed_modified_hamiltonian(ctx, report)
    assert report.integrals == [] and "no constant skew J" in said[-1]


@pytest.mark.slow
def test_the_seed_proves_the_five_dimensional_modified_hamiltonian():
    report, _, _ = _seeded(CUBIC_5D)
    [found] = report.integrals
    assert found.status is Status.VERIFIED and (len(found.frac.num), len(found.frac.den)) == (288, 84)


def test_a_basis_is_confirmed_mod_p_when_exact_heights_explode():
    """The basis of H~ on the KdV-case map: the exact orbit's heights grow exponentially, so the third point is mod p
    too and the status is evidence with a text that says so; a non-basis is not confirmed."""
    field = QuadraticField.from_toml(KDV)
    kmap = kahan_map(field)
    scene = make_scene(kmap, {"eps": 2})
    basis = [Frac.parse(kmap.ring, t) for t in (
        "q1**4, q1**2*q2**2, q1**2*p1**2, q1**2*p2**2, q2**4, q2**2*p1**2, q2**2*p2**2, q1**2*q2, q1*p1*p2, q2**3, "
        "q2*p1**2, q2*p2**2, q1**2, q2**2, p1**2, p2**2, q2, 1").split(", ")]
    entry = confirm_basis(scene, basis)
    assert entry["status"] == Status.EVIDENCE_EXACT.label and entry["dimension"] == 1
    assert entry["check"].startswith("algorithm (N) mod p only: an HK-basis at 3 of 3 points")
    assert "from above" in entry["check"] and "grow exponentially" in entry["check"]
    wrong = confirm_basis(scene, basis[1:])
    assert wrong["status"] == Status.UNKNOWN.label and wrong["dimension"] is None


def test_discover_with_the_seed_first_proves_what_the_search_alone_does_not_see():
    """The seed runs at the start of the search: on the KdV-case map at degree 2 the search alone finds no kernel,
    with the seed H~ is proven, independent, and in the report."""
    field = QuadraticField.from_toml(KDV)
    assert run.discover(field, 2, hamiltonian=False).verified == []
    report = run.discover(field, 2)
    [found] = report.verified
    assert found.kind == KIND and found.independent and found.status is Status.VERIFIED
    assert KIND in report.stages and "modified Hamiltonian" in report.text()
