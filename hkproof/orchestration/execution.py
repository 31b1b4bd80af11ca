"""Where proofs run: one small executor interface (in process, a process pool, Dask distributed) and the schedule
that walks the claim graph on it -- dependencies first, each claim proven once per run, a worker handed the
certificates its claim cites. The certificates do not depend on the executor."""
from __future__ import annotations

import concurrent.futures
import itertools
import logging
import math
import multiprocessing
import multiprocessing.connection
import os
import signal
import time
import uuid
from multiprocessing.connection import Connection
from contextlib import contextmanager, nullcontext
from typing import Any, Callable, Hashable, Iterable, Iterator, Mapping, Sequence, TypeVar, cast

import hkproof.algebra.pickling  # noqa: F401 -- FLINT polynomials travel to Dask workers as data
from hkproof.algebra.ring import cores, share_cores
from hkproof.budget import Budget, Spread, spread_on
from hkproof.errors import HKProofError
from hkproof.orchestration.graph import critical_path_first, in_dependency_order
from hkproof.orchestration.interrupts import as_worker, interrupts_blocked, interrupts_deferred
from hkproof.orchestration.registry import REGISTRY, Claim, cached, get_claim, load_all, remember
from hkproof.proof.certificate import Certificate

__all__ = ["dask_client", "DaskExecutor", "DaskSpread", "Executor", "EXECUTORS", "InProcessExecutor", "make_executor",
           "map_executor", "ProcessPoolExecutor", "prove_citing", "run_graph", "worker_failed"]

EXECUTORS = ("process", "dask")
# Seconds a claim took in one `prove --all --jobs 2` (2 cores, 2026-11-29), for the order of a parallel run only (never a
# result): the longest chains start first. A claim not listed weighs 1 s, or SLOW_SECONDS when marked slow.
EXPECTED_SECONDS = {
    "flow-second-bases-345": 100, "atlas-so4-euler-top-split-integrals": 38, "flow-conjecture": 3,
    "dc-invariant-measures": 23, "atlas-so4-euler-top-flow2-kernels": 21, "atlas-so4-euler-top-flow2-integrals": 21,
    "atlas-zhukovsky-volterra-1-liouville-arnold": 10, "dc-nambu-poisson": 10, "dc-f2-plain": 10, "dc-f2-reduced": 5,
    "atlas-kirchhoff-integrals": 9, "flow-second-theta": 6, "flow-second-l-relations-found": 4,
    "atlas-so4-euler-top-chart": 5, "flow-second-recipe-g": 2, "flow-theta-all": 2, "atlas-lagrange-top-integrals": 4,
    "dc345-relations-found": 3, "dc345-step5": 3, "atlas-volterra-4-liouville-arnold": 2,
    "atlas-gaudin-2-integrals": 2, "flow-second-relations-found": 3, "atlas-kirchhoff-kernels": 9, "dc345-alpha": 2,
    "dc345-max-basis": 2}
SLOW_SECONDS = 30


def expected_seconds(claim: Claim) -> float:
    """The scheduling weight of a claim (EXPECTED_SECONDS)."""
    return EXPECTED_SECONDS.get(claim.id, SLOW_SECONDS if claim.slow else 1)


T = TypeVar("T")


def prove_citing(claim_id: str, cited: Mapping[str, Certificate], seconds: float | None = None,
                 spread: bool = False, values: bool = True) -> Certificate:
    """A worker's task: the run's cache seeded with the certificates `claim_id` cites, then the claim proven once
    (within `seconds`, if given); with `spread` (a Dask worker) the parts of its computations are tasks of the same
    cluster (`DaskSpread`); without `values` its certificate travels back without its exact values
    (`Certificate.withhold_values`)."""
    load_all()
    remember(cited.values())
    with spread_on(DaskSpread()) if spread else nullcontext():
        cert = get_claim(claim_id).prove(seconds=seconds)
    if not values:
        cert.withhold_values()
    return cert


def _timed_part(fn: Callable[[int], T], k: int, budget: Budget) -> tuple[T, float]:
    """A task of `DaskSpread`: fn(k) under `budget` (its deadline travels as wall-clock time), and its seconds."""
    start = time.perf_counter()
    with budget.active():
        value = fn(k)
    return value, time.perf_counter() - start


class DaskSpread(Spread):
    """The parts of one computation (the points of a lattice, the primes of a modular identity) as tasks on a Dask
    cluster: `fn` is scattered once to every worker (FLINT polynomials as data, hkproof.algebra.pickling), then one
    task per part. With `client` None it runs inside a task of a Dask worker (`prove --executor dask`), whose client
    it takes through `distributed.worker_client` (the task leaves its thread to the parts while it waits). A part's
    exception is raised here; at the deadline the parts still queued are cancelled (a running one stops at its next
    budget check)."""

    def __init__(self, client: Any = None) -> None:
        super().__init__()
        import distributed
        self._distributed, self._client = distributed, client
        here = client if client is not None else distributed.get_client()
        self.slots = max(1, sum(here.nthreads().values()))

    def run(self, budget: Budget, doing: str, fn: Callable[[int], T], jobs: int) -> list[T]:
        start = time.perf_counter()
        budget.check(doing)
        with nullcontext(self._client) if self._client is not None else self._distributed.worker_client() as client:
            shared = client.scatter(fn, broadcast=True, hash=False)
            futures = [client.submit(_timed_part, shared, k, budget, pure=False) for k in range(jobs)]
            wait = budget.remaining() if math.isfinite(budget.deadline) else None
            try:
                self._distributed.wait(futures, timeout=wait)
            except TimeoutError:
                client.cancel(futures)
                raise budget.out_of_time(doing) from None
            answers = client.gather(futures)
        self.stages.append((doing, [seconds for _, seconds in answers], time.perf_counter() - start))
        return [value for value, _ in answers]


def worker_failed(claim_id: str, exc: BaseException) -> Certificate:
    """An `unknown` certificate for a claim whose worker died or could not return (not the prover's verdict)."""
    c = get_claim(claim_id)
    cert = Certificate(c.id, c.title, c.paper_ref, c.statement)
    cert.error = f"the worker proving {claim_id} failed: {type(exc).__name__}: {exc}"
    return cert


class Executor:
    """Runs proofs somewhere: `submit` one claim with the certificates it cites, `wait` until some finish.
    `slots` is how many proofs it runs at once, `seconds` the budget of each proof (None: no limit)."""

    slots = 1
    seconds: float | None = None

    def submit(self, claim_id: str, cited: Mapping[str, Certificate], values: bool = True) -> Hashable:
        """Start proving `claim_id` with the certificates it cites; without `values` its certificate may come back
        without its exact values (a worker in another process does not pack them)."""
        raise NotImplementedError

    def wait(self, handles: Sequence[Hashable]) -> list[tuple[Hashable, Certificate]]:
        """Block until at least one of `handles` is done; their certificates."""
        raise NotImplementedError

    def holder(self, shares: str) -> str | None:
        """Which workers have computed the intermediate `shares` (Claim.shares): "idle" (one is free), "busy" (only
        workers proving other claims), None (none, or an executor that does not say)."""
        return None

    def holder_task(self, shares: str) -> Hashable | None:
        """The task a busy worker holding the intermediate `shares` is running (None: none, or not said)."""
        return None

    def close(self, interrupted: bool = False) -> None:
        """Release the workers; after an interrupt, stop running proofs at once."""

    def __enter__(self) -> Executor:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close(interrupted=exc_type is not None)


class InProcessExecutor(Executor):
    """`--jobs 1`: a plain loop in this process (no pool), for debugging; the cited claims are in the run's cache."""

    def __init__(self) -> None:
        self._done: dict[Hashable, Certificate] = {}
        self._handles = itertools.count()

    def submit(self, claim_id: str, cited: Mapping[str, Certificate], values: bool = True) -> Hashable:
        handle = next(self._handles)
        self._done[handle] = get_claim(claim_id).prove(seconds=self.seconds)
        return handle

    def wait(self, handles: Sequence[Hashable]) -> list[tuple[Hashable, Certificate]]:
        return [(h, self._done.pop(h)) for h in handles]


def _serve(conn: Connection, parent_end: Connection | None = None, share: int | None = None) -> None:
    """A worker process: prove the claims the parent sends, one at a time, until it sends None or is gone, on at
    most `share` cores (`algebra.ring.share_cores`). The
    parent's end of the pipe, which a forked worker inherits, is closed first: open here, it would keep the pipe open
    after the parent's death, and the worker would wait for a task for ever. (A worker also inherits the parent's
    ends of the pipes of the workers started before it; it closes them by ending, and so on down to the first.)"""
    if parent_end is not None:
        parent_end.close()
    _own_group(0)
    as_worker()
    share_cores(share)
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):     # the parent died without stopping this worker: end quietly
            return
        if task is None:
            return
        claim_id, cited, seconds, values = task
        cert = prove_citing(claim_id, cited, seconds, values=values)
        try:
            conn.send(cert)
        except OSError:     # the parent is gone
            return
        except Exception as exc:  # noqa: BLE001 -- e.g. a certificate that cannot be pickled
            conn.send(worker_failed(claim_id, exc))


def _own_group(pid: int) -> None:
    """Make the worker `pid` (0: this process) the leader of a process group of its own, which the processes it
    forks (`Budget.call`) join: stopping the group stops them too, where stopping the worker alone would leave them
    computing, holding the output pipes. Set by the parent and by the worker, whichever runs first (POSIX only)."""
    try:
        os.setpgid(pid, 0)
    except (OSError, AttributeError):   # the worker has already ended; no process groups (Windows)
        pass


class _Worker:
    """One worker process and the pipe to it."""

    def __init__(self, share: int | None = None) -> None:
        self.conn, child = multiprocessing.Pipe()
        self.process = multiprocessing.Process(target=_serve, args=(child, self.conn, share), daemon=True)
        with interrupts_blocked():       # until the worker has its own signal dispositions
            self.process.start()
        _own_group(cast(int, self.process.pid))
        child.close()
        self.shared: set[str] = set()    # the intermediates (Claim.shares) its claims have computed
        self.task: _Task | None = None   # the claim it is proving

    def stop(self, sig: int = signal.SIGTERM) -> None:
        """Send `sig` to the worker and to the processes it forked (its process group)."""
        try:
            os.killpg(cast(int, self.process.pid), sig)
        except (OSError, AttributeError):   # no group of its own yet (it forks nothing before it has one); Windows
            if sig == getattr(signal, "SIGKILL", None):
                self.process.kill()
            else:
                self.process.terminate()


class _Task:
    """A claim being proven by a worker (the handle `submit` returns)."""

    def __init__(self, claim_id: str, worker: _Worker) -> None:
        self.claim_id, self.worker = claim_id, worker


class ProcessPoolExecutor(Executor):
    """`--jobs N`: N worker processes on this machine, each proving one claim at a time; a worker that dies costs
    its claim (an `unknown` certificate) and is replaced; a claim that shares an intermediate (Claim.shares) goes to
    an idle worker that has computed it. Plain pipes, no helper threads: Ctrl-C stops it at once."""

    def __init__(self, jobs: int) -> None:
        self.slots = jobs
        self.share = max(1, cores() // jobs)     # each worker's cores
        self._idle: list[_Worker] = []
        self._busy: list[_Worker] = []

    def submit(self, claim_id: str, cited: Mapping[str, Certificate], values: bool = True) -> Hashable:
        # every worker is in _busy or _idle whenever an interrupt can take effect, so that `close` stops it: an
        # interrupt raised while one was being started would leave it waiting for a task, holding the output pipe
        shares = get_claim(claim_id).shares
        with interrupts_deferred():
            warm = [w for w in self._idle if shares and shares in w.shared]
            worker = (warm[0] if warm else self._idle[-1]) if self._idle else _Worker(self.share)
            if worker in self._idle:
                self._idle.remove(worker)
            self._busy.append(worker)
            try:
                worker.conn.send((claim_id, dict(cited), self.seconds, values))
            except OSError:  # the worker died while idle
                self._busy.remove(worker)
                self._discard(worker)
                worker = _Worker(self.share)
                self._busy.append(worker)
                worker.conn.send((claim_id, dict(cited), self.seconds, values))
            if shares:
                worker.shared.add(shares)
            worker.task = _Task(claim_id, worker)
        return worker.task

    def wait(self, handles: Sequence[Hashable]) -> list[tuple[Hashable, Certificate]]:
        tasks = {task.worker.conn: task for task in (cast(_Task, h) for h in handles)}
        done: list[tuple[Hashable, Certificate]] = []
        for conn in multiprocessing.connection.wait(list(tasks)):
            task = tasks[cast(Any, conn)]
            try:
                cert = task.worker.conn.recv()      # interrupted here, the worker is still busy: `close` stops it
            except (EOFError, OSError) as exc:
                self._busy.remove(task.worker)
                self._discard(task.worker)
                cert = worker_failed(task.claim_id, exc if str(exc) else
                                     RuntimeError(f"exit code {task.worker.process.exitcode}"))
            else:
                self._busy.remove(task.worker)
                self._idle.append(task.worker)
            done.append((task, cert))
        return done

    def holder(self, shares: str) -> str | None:
        if any(shares in w.shared for w in self._idle):
            return "idle"
        return "busy" if any(shares in w.shared for w in self._busy) else None

    def holder_task(self, shares: str) -> Hashable | None:
        return next((w.task for w in self._busy if shares in w.shared), None)

    def _discard(self, worker: _Worker) -> None:
        worker.stop(getattr(signal, "SIGKILL", signal.SIGTERM))
        worker.process.join()
        worker.conn.close()

    def close(self, interrupted: bool = False) -> None:
        for worker in self._busy + self._idle:
            if interrupted or worker in self._busy:
                worker.stop()
            else:
                worker.conn.send(None)
        for worker in self._busy + self._idle:
            worker.process.join()
            worker.conn.close()
        self._busy, self._idle = [], []


def _result(future, claim_id: str) -> Certificate:
    """The certificate a Dask future holds, or an `unknown` one if its worker failed."""
    try:
        return future.result()
    except Exception as exc:  # noqa: BLE001 -- a dead worker costs its claim, never the run
        return worker_failed(claim_id, exc)


class DaskExecutor(Executor):
    """`--executor dask`: the same graph on Dask distributed, on the cluster at `scheduler`, or on a LocalCluster
    of `jobs` worker processes that this executor starts and stops."""

    def __init__(self, jobs: int, scheduler: str | None = None) -> None:
        import distributed
        self._distributed = distributed
        self._client, self._cluster = dask_client(jobs, scheduler)
        self.slots = max(1, sum(self._client.nthreads().values()))
        self._claims: dict[Hashable, str] = {}

    def submit(self, claim_id: str, cited: Mapping[str, Certificate], values: bool = True) -> Hashable:
        future = self._client.submit(prove_citing, claim_id, dict(cited), self.seconds, True, values,
                                     key=f"prove-{claim_id}-{uuid.uuid4().hex}")
        self._claims[future] = claim_id
        return future

    def wait(self, handles: Sequence[Hashable]) -> list[tuple[Hashable, Certificate]]:
        done, _ = self._distributed.wait(list(handles), return_when="FIRST_COMPLETED")
        return [(f, _result(f, self._claims.pop(f))) for f in done]

    def close(self, interrupted: bool = False) -> None:
        if interrupted:
            self._client.cancel(list(self._claims))
        self._client.close()
        if self._cluster is not None:
            self._cluster.close()


def dask_client(jobs: int, scheduler: str | None) -> tuple[Any, Any]:
    """(client, cluster): a client of the Dask scheduler at `scheduler`, or of a LocalCluster of `jobs` worker
    processes started here (cluster None when the scheduler was given)."""
    try:
        import distributed
    except ImportError:
        raise HKProofError("--executor dask needs Dask distributed: pip install 'hkproof[dask]'") from None
    cluster = None
    try:
        if scheduler is not None:
            return distributed.Client(_checked_address(scheduler), timeout=10), None
        cluster = distributed.LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True,
                                           dashboard_address=None, silence_logs=logging.ERROR)
        return distributed.Client(cluster), cluster
    except (OSError, TimeoutError, ValueError, TypeError) as exc:   # unreachable, or an address Dask cannot read
        if cluster is not None:
            cluster.close()
        raise HKProofError(f"cannot reach the Dask scheduler {scheduler or '(local cluster)'}: {exc}") from None


def _checked_address(scheduler: str) -> str:
    """A Dask scheduler address that is not blank (a blank one would silently start a local cluster)."""
    if not scheduler.strip():
        raise HKProofError("--scheduler is empty: give the address of a running Dask scheduler, e.g. "
                           "tcp://10.0.0.5:8786, or leave --scheduler out for a local cluster")
    return scheduler.strip()


def _check_run_options(kind: str, scheduler: str | None) -> None:
    """A known executor, and a scheduler address only for Dask."""
    if kind not in EXECUTORS:
        raise HKProofError(f"unknown executor '{kind}'; executors are {', '.join(EXECUTORS)}")
    if scheduler is not None and kind != "dask":
        raise HKProofError("--scheduler ADDRESS is the address of a Dask scheduler: use it with --executor dask")


@contextmanager
def map_executor(kind: str, jobs: int, scheduler: str | None, tasks: int
                 ) -> Iterator[concurrent.futures.Executor | None]:
    """A concurrent.futures executor for the embarrassingly parallel steps of one command (kernel profiles over many
    points), for `tasks` tasks: a local pool of at most `tasks` processes, Dask's executor on a (local) cluster, or
    None for a plain loop (one job, or at most one task). On an interrupt, tasks not yet started are cancelled."""
    _check_run_options(kind, scheduler)
    workers = min(jobs, tasks)
    if kind == "dask" and workers >= 1:
        client, cluster = dask_client(workers, scheduler)
        try:
            with spread_on(DaskSpread(client)):
                yield client.get_executor()
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    elif kind == "process" and workers > 1:
        pool = concurrent.futures.ProcessPoolExecutor(max_workers=workers, initializer=as_worker)
        try:
            yield pool
        finally:
            pool.shutdown(wait=True, cancel_futures=True)
    else:
        yield None


def make_executor(kind: str, jobs: int, scheduler: str | None, tasks: int, seconds: float | None = None) -> Executor:
    """The executor for `--executor kind --jobs jobs [--scheduler ADDRESS]`, for `tasks` proofs to run: never more
    workers than tasks, and none when every claim is already proven; each proof within `seconds` (if given)."""
    _check_run_options(kind, scheduler)
    workers = min(jobs, tasks)
    executor: Executor
    if kind == "dask" and workers >= 1:
        executor = DaskExecutor(workers, scheduler)
    else:
        executor = ProcessPoolExecutor(workers) if workers > 1 else InProcessExecutor()
    executor.seconds = seconds
    return executor


def _holder_sooner(executor: Executor, shares: str, running: Mapping[Hashable, str],
                   started: Mapping[Hashable, float]) -> bool:
    """Whether the busy worker holding the intermediate `shares` is expected (EXPECTED_SECONDS) to finish its claim
    before a cold worker would have computed the intermediate again (the longest claim that shares it): then a claim
    reading it waits for that worker instead of taking a free one."""
    task = executor.holder_task(shares)
    if task is None or task not in running:
        return False
    left = expected_seconds(REGISTRY[running[task]]) - (time.monotonic() - started[task])
    return left < max(expected_seconds(c) for c in REGISTRY.values() if c.shares == shares)


def run_graph(claim_ids: Iterable[str], executor: Executor, on_done: Callable[[Certificate], None] = lambda cert: None,
              values: bool = True) -> dict[str, Certificate]:
    """Prove `claim_ids` and the claims they cite, each at most once per run (the run's cache), dependencies first,
    up to `executor.slots` at a time (the longest chains of citations first, `critical_path_first`; claims sharing
    an intermediate one after the other, so that the worker that computed it proves the next); `on_done` sees each
    certificate of `claim_ids` as it completes. Every certificate of an unperturbed claim goes into the run's cache,
    except one whose exact values stayed with its worker: without `values` only the claims that another claim of the
    run cites bring their values back."""
    load_all()
    wanted = list(dict.fromkeys(claim_ids))
    order = in_dependency_order(wanted, REGISTRY)
    done: dict[str, Certificate] = {}
    for cid in order:
        cert = cached(cid)
        if cert is not None:
            done[cid] = cert
            if cid in wanted:
                on_done(cert)
    pending = [cid for cid in order if cid not in done]
    cited = {u for cid in pending for u in REGISTRY[cid].uses}
    if executor.slots > 1:       # the longest chains of expected seconds start first
        pending = critical_path_first(pending, REGISTRY, expected_seconds)
    running: dict[Hashable, str] = {}
    started: dict[Hashable, float] = {}
    finished: list[Certificate] = []   # reported to on_done once the free workers have their next claims (printing
                                       # a certificate's formulas, with --jsonl, can take seconds)

    def report() -> None:
        while finished:
            on_done(finished.pop(0))
    try:
        while pending or running:
            held = {REGISTRY[cid].shares for cid in running.values()}     # one claim at a time per shared intermediate
            ready = [cid for cid in pending if all(u in done for u in REGISTRY[cid].uses)]
            # a claim whose intermediate a free worker holds goes first (to that worker); one whose intermediate only
            # a busy worker holds comes last, so that another claim takes the free slot while it waits for that worker
            where = {cid: executor.holder(REGISTRY[cid].shares) if REGISTRY[cid].shares else None for cid in ready}
            for cid in sorted(ready, key=lambda c: {"idle": 0, None: 1, "busy": 2}[where[c]]):
                shares = REGISTRY[cid].shares
                if len(running) >= executor.slots or (shares and shares in held):
                    continue
                if where[cid] == "busy" and _holder_sooner(executor, shares, running, started):
                    continue
                handle = executor.submit(cid, {u: done[u] for u in REGISTRY[cid].uses}, values or cid in cited)
                running[handle], started[handle] = cid, time.monotonic()
                pending.remove(cid)
                held.add(shares)
            report()
            for handle, cert in executor.wait(list(running)):
                cid = running.pop(handle)
                started.pop(handle, None)
                done[cid] = cert
                if not cert.values_withheld:
                    remember([cert])
                if cid in wanted:
                    finished.append(cert)
    finally:
        report()
    return {cid: done[cid] for cid in wanted}
