"""Plans mod p (hkproof.pipelines.discover.relation_plan): relations l.c = R(K) that make a basis' reduced system
square. The shortcuts of the planner (one pool of points per basis, one subset of knowns where their gradients are
independent) are checked against the exhaustive search they replace, on the split so(4) map."""
from __future__ import annotations

import random

import pytest

from hkproof.algebra.modular import random_prime
from hkproof.dynamics.catalogue import kahan_map
from hkproof.errors import HKProofError
from hkproof.pipelines.discover import relation_plan
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover import sample_pool
from hkproof.pipelines.discover.relation_plan import plan_mod_p
from hkproof.pipelines.discover.sample_pool import SamplePool
from hkproof.pipelines.discover.solve import BasisProof, prove_basis
from hkproof.proof.status import Status

P = 1_000_003
SPLIT = "so4-euler-top-split"
PAIRS = [(1, 0, 0, 1, 0, 0), (0, 1, 0, 0, 1, 0), (0, 0, 1, 0, 0, 1), (0, 0, 0, 0, 0, 0)]     # u_k v_k, 1
SQUARES = [tuple(2 * int(i == k) for i in range(6)) for k in range(6)]


def test_one_subset_where_the_gradients_are_independent() -> None:
    g = [[1, 0, 0, 2], [0, 1, 0, 5], [0, 0, 1, 7]]
    target = [(2 * a + 3 * c) % P for a, c in zip(g[0], g[2])]
    assert relation_plan._subsets_for(g, target, P) == [(0, 2)]
    assert relation_plan._subsets_for(g, [0, 0, 0, 0], P) == [()]          # a constant combination
    assert relation_plan._subsets_for(g, [0, 0, 0, 1], P) == []            # outside the span: no R at all


def test_every_independent_subset_where_the_gradients_are_dependent() -> None:
    g = [[1, 0, 3], [2, 0, 6], [0, 1, 0]]
    assert relation_plan._subsets_for(g, [1, 1, 3], P) == relation_plan._independent_subsets(g, P)


def test_a_pool_serves_one_length_of_orbits() -> None:
    kmap = kahan_map(SPLIT)
    pool = SamplePool(kmap, {}, P, {n: 3 for n in kmap.field.control_names}, random.Random(1), 2)
    with pytest.raises(HKProofError, match="orbits of 2 steps"):
        plan_mod_p(kmap, SQUARES, {}, P, {}, random.Random(1), pool=pool)


@pytest.fixture(scope="module")
def pairs_integral():
    """c_1 / c_4 of the basis (u1 v1, u2 v2, u3 v3, 1), proven whole by constant relations."""
    ctx = SearchContext.for_maps(kahan_map(SPLIT))
    proof = prove_basis(ctx, PAIRS, {}, random.Random(3))
    assert isinstance(proof, BasisProof) and proof.status == Status.VERIFIED
    return ctx, {"I1": proof.coordinates[0] / proof.coordinate(PAIRS[-1])}


def _plans(ctx: SearchContext, known: dict, shared: bool) -> list[tuple[int, bool]]:
    rng = random.Random(5)
    p = random_prime(rng, 50)
    controls = {n: rng.randrange(1, p) for n in ctx.kmap.field.control_names} | \
        {n: 1 for n in ctx.weights.normalized}
    pool = SamplePool(ctx.kmap, known, p, controls, rng, len(SQUARES) - 2) if shared else None
    out = []
    for last in range(len(SQUARES)):
        order = [e for k, e in enumerate(SQUARES) if k != last] + [SQUARES[last]]
        plan = plan_mod_p(ctx.kmap, order, known, p, controls, rng, pool=pool)
        out.append((plan.rank, plan.complete))
    return out


def test_the_shortcuts_lose_no_plan(pairs_integral, monkeypatch) -> None:
    """The six squares with the integral I1: the planner with a shared pool and the pruned subsets completes the
    same normalizations, with the same ranks, as with fresh points and every subset of knowns."""
    ctx, known = pairs_integral
    fast = _plans(ctx, known, shared=True)
    assert any(complete for _, complete in fast)
    monkeypatch.setattr(relation_plan, "_subsets_for", lambda g, target, p: relation_plan._independent_subsets(g, p))
    assert _plans(ctx, known, shared=False) == fast


def test_a_normalization_over_a_size_limit_gives_way_to_the_next(monkeypatch):
    """_race: a normalization whose reconstruction hits a size limit (memory) is dropped and the next one is used;
    when every one does, the limit propagates (prove_basis then postpones the basis)."""
    from types import SimpleNamespace

    from hkproof.budget import Budget
    from hkproof.errors import ResourceLimitError
    from hkproof.pipelines.discover import solve
    ctx = SimpleNamespace(budget=Budget(60), stages=SimpleNamespace(say=lambda text: None),
                          kmap=SimpleNamespace(variables=("x", "y")))
    orders = [([(1, 0), (0, 1)], "plan a"), ([(0, 1), (1, 0)], "plan b")]
    tried = []

    def coordinates(ctx_, order, rng, budget):
        tried.append(order)
        if order == orders[0][0]:
            raise ResourceLimitError("too many shifted terms")
        return ["coords"]
    monkeypatch.setattr(solve, "coordinates", coordinates)
    assert solve._race(ctx, orders, random.Random(1)) == (orders[1][0], "plan b", ["coords"])
    monkeypatch.setattr(solve, "coordinates", lambda *a, **k: (_ for _ in ()).throw(ResourceLimitError("limit")))
    with pytest.raises(ResourceLimitError):
        solve._race(ctx, orders, random.Random(1))


def test_the_pool_renormalizes_one_kernel_exactly() -> None:
    """SamplePool.coordinates: the coordinates and gradients of every normalization of a basis, renormalized from
    one kernel per point, are those recipe (B) solves for that normalization directly; a wrong quotient rule fails."""
    kmap = kahan_map(SPLIT)
    pool = SamplePool(kmap, {}, P, {n: 3 for n in kmap.field.control_names}, random.Random(2), len(SQUARES) - 2)
    for index in range(3):
        x, orbit = pool.point(index)
        for last in range(len(SQUARES)):
            order = [e for k, e in enumerate(SQUARES) if k != last] + [SQUARES[last]]
            assert pool.coordinates(x, orbit, order, gradients=True) == sample_pool._direct(orbit, order, True)
            assert pool.coordinates(x, orbit, order) == (sample_pool._direct(orbit, order, False)[0], None)
    order = SQUARES[1:] + SQUARES[:1]
    coords, grads = pool.coordinates(x, orbit, order, gradients=True)
    assert grads != [[-g % P for g in row] for row in grads]      # the gradients are not trivially sign-symmetric
    assert sample_pool._direct(orbit, order, True) != (coords, [[-g % P for g in row] for row in grads])
