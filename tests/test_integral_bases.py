"""discover's last stage: bases of monomials and integrals of the continuous flow, solved together
(hkproof.pipelines.discover.integral_bases). Every piece is checked against an independent computation or shown to
fail when its input is perturbed."""
from __future__ import annotations

import random

import pytest
import sympy

from hkproof.algebra.fraction import Frac
from hkproof.algebra.monomials import exponents_upto
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.block_system import BlockSystem, verify_candidate
from hkproof.hk.independence import sample_point
from hkproof.pipelines.discover import discover
from hkproof.pipelines.discover.context import SearchContext
from hkproof.hk.flow_integrals import continuous_integral_circuits
from hkproof.pipelines.discover.group_coordinates import lift_group_relations
from hkproof.pipelines.discover.groups import find_group, integral_bases
from hkproof.pipelines.discover.integral_bases import prove_group
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status
from tests.sympy_bridge import constant_along_sympy_orbit

SPLIT = "so4-euler-top-split"


@pytest.fixture(scope="module")
def split_ctx() -> SearchContext:
    return SearchContext.for_maps(kahan_map(SPLIT))


@pytest.fixture(scope="module")
def circuits(split_ctx):
    return continuous_integral_circuits(split_ctx.kmap, 2, random.Random(1))


def _quadratic_support() -> list:
    """The monomials the degree-2 kernel of the split so(4) map involves: the six squares, u_k v_k and 1."""
    return [e for e in exponents_upto(6, 2)
            if sum(e) == 0 or (sum(e) == 2 and (max(e) == 2 or any(e[k] and e[k + 3] for k in range(3))))]


def test_circuits_are_integrals_of_the_flow_by_sympy(split_ctx, circuits):
    """Each circuit has zero Lie derivative along the printed field (sympy), and none is a multiple of another."""
    field = split_ctx.kmap.field
    xs = sympy.symbols(field.variables)
    rhs = [sympy.sympify(str(c)) for c in field.rhs]
    assert len(circuits) >= 4
    for c in circuits:
        expr = sympy.sympify(str(c))
        assert sympy.expand(sum(sympy.diff(expr, x) * f for x, f in zip(xs, rhs))) == 0
    supports = {frozenset(m[:6] for m in c.num.monoms()) for c in circuits}
    assert len(supports) == len(circuits)


def test_a_field_without_polynomial_integrals_has_no_circuits():
    ctx = SearchContext.for_maps(kahan_map("lotka-volterra"))
    assert continuous_integral_circuits(ctx.kmap, 2, random.Random(1)) == []


@pytest.fixture(scope="module")
def first_group(split_ctx, circuits):
    """With no integral known, the smallest group: the basis (u1 v1, u2 v2, 1, I3) alone (I3 the continuous energy)."""
    rng = random.Random(1)
    bases = integral_bases(split_ctx, _quadratic_support(), circuits, [], rng)
    assert bases and all(b.new for b in bases)
    group = find_group(split_ctx, bases, rng)
    assert group is not None
    return group


def test_a_group_is_proven_and_its_coordinates_are_integrals(split_ctx, first_group):
    candidate, cert, _ = prove_group(split_ctx, first_group, random.Random(2))
    assert cert.status is Status.VERIFIED, cert.error
    kmap = split_ctx.kmap

    class Named:
        def __init__(self, k, h):
            self.name, self.frac = f"a{k}", h
    assert constant_along_sympy_orbit(kmap.field, [Named(k, h) for k, h in enumerate(candidate)]) == []


def test_a_perturbed_candidate_is_refuted(split_ctx, first_group):
    """One coefficient changed in one coordinate: the block proof does not call it verified."""
    rng = random.Random(2)
    relations = lift_group_relations(split_ctx, first_group, rng)
    candidate, _, _ = prove_group(split_ctx, first_group, rng)
    ring = split_ctx.kmap.ring
    k = max(range(len(candidate)), key=lambda i: len(candidate[i].num))
    bumped = list(candidate)
    bumped[k] = Frac(ring, candidate[k].num + ring.ctx.from_dict({candidate[k].num.monoms()[0]: 1}),
                     candidate[k].den)
    system = BlockSystem(split_ctx.kmap, tuple(tuple(first_group.order(m)) for m in first_group.members),
                         tuple(relations), (0, 1))
    cert = Certificate("perturbed", "a perturbed candidate", "test", "")
    names = [f"a{i}" for i in range(len(candidate))]
    with pytest.raises(ProofStopped):
        verify_candidate(cert, system, names, bumped, sample_point(ring.names, 3))
    assert cert.status < Status.VERIFIED_SPECIALIZED


@pytest.mark.slow
def test_discover_proves_four_integrals_of_the_split_so4_map():
    """The Liouville count: three integrals from monomial bases, the fourth from three bases with integrals of the
    flow solved together (about 2 minutes); each constant along a sympy orbit."""
    report = discover(SPLIT, 2)
    proven = [i for i in report.integrals if i.status is Status.VERIFIED and i.independent]
    assert len(proven) == 4
    assert any("solved together" in i.method for i in proven)
    assert constant_along_sympy_orbit(kahan_map(SPLIT).field, proven) == []


def test_the_batch_black_box_agrees_with_the_pointwise_kernel(split_ctx, first_group):
    """KernelBlackBox on a basis with an integral of the flow (numpy batches) against recipe (B) point by point."""
    from hkproof.algebra.modular import random_prime
    from hkproof.pipelines.discover.blackbox import KernelBlackBox
    from hkproof.pipelines.discover.symbolic import PRIME_BITS
    from hkproof.pipelines.discover.groups import ModularScene, kernel_vector, normalized
    basis = first_group.order(first_group.members[0])
    ring = split_ctx.kmap.ring
    inputs = list(ring.names)
    rng = random.Random(4)
    p = random_prime(rng, PRIME_BITS)
    points = [[rng.randrange(1, p) for _ in inputs] for _ in range(5)]
    for k in range(len(basis) - 1):
        box = KernelBlackBox(split_ctx.kmap, basis, k, len(basis) - 1, inputs)
        batch = box(p, points)
        for pt, value in zip(points, batch):
            controls = {n: v for n, v in zip(inputs, pt) if n not in split_ctx.kmap.variables}
            x = [v for n, v in zip(inputs, pt) if n in split_ctx.kmap.variables]
            mod = ModularScene(split_ctx, p, controls)
            a = normalized(kernel_vector(mod, basis, mod.map.orbit(x, len(basis) - 2)), len(basis) - 1, p)
            assert value == [(-a[k]) % p]          # the box gives [c_k / c_l] = [-a_k]


def test_the_coordinates_of_one_basis_share_their_kernel_vectors(split_ctx, first_group, monkeypatch):
    """The boxes of one basis's coordinates compute each point's kernel vector once per process (the memo behind
    KernelBlackBox.kernels); a box of another basis, or at another prime, computes its own."""
    from hkproof.algebra.modular import random_prime
    from hkproof.pipelines.discover import blackbox
    from hkproof.pipelines.discover.symbolic import PRIME_BITS
    monkeypatch.setattr(blackbox, "_KERNELS", {})
    computed: list[int] = []
    vectors = blackbox.KernelBlackBox.vectors
    monkeypatch.setattr(blackbox.KernelBlackBox, "vectors",
                        lambda self, p, pts: (computed.append(len(pts)), vectors(self, p, pts))[1])
    basis = first_group.order(first_group.members[0])
    inputs = list(split_ctx.kmap.ring.names)
    rng = random.Random(5)
    p, q = random_prime(rng, PRIME_BITS), random_prime(rng, PRIME_BITS)
    points = [[rng.randrange(1, p) for _ in inputs] for _ in range(4)]
    boxes = [blackbox.KernelBlackBox(split_ctx.kmap, basis, k, len(basis) - 1, inputs) for k in range(len(basis) - 1)]
    first = boxes[0](p, points + points[:2])                      # a repeated point is computed once
    assert computed == [4] and first[4:] == first[:2]
    for box in boxes[1:]:
        box(p, points[1:])
    assert computed == [4]
    boxes[1](q, points)
    other = [basis[1], basis[0], *basis[2:]]                     # another basis (the same functions reordered)
    blackbox.KernelBlackBox(split_ctx.kmap, other, 0, len(other) - 1, inputs)(p, points)
    assert computed == [4, 4, 4]


def test_a_failure_inside_the_stage_is_reported_not_raised(monkeypatch):
    """An unlucky prime inside step 5d ends the stage with a note; the report and the earlier integrals stand."""
    import hkproof.pipelines.discover.run as run
    from hkproof.errors import UnluckyPrimeError
    from hkproof.pipelines.discover.reconstruct import Reconstructed

    def nothing(ctx, report, candidates, target, p, proven=()):
        return Reconstructed(covered="nothing reconstructed (test)")

    def unlucky(*args, **kwargs):
        raise UnluckyPrimeError("det M = 0 mod p at every point tried (test)")
    monkeypatch.setattr(run, "reconstruct_candidates", nothing)
    monkeypatch.setattr(run, "prove_with_integral_bases", unlucky)
    report = discover("euler-top", 2)
    assert report.integrals == []
    assert any("stopped" in c and "det M = 0" in c for c in report.covered)


def test_the_block_proof_is_a_certificate_the_checker_verifies_and_refutes_when_perturbed(split_ctx, first_group):
    """The group's Prop. "prop: even" step (blocks) in a certificate file: `hkproof check` re-verifies it from the
    file alone; one coefficient changed in the solution is refuted; without its relations the rows cannot determine
    the unknowns and the file is malformed."""
    import copy
    import json
    from hkproof.checker import check_document
    from hkproof.proof.export import document
    _, cert, _ = prove_group(split_ctx, first_group, random.Random(2))
    (step,) = [s for s in cert.checks if "blocks" in s]
    doc = json.loads(json.dumps(document("group", "the coordinates are integrals", [], certificates=[cert])))
    assert check_document(doc).verdict == "verified"
    jsonschema = pytest.importorskip("jsonschema")
    from pathlib import Path
    schema = json.loads((Path(__file__).resolve().parents[1] / "docs" / "certificate.schema.json").read_text())
    jsonschema.validate(doc, schema)
    bad = copy.deepcopy(doc)
    k = max(range(len(step["solution"])), key=lambda i: len(step["solution"][i]))
    bad["steps"][-1]["solution"][k] = step["solution"][k].replace("b1", "2*b1", 1)
    assert check_document(bad).verdict == "refuted"
    short = copy.deepcopy(doc)
    short["steps"][-1]["relations"] = []
    assert check_document(short).verdict == "malformed"


@pytest.mark.slow          # a whole discover of so4-euler-top-split (30-40 s)
def test_a_budget_that_runs_out_in_step_5d_says_how_far_it_got(monkeypatch, capsys):
    """The budget running out inside the group's reconstruction is reported with the coordinates already rebuilt
    (here the second reconstruction is stopped: 1 of the group's 14), not only with the stage it stopped in."""
    from hkproof.cli import main
    from hkproof.errors import BudgetExhausted
    from hkproof.pipelines.discover import group_coordinates as ib
    calls: list[int] = []
    honest = ib.reconstruct

    def stopped_at_the_second(*args, **kwargs):
        if kwargs.get("method", "sparse") == "sparse":          # a coordinate (the relations are rebuilt densely)
            calls.append(1)
        if len(calls) == 2:
            raise BudgetExhausted("the time budget of 1 s ran out while testing", limit="1 s", raise_with="more")
        return honest(*args, **kwargs)
    monkeypatch.setattr(ib, "reconstruct", stopped_at_the_second)
    main(["discover", "so4-euler-top-split", "--no-progress"])
    assert "step 5d had reconstructed 1 of the 14 coordinates of the bases (" in capsys.readouterr().out


def test_the_coordinates_of_a_group_rebuilt_side_by_side_on_an_executor_are_those_of_the_plain_loop(split_ctx,
                                                                                                 first_group):
    """With an executor (--jobs) each coordinate is one job in a worker process; the candidate is the same."""
    import concurrent.futures
    import dataclasses

    from hkproof.pipelines.discover.group_coordinates import group_coordinates
    plain = group_coordinates(split_ctx, first_group, random.Random(5))
    with concurrent.futures.ProcessPoolExecutor(max_workers=2) as pool:
        pooled = group_coordinates(dataclasses.replace(split_ctx, mapper=pool.map), first_group, random.Random(5))
    assert len(plain) == len(pooled) >= 2
    assert all(a == b for a, b in zip(plain, pooled))


def test_candidates_whose_proof_the_budget_stopped_are_evidence_at_exact_points_and_a_wrong_one_is_refuted(
        split_ctx, first_group):
    """When the budget stops the block proof (the row check by Horner of a very large candidate), the candidates are
    checked at random exact points: evidence(exact), never verified; a perturbed one is refuted there."""
    from hkproof.hk.block_system import evidence_at_points
    from hkproof.pipelines.discover.group_coordinates import group_coordinates
    candidate = group_coordinates(split_ctx, first_group, random.Random(3))
    names = [f"a{k}" for k in range(len(candidate))]
    cert = evidence_at_points(split_ctx.kmap, names, candidate, random.Random(4), {})
    assert cert.status is Status.EVIDENCE_EXACT and cert.steps[-1].points == 2
    ring = split_ctx.kmap.ring
    bumped = list(candidate)
    bumped[0] = candidate[0] + Frac(ring, ring.gen("u1"))
    assert evidence_at_points(split_ctx.kmap, names, bumped, random.Random(4), {}).status is Status.REFUTED


@pytest.mark.slow          # a whole discover of so4-euler-top-split (30-40 s)
def test_a_block_proof_stopped_by_the_budget_reports_its_integrals_as_evidence(monkeypatch, capsys):
    """discover so4-euler-top-split with the row check i = 1 stopped as by the budget: the group's new integral is
    reported as evidence(exact) with the reason, and counted apart from the proven ones."""
    from hkproof.cli import main
    from hkproof.errors import BudgetExhausted
    from hkproof.hk import block_system
    honest = block_system.row_holds

    def stopped(kmap, basis, target, i, solution):
        if i == 1:
            raise BudgetExhausted("the time budget of 1 s ran out while checking row i = 1 by Horner's scheme",
                                  limit="1 s", raise_with="more")
        return honest(kmap, basis, target, i, solution)
    monkeypatch.setattr(block_system, "row_holds", stopped)
    main(["discover", "so4-euler-top-split", "--no-progress", "--json"])
    import json
    report = json.loads(capsys.readouterr().out)
    evidence = [i for i in report["integrals"] if i["status"] == "evidence(exact)"]
    assert evidence and all("was stopped" in " ".join(i["notes"]) for i in evidence)
    assert all("random exact points" in i["method"] for i in evidence)
    assert any("candidates only checked at random exact points" in c for c in report["covered"])
    assert report["complete"] is False
