"""The parts of one computation as tasks of a Dask cluster (budget.spread_on, DaskSpread): FLINT polynomials travel
as data, a lattice identity gets the verdict of forked children, a part's error and the deadline reach the caller."""
from __future__ import annotations

import pickle

import flint
import pytest

from hkproof.algebra.lattice_identity import horner, plan_lattice, vanishes_on_lattice
from hkproof.budget import Budget, parallel_parts, spread_on, spread_slots
from hkproof.errors import BudgetExhausted, HKProofError
from hkproof.hk.row_check import RouteCosts
from hkproof.orchestration.execution import DaskSpread, dask_client

from tests.test_lattice_identity import A, E, R, X, Y, zero_identity

distributed = pytest.importorskip("distributed", reason="Dask distributed is an optional extra: "
                                  "pip install 'hkproof[dask]'")


@pytest.mark.parametrize("ordering", ["lex", "deglex", "degrevlex"])
def test_flint_polynomials_pickle_as_data(ordering):
    ctx = flint.fmpz_mpoly_ctx.get(("u", "v", "w"), ordering)
    u, v, w = ctx.gens()
    for p in (ctx.from_dict({}), ctx.from_dict({(0, 0, 0): -7}), (u - 2 ** 90 * v * w + 3) ** 5):
        q = pickle.loads(pickle.dumps(p))
        assert q == p and q.context() is ctx


@pytest.fixture(scope="module")
def cluster():
    """A client of a local cluster of two worker processes."""
    client, cluster = dask_client(2, None)
    try:
        yield client
    finally:
        client.close()
        cluster.close()


def test_a_lattice_on_dask_workers_gives_the_forked_verdicts(cluster):
    cluster_spread = DaskSpread(cluster)
    terms, factors = zero_identity(7, top=9)
    plan = plan_lattice(terms, factors, R.names, ("eps",), ("a", "b"))
    bad = {(1, 0): terms[(1, 0)] + X * Y ** 2 * E ** 2 * A ** 2, (0, 1): terms[(0, 1)]}
    bad_plan = plan_lattice(bad, factors, R.names, ("eps",), ("a", "b"))
    with spread_on(cluster_spread):
        assert spread_slots() == 2 and parallel_parts(2) == 8
        before = len(cluster_spread.stages)
        assert vanishes_on_lattice(terms, factors, plan, jobs=8) == (True, None)
        holds, point = vanishes_on_lattice(bad, factors, bad_plan, jobs=8)
    assert vanishes_on_lattice(bad, factors, bad_plan, jobs=2)[0] is False          # forked children agree
    assert not holds and point is not None
    at = {"eps": 1, **point}
    assert not horner({mu: t.subs(at) for mu, t in bad.items()}, [f.subs(at) for f in factors]).is_zero()
    doing, seconds, wall = cluster_spread.stages[before]
    assert "lattice" in doing and len(seconds) == 8 and wall > 0


def test_a_part_that_fails_or_a_passed_deadline_reaches_the_caller(cluster):
    def part(k: int) -> int:
        if k == 1:
            raise HKProofError("part 1 cannot be done")
        return k

    with spread_on(DaskSpread(cluster)):
        with pytest.raises(HKProofError, match="part 1"):
            Budget(60).call_each("a test", part, 3)
        with pytest.raises(BudgetExhausted, match="a test"):
            Budget(0.0).call_each("a test", part, 3)
        assert Budget(60).call_each("a test", lambda k: k * k, 4) == [0, 1, 4, 9]


def test_a_spread_with_more_slots_than_cores_makes_the_lattice_cheaper():
    terms, factors = zero_identity(7, top=9)
    local = RouteCosts(terms, factors, R.names, ("eps", "a", "b"), jobs=2).costs["lattice"]
    wide = RouteCosts(terms, factors, R.names, ("eps", "a", "b"), jobs=64).costs["lattice"]
    assert wide < local


def test_a_proof_running_on_a_dask_worker_spreads_its_parts_on_the_same_cluster(cluster):
    """`prove --executor dask`: the claim is a task of a worker, and its parts are tasks of the same cluster
    (`DaskSpread()` takes the worker's client; the task leaves its thread to them while it waits)."""
    def claim_like() -> tuple[list[int], int]:
        from hkproof.orchestration.execution import DaskSpread as Inner
        inner = Inner()
        with spread_on(inner):
            return Budget(60).call_each("parts of a claim", lambda k: k + 10, 5), len(inner.stages)

    assert cluster.submit(claim_like, pure=False).result(timeout=60) == ([10, 11, 12, 13, 14], 1)


def test_a_task_that_carries_a_budget_has_a_dask_key():
    """discover --executor dask maps step 5d's coordinates (dataclasses holding the command's Budget) through Dask's
    executor, which tokenizes its arguments: the budget's pickled state holds a wall-clock time, so it names its own
    token (without it: TokenizationError, an internal error of the command)."""
    from dataclasses import dataclass

    from dask.base import tokenize

    @dataclass(frozen=True)
    class Job:
        seed: int
        budget: Budget

    import dask
    budget = Budget(60)
    with dask.config.set({"tokenize.ensure-deterministic": True}):       # what made Dask's executor refuse the job
        assert tokenize(Job(1, budget)) == tokenize(Job(1, budget)) != tokenize(Job(2, budget))
