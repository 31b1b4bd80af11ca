"""The claim graph, the run's certificate cache, total provers and the executors (in process, pool, Dask)."""
from __future__ import annotations

import json

import flint
import pytest

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import get_ring
from hkproof.cli import main
from hkproof.errors import HKProofError
from hkproof.orchestration import registry
from hkproof.orchestration.execution import DaskExecutor, InProcessExecutor, ProcessPoolExecutor, run_graph
from hkproof.orchestration.graph import CitationCycleError, in_dependency_order
from hkproof.orchestration.registry import REGISTRY, claim, get_claim, load_all, proven, require_proven, select
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

load_all()


@pytest.fixture
def fresh_run(monkeypatch):
    """A new run (empty certificate cache); the claims a test registers are forgotten afterwards."""
    monkeypatch.setattr(registry, "_CACHE", {})
    before = dict(REGISTRY)
    yield
    REGISTRY.clear()
    REGISTRY.update(before)


def _verified_claim(claim_id: str, uses=(), log=None, claimed=None) -> None:
    """A tiny claim that is verified (or refuted when its claimed 'x' is not '1'); `log` counts its proofs."""
    @claim(claim_id, "test", claim_id, "-", "-", claimed=claimed or {"x": "1"}, uses=uses)
    def prove(cert: Certificate, given) -> None:
        if log is not None:
            with open(log, "a") as out:
                out.write(claim_id + "\n")
        for u in uses:
            require_proven(cert, u)
        with cert.step("x is 1", "comparison", "-") as s:
            s.require(given["x"] == "1", "x is not 1")


# -- the claim graph ------------------------------------------------------------------------------------------------
def test_claim_graph_declared_and_acyclic():
    order = in_dependency_order(REGISTRY, REGISTRY)
    assert sorted(order) == sorted(REGISTRY)
    position = {cid: k for k, cid in enumerate(order)}
    for c in REGISTRY.values():
        assert set(c.uses) <= set(REGISTRY), f"{c.id} uses an unregistered claim"
        assert all(position[u] < position[c.id] for u in c.uses)
    assert {"flow-reduction", "flow-second-theta", "flow-second-theorem", "dc-theta"} == set(REGISTRY["flow-theta-all"].uses)


def test_graph_refuses_cycles_and_unknown_citations(fresh_run):
    _verified_claim("t-a", uses=["t-b"])
    _verified_claim("t-b", uses=["t-a"])
    with pytest.raises(CitationCycleError, match="cycle"):
        in_dependency_order(["t-a"], REGISTRY)
    _verified_claim("t-c", uses=["t-nowhere"])
    with pytest.raises(Exception, match="not a registered claim"):
        in_dependency_order(["t-c"], REGISTRY)


def test_undeclared_citation_is_refused(fresh_run):
    @claim("t-undeclared", "test", "-", "-", "-")
    def prove(cert, given):
        require_proven(cert, "et-first-hk-basis")

    @claim("t-undeclared-proven", "test", "-", "-", "-")
    def prove_quietly(cert, given):
        proven("et-first-hk-basis")

    for cid in ("t-undeclared", "t-undeclared-proven"):
        cert = get_claim(cid).prove()
        assert cert.status is Status.UNKNOWN
        assert "not declared" in cert.error
    assert registry.cached("et-first-hk-basis") is None  # refused before anything was proven


def _claim_with_value(claim_id: str, uses=()) -> None:
    """A verified claim recording the exact value x1 + 1 (formula 'v'), reading the value 'v' of each claim it cites."""
    @claim(claim_id, "test", claim_id, "-", "-", uses=uses)
    def prove(cert: Certificate, given) -> None:
        r = get_ring(("x1",))
        for u in uses:
            assert require_proven(cert, u).values["v"] == Frac.parse(r, "x1 + 1")
        with cert.step("v", "-", "-"):
            cert.formula("v", Frac.parse(r, "x1 + 1"))


@pytest.mark.parametrize("values", [True, False])
def test_values_come_back_only_where_read(fresh_run, values):
    """Without `values`, a worker keeps the exact values of a claim nobody in the run cites (its formula then says so
    when read, and it stays out of the run's cache); a cited claim's values always come back."""
    _claim_with_value("t-cited")
    _claim_with_value("t-citing", uses=["t-cited"])
    with ProcessPoolExecutor(2) as executor:
        certs = run_graph(["t-cited", "t-citing"], executor, values=values)
    assert all(c.status is Status.VERIFIED for c in certs.values())
    assert certs["t-cited"].formulas["v"] == "x1 + 1"
    assert certs["t-citing"].values_withheld is not values
    if values:
        assert certs["t-citing"].formulas["v"] == "x1 + 1" and registry.cached("t-citing") is certs["t-citing"]
    else:
        with pytest.raises(HKProofError, match="stayed with the worker"):
            certs["t-citing"].formulas["v"]
        assert registry.cached("t-citing") is None and registry.cached("t-cited") is certs["t-cited"]


# -- one certificate cache per run ------------------------------------------------------------------------------------
@pytest.mark.parametrize("pool", [False, True], ids=["in-process", "pool"])
def test_cited_claim_proven_once_per_run(fresh_run, tmp_path, pool):
    log = tmp_path / "proofs.log"
    _verified_claim("t-base", log=log)
    _verified_claim("t-left", uses=["t-base"], log=log)
    _verified_claim("t-right", uses=["t-base"], log=log)
    executor = ProcessPoolExecutor(2) if pool else InProcessExecutor()
    with executor:
        certs = run_graph(["t-left", "t-right"], executor)
    assert all(c.status is Status.VERIFIED and c.cites == ["t-base"] for c in certs.values())
    assert sorted(log.read_text().split()) == ["t-base", "t-left", "t-right"]
    # pytest, report and prove read the same cache: nothing is proven again
    assert get_claim("t-left").prove() is registry.cached("t-left")
    assert proven("t-base").status is Status.VERIFIED
    assert get_claim("t-base").prove() is registry.cached("t-base")
    assert sorted(log.read_text().split()) == ["t-base", "t-left", "t-right"]
    # a perturbed claim is proven afresh and never enters the cache
    perturbed = get_claim("t-left").prove({"x": "2"})
    assert perturbed.status is Status.REFUTED
    assert registry.cached("t-left").status is Status.VERIFIED


def _claims_sharing(log, specs) -> None:
    """Register test claims (id, shared intermediate or "", seconds to wait) whose provers read one lru-cached
    intermediate (its computation logged as "computed PID") and log "ID PID" when done."""
    import functools
    import os
    import time

    @functools.lru_cache(maxsize=1)
    def intermediate() -> int:
        with open(log, "a") as out:
            out.write(f"computed {os.getpid()}\n")
        return 1

    def register(claim_id: str, shares: str, seconds: float, uses: tuple[str, ...] = ()) -> None:
        @claim(claim_id, "test", claim_id, "-", "-", claimed={"x": "1"}, shares=shares, uses=uses)
        def prove(cert: Certificate, given) -> None:
            with cert.step("reads the intermediate or waits", "comparison", "-") as s:
                s.require(not shares or intermediate() == 1, "wrong intermediate")
                time.sleep(seconds)
                with open(log, "a") as out:
                    out.write(f"{claim_id} {os.getpid()}\n")
    for spec in specs:
        register(*spec)


def test_claims_sharing_an_intermediate_run_on_one_worker_which_computes_it_once(fresh_run, tmp_path):
    """Claim.shares: two claims reading one per-process intermediate are proven one after the other by the worker
    that computed it (with --jobs 2 they would otherwise compute it twice, once in each worker); a third claim runs
    beside them."""
    log = tmp_path / "shared.log"
    _claims_sharing(log, [("t-shared-a", "t-intermediate", 0), ("t-shared-b", "t-intermediate", 0),
                          ("t-alone", "", 0)])
    with ProcessPoolExecutor(2) as executor:
        certs = run_graph(["t-shared-a", "t-shared-b", "t-alone"], executor)
    assert all(c.status is Status.VERIFIED for c in certs.values())
    lines = [line.split() for line in log.read_text().splitlines()]
    pids = {name: pid for name, pid in lines if name != "computed"}
    assert [pid for name, pid in lines if name == "computed"] == [pids["t-shared-a"]]
    assert pids["t-shared-a"] == pids["t-shared-b"]


def test_a_claim_sharing_an_intermediate_goes_to_the_free_worker_that_holds_it(fresh_run, tmp_path):
    """When the worker that computed an intermediate is free again, the claim reading it goes there before an
    unrelated claim takes that worker (else it would wait for the other worker and compute it a second time)."""
    log = tmp_path / "warm.log"
    _claims_sharing(log, [("t-warm-a", "t-x", 0), ("t-busy-1", "", 0.3), ("t-busy-2", "", 1.2), ("t-warm-b", "t-x", 0)])
    with ProcessPoolExecutor(2) as executor:
        certs = run_graph(["t-warm-a", "t-busy-1", "t-busy-2", "t-warm-b"], executor)
    assert all(c.status is Status.VERIFIED for c in certs.values())
    assert sum(line.startswith("computed") for line in log.read_text().splitlines()) == 1


@pytest.mark.parametrize("long_claim, computed", [(1.0, 1), (100.0, 2)])
def test_a_claim_waits_for_the_busy_worker_holding_its_intermediate_when_that_is_sooner(
        fresh_run, tmp_path, monkeypatch, long_claim, computed):
    """t-b reads the intermediate t-a computed, and is ready (after t-dep) while that worker proves t-long (after
    t-a): it waits for it when t-long is expected to end before the intermediate could be computed again
    (EXPECTED_SECONDS: t-long 1 s, the intermediate's claims 3 s), and takes the free worker, computing it a second
    time, when t-long is expected to take far longer (100 s)."""
    from hkproof.orchestration import execution
    for cid, seconds in (("t-a", 3), ("t-b", 3), ("t-dep", 1.5), ("t-long", long_claim)):
        monkeypatch.setitem(execution.EXPECTED_SECONDS, cid, seconds)
    log = tmp_path / "wait.log"
    _claims_sharing(log, [("t-a", "t-y", 0), ("t-dep", "", 1.5), ("t-long", "", 3.0, ("t-a",)),
                          ("t-b", "t-y", 0, ("t-dep",))])
    with ProcessPoolExecutor(2) as executor:
        certs = run_graph(["t-a", "t-dep", "t-long", "t-b"], executor)
    assert all(c.status is Status.VERIFIED for c in certs.values())
    lines = [line.split() for line in log.read_text().splitlines()]
    assert sum(name == "computed" for name, _ in lines) == computed, lines


def test_workers_share_the_cores(fresh_run, tmp_path, monkeypatch):
    """Each of N workers uses at most cores // N cores (FLINT's threads, forked parts), at least one; the parent
    and a single in-process run keep them all."""
    from hkproof.algebra import ring
    monkeypatch.setattr(ring.os, "sched_getaffinity", lambda pid: set(range(8)), raising=False)
    log = tmp_path / "cores.log"

    def register(claim_id: str) -> None:
        @claim(claim_id, "test", claim_id, "-", "-", claimed={"x": "1"})
        def prove(cert: Certificate, given) -> None:
            with cert.step("reads its cores", "comparison", "-"):
                log.write_text(str(ring.cores()))
    for jobs, share in ((2, 4), (3, 2), (16, 1)):
        register(f"t-cores-{jobs}")
        with ProcessPoolExecutor(jobs) as executor:
            run_graph([f"t-cores-{jobs}"], executor)
        assert log.read_text() == str(share)
    assert ring.cores() == 8


# -- total provers ----------------------------------------------------------------------------------------------------
def _recursion():
    return _recursion()


def _flint_error():
    ctx = flint.fmpz_mpoly_ctx.get(("x",))
    return ctx.gen(0) ** -1


CRASHES = {
    "IndexError": lambda: [][1],
    "ValueError": lambda: int("x"),
    "AssertionError": lambda: exec("assert False, 'a bug'"),
    "RecursionError": _recursion,
    "MemoryError": lambda: (_ for _ in ()).throw(MemoryError("out of memory")),
    "DomainError": _flint_error,
}


@pytest.mark.parametrize("inside_step", [True, False], ids=["in-step", "outside-step"])
@pytest.mark.parametrize("name", list(CRASHES))
def test_any_prover_error_is_an_unknown_certificate(fresh_run, name, inside_step):
    @claim("t-crash", "test", "-", "-", "-")
    def prove(cert, given):
        if inside_step:
            with cert.step("crashing step", "-", "-"):
                CRASHES[name]()
        CRASHES[name]()

    cert = get_claim("t-crash").prove()
    assert cert.status is Status.UNKNOWN
    assert name in cert.error
    if inside_step:
        assert cert.steps[0].status is Status.UNKNOWN and name in cert.steps[0].detail


def test_keyboard_interrupt_is_not_swallowed(fresh_run):
    @claim("t-interrupted", "test", "-", "-", "-")
    def prove(cert, given):
        with cert.step("interrupted", "-", "-"):
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        get_claim("t-interrupted").prove()


def test_a_crash_does_not_stop_the_run(fresh_run):
    @claim("t-crash", "test", "-", "-", "-")
    def prove(cert, given):
        [][0]

    _verified_claim("t-after", uses=["t-crash"])
    _verified_claim("t-independent")
    certs = run_graph(["t-crash", "t-after", "t-independent"], InProcessExecutor())
    assert [certs[c].status for c in ("t-crash", "t-after", "t-independent")] == [
        Status.UNKNOWN, Status.UNKNOWN, Status.VERIFIED]
    assert "t-crash is unknown" in certs["t-after"].error


# -- executors --------------------------------------------------------------------------------------------------------
def _without_timings(cert: Certificate) -> dict:
    d = cert.to_dict()
    d.pop("seconds")
    d["steps"] = [{k: v for k, v in s.items() if k != "seconds"} for s in d["steps"]]
    return d


def _euler_top_with(executor, monkeypatch) -> dict[str, dict]:
    monkeypatch.setattr(registry, "_CACHE", {})
    with executor:
        certs = run_graph([c.id for c in select(groups=["euler-top"])], executor)
    return {cid: _without_timings(cert) for cid, cert in certs.items()}


def test_pool_and_in_process_certificates_identical(monkeypatch):
    serial = _euler_top_with(InProcessExecutor(), monkeypatch)
    assert all(c["status"] == "verified" for c in serial.values())
    assert _euler_top_with(ProcessPoolExecutor(2), monkeypatch) == serial


def test_dask_local_cluster_certificates_identical(monkeypatch):
    pytest.importorskip("distributed", reason="Dask distributed is an optional extra: pip install 'hkproof[dask]'")
    serial = _euler_top_with(InProcessExecutor(), monkeypatch)
    assert _euler_top_with(DaskExecutor(2), monkeypatch) == serial


def test_dask_on_an_existing_scheduler(monkeypatch):
    distributed = pytest.importorskip("distributed", reason="Dask distributed is an optional extra")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None) as cl:
        certs = _euler_top_with(DaskExecutor(1, scheduler=cl.scheduler_address), monkeypatch)
    assert all(c["status"] == "verified" for c in certs.values())


# -- the command line -------------------------------------------------------------------------------------------------
def test_prove_jsonl_streams_one_object_per_line(capsys):
    assert main(["prove", "--group", "euler-top", "--jsonl", "--jobs", "2"]) == 0
    lines = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["id"] for r in lines[:-1]] and all(r["status"] == "verified" for r in lines[:-1])
    assert lines[-1]["interrupted"] is False and lines[-1]["finished"] == len(lines) - 1


@pytest.mark.parametrize("argv", [["--json", "--jsonl"], ["--jobs", "0"], ["--scheduler", "tcp://127.0.0.1:1"]])
def test_prove_refuses_bad_run_options(argv, capsys):
    try:
        code = main(["prove", "et-full-basis", *argv])
    except SystemExit as exc:  # argparse
        code = exc.code
    assert code == 2


def test_report_write_checks_the_target_first(tmp_path, capsys):
    assert main(["report", "--write", str(tmp_path / "missing" / "theorems.md")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["report", "--write", str(tmp_path)]) == 2


def test_report_writes_atomically(tmp_path):
    from hkproof.commands.report import write_atomically
    target = tmp_path / "theorems.md"
    target.write_text("old")
    target.chmod(0o644)
    write_atomically(target, "new")
    assert target.read_text() == "new"
    assert target.stat().st_mode & 0o777 == 0o644  # not the temporary file's 0600
    assert [p.name for p in tmp_path.iterdir()] == ["theorems.md"]


# -- layers -----------------------------------------------------------------------------------------------------------
def _imports(path) -> set[str]:
    import ast
    tree = ast.parse(path.read_text())
    found = {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names}
    return found | {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.module}


def test_only_theorems_and_front_ends_import_orchestration():
    from pathlib import Path
    package = Path(__file__).resolve().parents[1] / "hkproof"
    lower = [p for layer in ("algebra", "dynamics", "hk", "experiments") for p in (package / layer).glob("*.py")]
    lower += [package / "proof" / "status.py", package / "proof" / "certificate.py"]
    offenders = [str(p.relative_to(package)) for p in lower
                 if any(m.startswith("hkproof.orchestration") for m in _imports(p))]
    assert offenders == []


def test_certificate_travels_with_its_exact_values():
    import pickle
    cert = proven("dc-basis2")
    assert cert.values  # d7, d8, ... kept exactly
    copy = pickle.loads(pickle.dumps(cert))
    assert copy.to_dict() == cert.to_dict()
    assert all(copy.values[k] == v and copy.values[k].ring == v.ring for k, v in cert.values.items())
    again = pickle.loads(pickle.dumps(copy))  # passed on by the scheduler without packing again
    assert all(again.values[k] == v for k, v in cert.values.items())


def test_packed_values_keep_large_exponents_and_coefficients_and_share_equal_polynomials():
    """Exponents of any size and coefficients of any length survive the packing; a denominator that several values
    share (equal, not necessarily the same object) is written once."""
    import pickle
    from hkproof.algebra.fraction import Frac
    from hkproof.algebra.ring import get_ring
    ring = get_ring(("x", "eps"))
    den = Frac.parse(ring, "(1 + eps*x**300 + 7*x**70000)**2 * (1 + x + eps)**30").num
    nums = [Frac.parse(ring, t).num for t in ("x**2 - 3**90", "eps**255 * x", "x**256 + 1")]
    cert = Certificate("c", "t", "p", "s")
    for k, num in enumerate(nums):
        cert.formula(f"g{k}", Frac(ring, num, den * 1, reduced=True))   # den * 1: equal, another object
    copy = pickle.loads(pickle.dumps(cert))
    assert all(copy.values[f"g{k}"] == Frac(ring, num, den, reduced=True) for k, num in enumerate(nums))
    one = Certificate("c", "t", "p", "s")
    one.formula("g0", Frac(ring, nums[0], den, reduced=True))
    assert len(pickle.dumps(cert)) < len(pickle.dumps(one)) + 200   # the shared denominator once
    assert pickle.loads(pickle.dumps(copy)).values["g2"] == cert.values["g2"]


def test_exact_values_stay_packed_until_read():
    """A pickled certificate's values are unpacked one by one when read (the scheduler, which only prints or forwards
    a certificate, builds no polynomial), passed on as they came, and a value set after arrival is packed anew."""
    import pickle
    from hkproof.algebra.fraction import Frac
    from hkproof.algebra.ring import get_ring
    from hkproof.proof.certificate import PackedValues
    ring = get_ring(("x", "eps"))
    cert = Certificate("c", "t", "p", "s")
    for name, text in (("g", "x/(1 + eps)"), ("h", "(x**2 - eps)/(1 + x)")):
        cert.formula(name, Frac.parse(ring, text))
    copy = pickle.loads(pickle.dumps(cert))
    assert isinstance(copy.values, PackedValues) and copy.values._values == {}
    assert copy.values["h"] == cert.values["h"] and set(copy.values._values) == {"h"}
    copy.formula("k", Frac.parse(ring, "eps - x"))
    again = pickle.loads(pickle.dumps(copy))
    assert sorted(again.values) == ["g", "h", "k"] == sorted(again.formulas)
    assert all(again.values[n] == Frac.parse(ring, t) for n, t in (("g", "x/(1 + eps)"), ("k", "eps - x")))


def test_the_longest_chain_of_citations_starts_first():
    """In `prove --all` the short flow-second-theorem, on which the chain of the two slowest claims waits, comes
    before a slow claim that nothing cites; dependencies still come first."""
    from hkproof.orchestration.execution import EXPECTED_SECONDS, expected_seconds
    from hkproof.orchestration.graph import critical_path_first
    load_all()
    assert set(EXPECTED_SECONDS) <= set(REGISTRY)       # the scheduling table names registered claims only
    order = critical_path_first(in_dependency_order(list(REGISTRY), REGISTRY), REGISTRY, expected_seconds)
    position = {cid: k for k, cid in enumerate(order)}
    assert position["flow-second-theorem"] < position["atlas-so4-euler-top-split-integrals"]
    assert position["flow-second-bases-345"] < position["flow-conjecture"]
    assert position["flow-second-l-relations-found"] < position["dc-basis1-even"]
    assert all(position[u] < position[cid] for cid in order for u in REGISTRY[cid].uses)


def test_a_formula_with_its_value_is_written_out_only_when_read():
    """A certificate's formula recorded with its exact value stays unwritten through pickling (a worker's certificate
    on its way to the scheduler) and is the value's text when read."""
    import pickle
    from hkproof.algebra.fraction import Frac
    from hkproof.algebra.ring import get_ring
    h = Frac.parse(get_ring(("x", "eps")), "(x**2 - eps)/(1 + x)")
    cert = Certificate("c", "t", "p", "s")
    cert.formula("h", h)
    cert.formula("n", "3")
    assert cert.formulas.unwritten() == {"h": None, "n": "3"}
    copy = pickle.loads(pickle.dumps(cert))
    assert copy.formulas.unwritten() == {"h": None, "n": "3"} and copy.values["h"] == h
    assert copy.formulas["h"] == str(h) and Frac.parse(h.ring, copy.formulas["h"]) == h
    assert dict(copy.formulas) == {"h": str(h), "n": "3"} == copy.to_dict()["formulas"]


# -- heavy steps over the same executors: kernel profiles of `scan` ------------------------------------------------
SCAN = ["scan", "euler-top", "--basis", "x1**2, x2**2, x3**2, 1", "--points", "16", "--eps", "1/3", "--json",
        "--no-progress"]


def _scan_profiles(capsys, *extra: str) -> list:
    from hkproof.cli import main
    assert main([*SCAN, *extra]) == 0
    return json.loads(capsys.readouterr().out)["points"]


def _without_times(profiles: list) -> list:
    return [{k: v for k, v in p.items() if k != "seconds"} for p in profiles]


def test_scan_profiles_identical_in_a_pool_and_on_dask(capsys):
    pytest.importorskip("distributed")
    alone = _without_times(_scan_profiles(capsys, "--jobs", "1"))
    assert _without_times(_scan_profiles(capsys, "--jobs", "2")) == alone
    assert _without_times(_scan_profiles(capsys, "--jobs", "2", "--executor", "dask")) == alone


def test_a_refutation_message_given_as_a_callable_is_written_only_on_failure():
    from hkproof.errors import ProofStopped
    from hkproof.proof.status import Status as S
    written: list[str] = []

    def message() -> str:
        written.append("text")
        return "the big formula"
    cert = Certificate("c", "t", "p", "s")
    with cert.step("holds", "m", "-") as s:
        s.require(True, message)
    with pytest.raises(ProofStopped), cert.step("fails", "m", "-") as s:
        s.require(False, message)
    assert written == ["text"] and cert.steps[-1].status is S.REFUTED and "the big formula" in cert.steps[-1].detail


def test_a_finished_claim_is_reported_after_the_next_claims_are_handed_out(fresh_run):
    """on_done (which may print a long certificate) runs once the free slot has its next claim, and every finished
    certificate is reported exactly once."""
    _verified_claim("t-first")
    _verified_claim("t-second", uses=["t-first"])
    _verified_claim("t-third", uses=["t-second"])
    events: list[str] = []

    class Logging(InProcessExecutor):
        def submit(self, claim_id, cited, values=True):
            events.append("submit " + claim_id)
            return super().submit(claim_id, cited)
    certs = run_graph(["t-first", "t-second", "t-third"], Logging(),
                      lambda cert: events.append("done " + cert.claim_id))
    assert events == ["submit t-first", "submit t-second", "done t-first", "submit t-third", "done t-second",
                      "done t-third"]
    assert all(c.status is Status.VERIFIED for c in certs.values())
