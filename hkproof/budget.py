"""A cooperative budget: a deadline (and a memory ceiling) that long computations check inside their loops.

The one rule, followed everywhere:

1. Code checks the **active** budget: every long loop of hkproof (exact orbits, eliminations, reconstructions, Groebner
   steps, sampling) calls the module-level `check(what)`, which consults the budget active in this thread (none: no
   limit). No check callable is threaded through arguments.
2. Whoever owns a budget activates it: the command line around each command, a pipeline (or an engine given a
   `budget=`) around its work with `with budget.active():`, and **every job that runs in another process** (a worker
   of a pool or of Dask, a job of `Budget.call`) at its entry: a Budget is sent with the job (its deadline travels as
   wall-clock time) and activated there, since the active budget of one process means nothing in another.
3. One long call that no loop can interrupt (a big FLINT compose or gcd) runs through `Budget.call`, in a forked child
   held to the deadline and the memory ceiling.
4. When the deadline has passed, `BudgetExhausted` says what was being done, and the pipeline reports what it covered.
   The front end says how to raise the budget (`raise_with`); nothing below `hkproof.commands` names an option.

>>> b = Budget(None)
>>> b.check("nothing"); b.expired, b.remaining() == float("inf")
(False, True)
>>> Budget(0.0).expired
True
"""
from __future__ import annotations

import math
import os
try:
    import resource
except ImportError:                 # Windows: no rlimits (and no fork: Budget.call runs inline there)
    resource = None  # type: ignore[assignment]
import pickle
import select
import signal
import time
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, Callable, Iterator, Sequence, TypeVar

from hkproof.errors import BudgetExhausted, HKProofError

__all__ = ["Budget", "Spread", "UNLIMITED", "check", "current", "parallel_parts", "spread_on", "spread_slots"]

T = TypeVar("T")

_PAGE_MB = os.sysconf("SC_PAGE_SIZE") / 2**20 if hasattr(os, "sysconf") else 4 / 1024


def resident_mb() -> float | None:
    """This process's resident memory now, in MB (None where /proc is not available)."""
    try:
        with open("/proc/self/statm", "rb") as fh:
            return int(fh.read().split()[1]) * _PAGE_MB
    except (OSError, ValueError, IndexError):
        return None


class Budget:
    """A deadline `seconds` from now (None: no deadline) and a memory ceiling in MB (None: none): `check` compares it
    with this process's resident memory, and a child of `call` may grow its address space by that much at most."""

    def __init__(self, seconds: float | None = None, *, memory_mb: float | None = None,
                 raise_with: str = "a larger budget", _deadline: float | None = None):
        if seconds is not None and (not isinstance(seconds, (int, float)) or math.isnan(seconds) or seconds < 0):
            raise HKProofError(f"a time budget must be a number of seconds >= 0, got {seconds!r}")
        if memory_mb is not None and (math.isnan(memory_mb) or memory_mb <= 0):
            raise HKProofError(f"a memory ceiling must be a positive number of MB, got {memory_mb!r}")
        self.started = time.monotonic()
        self.seconds = seconds
        self.deadline = _deadline if _deadline is not None else (
            math.inf if seconds is None else self.started + seconds)
        self.memory_mb = memory_mb
        self.raise_with = raise_with
        self._memory_checked = 0.0

    def __repr__(self) -> str:
        return f"Budget(seconds={self.seconds}, memory_mb={self.memory_mb})"

    def __getstate__(self) -> dict:
        """Sent to a worker process (or a Dask worker on another machine) with its start and deadline as wall-clock
        times: the monotonic clock of one process means nothing in another."""
        shift = time.time() - time.monotonic()
        return {**self.__dict__, "started": self.started + shift, "deadline": self.deadline + shift}

    def __dask_tokenize__(self) -> tuple:
        """Dask's key for a task that carries this budget: the budget itself (its pickled state holds a wall-clock time,
        which Dask would refuse as a non-deterministic token)."""
        return ("hkproof.Budget", id(self), self.seconds, self.memory_mb)

    def __setstate__(self, state: dict) -> None:
        shift = time.monotonic() - time.time()
        self.__dict__.update(state, started=state["started"] + shift, deadline=state["deadline"] + shift,
                             _memory_checked=0.0)

    @property
    def elapsed(self) -> float:
        return time.monotonic() - self.started

    @property
    def expired(self) -> bool:
        return time.monotonic() >= self.deadline

    def remaining(self) -> float:
        """Seconds left (inf without a deadline, 0 when expired)."""
        return max(0.0, self.deadline - time.monotonic())

    def check(self, doing: str) -> None:
        """Raise BudgetExhausted (saying what was being done) once the deadline or the memory ceiling is passed."""
        now = time.monotonic()
        if now >= self.deadline:
            raise self.out_of_time(doing)
        if self.memory_mb is not None and now - self._memory_checked > 0.2:
            self._memory_checked = now
            used = resident_mb()
            if used is not None and used > self.memory_mb:
                raise BudgetExhausted(f"the memory ceiling of {self.memory_mb:g} MB was passed ({used:.0f} MB) "
                                      f"while {doing} (give {self.raise_with} to go further)",
                                      limit=f"a memory ceiling of {self.memory_mb:g} MB", raise_with=self.raise_with)

    def child(self, seconds: float | None = None, *, share: float | None = None) -> Budget:
        """A budget for one part of the work: at most `seconds` (or `share` of what is left), never past this
        budget's own deadline; the memory ceiling is shared."""
        limit = self.deadline
        now = time.monotonic()
        if seconds is not None:
            limit = min(limit, now + seconds)
        if share is not None and math.isfinite(self.deadline):
            limit = min(limit, now + share * max(0.0, self.deadline - now))
        total = None if not math.isfinite(limit) else max(0.0, limit - now)
        return Budget(total, memory_mb=self.memory_mb, raise_with=self.raise_with, _deadline=limit)

    def out_of_time(self, doing: str) -> BudgetExhausted:
        """The exception of this budget's deadline, saying what was being done (raised by its owner)."""
        return BudgetExhausted(f"the time budget of {self.seconds:g} s ran out while {doing} (give {self.raise_with} "
                               "to go further)", limit=f"a time budget of {self.seconds:g} s", raise_with=self.raise_with)

    def call(self, doing: str, fn: Callable[..., T], *args: Any) -> T:
        """fn(*args), stopped at the deadline even inside one long FLINT call that no check can interrupt: with a
        deadline it runs in a forked child (which shares this process's memory, so big arguments are not copied)
        killed when the deadline passes (BudgetExhausted); the result, and any exception, must be picklable. A plain
        os.fork, so that it works inside daemonic worker processes too (multiprocessing forbids their children).
        Without a deadline it runs in a child too where this process answers SIGTERM or SIGHUP by a Python handler
        (the command line does): Python runs a handler only between bytecodes, so a FLINT call in this process would
        hold a SIGTERM off for as long as it runs, while the parent waiting for its child answers at once (the
        handler's exception kills the child)."""
        if not hasattr(os, "fork") or not (math.isfinite(self.deadline) or _interrupts_handled()):
            return fn(*args)                    # no deadline and no handler to keep responsive, or no fork (Windows)
        return self._in_children(doing, [(fn, args)])[0]

    def call_each(self, doing: str, fn: Callable[[int], T], jobs: int) -> list[T]:
        """[fn(0), ..., fn(jobs - 1)], each in a forked child at the same time (side by side on the cores), with the
        deadline of `call`: every child is killed when it passes (BudgetExhausted), and a child's exception is
        raised here. Under `spread_on(spread)` the parts are tasks of that spread instead (Dask workers, on other
        machines too), each under this budget. One job, or no fork (Windows), runs in this process."""
        spread = _SPREAD.get()
        if jobs > 1 and spread is not None:
            return spread.run(self, doing, fn, jobs)
        if jobs <= 1 or not hasattr(os, "fork"):
            return [fn(k) for k in range(jobs)]
        return self._in_children(doing, [(fn, (k,)) for k in range(jobs)])

    def _in_children(self, doing: str, calls: Sequence[tuple[Callable[..., T], tuple]]) -> list[T]:
        """fn(*args) for each call, each in a forked child (which shares this process's memory, so big arguments are
        not copied), the answers read in order until the deadline; every child is killed and reaped at the end."""
        self.check(doing)
        children: list[tuple[int, Any]] = []
        answers = []
        try:
            for fn, args in calls:
                read_end, write_end = os.pipe()
                held = _hold_interrupts()       # a signal between the fork and `append` would leave the child behind
                try:
                    pid = os.fork()
                    if pid == 0:                # the child: compute, send, leave without any clean-up
                        try:
                            os.close(read_end)
                            _release_interrupts(held)
                            os.dup2(2, 1)    # a library's last words (FLINT aborts on stdout) go to stderr
                            _cap_address_space(self.memory_mb)
                            _call_and_send(write_end, fn, args)
                        finally:
                            os._exit(0)
                    children.append((pid, os.fdopen(read_end, "rb")))
                finally:
                    _release_interrupts(held)
                    os.close(write_end)
            for _, answer in children:
                wait = self.remaining() if math.isfinite(self.deadline) else None
                if not select.select([answer], [], [], wait)[0]:
                    raise self.out_of_time(doing)
                answers.append(answer.read())
        finally:
            for pid, answer in children:
                answer.close()
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                _reap(pid)
        out = []
        for data in answers:
            if not data and self.memory_mb is not None:
                raise BudgetExhausted(f"the process {doing} died without an answer, at the memory ceiling of "
                                      f"{self.memory_mb:g} MB (give {self.raise_with} to go further)",
                                      limit=f"a memory ceiling of {self.memory_mb:g} MB", raise_with=self.raise_with)
            if not data:
                raise HKProofError(f"the process {doing} died without an answer (out of memory?)")
            ok, value = pickle.loads(data)
            if not ok:
                raise value
            out.append(value)
        return out

    @contextmanager
    def active(self) -> Iterator["Budget"]:
        """Make this the budget that `check` consults in this thread (nested budgets: the innermost wins)."""
        token = _ACTIVE.set(self)
        try:
            yield self
        finally:
            _ACTIVE.reset(token)


def _cap_address_space(memory_mb: float | None) -> None:
    """In a child of `Budget.call`: the memory ceiling made hard, so that it holds inside one FLINT call too: the
    address space may grow by `memory_mb` beyond what the child has at the fork (an allocation past it fails, and GMP
    aborts the child, which the parent reports as the ceiling)."""
    if memory_mb is None or resource is None:
        return
    try:
        with open("/proc/self/statm", "rb") as fh:
            size = int(fh.read().split()[0]) * _PAGE_MB
    except (OSError, ValueError, IndexError):
        return
    limit = int((size + memory_mb) * 2**20)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


_INTERRUPTS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


def _hold_interrupts() -> set | None:
    """Hold interrupt signals back (delivered by `_release_interrupts`): the mask to restore (None: no masks)."""
    return signal.pthread_sigmask(signal.SIG_BLOCK, _INTERRUPTS) if hasattr(signal, "pthread_sigmask") else None


def _release_interrupts(held: set | None) -> None:
    if held is not None:
        signal.pthread_sigmask(signal.SIG_SETMASK, held)


def _interrupts_handled() -> bool:
    """Whether SIGTERM or SIGHUP runs a Python handler in this process (hkproof's command line installs one; by
    default both end the process at once, inside a C call too). SIGINT is not asked: Python always handles it."""
    return any(callable(signal.getsignal(getattr(signal, name))) for name in ("SIGTERM", "SIGHUP")
               if hasattr(signal, name))


def _call_and_send(fd: int, fn: Callable[..., Any], args: tuple) -> None:
    """The child of `Budget.call`: fn(*args) written to `fd` as a pickled (True, result) or (False, exception)."""
    try:
        message: tuple[bool, Any] = (True, fn(*args))
    except BaseException as exc:         # noqa: BLE001 - the parent re-raises it
        message = (False, exc)
    try:
        data = pickle.dumps(message)
    except Exception as exc:             # noqa: BLE001 - an unpicklable result or exception
        data = pickle.dumps((False, HKProofError(f"the answer could not be sent back: {type(exc).__name__}: {exc}")))
    with os.fdopen(fd, "wb") as out:
        out.write(data)


def _reap(pid: int) -> None:
    """Wait for a child of `Budget.call` (killed or finished), so that none is left as a zombie."""
    try:
        os.waitpid(pid, 0)
    except ChildProcessError:
        pass


class Spread:
    """Where the parts of one computation (`Budget.call_each`) run instead of forked children: `slots` at once, on
    workers that may be other machines (hkproof.orchestration.execution.DaskSpread). `stages` records, for each call,
    what was done, the seconds of each part and the wall time of the call: the critical path of the run's tasks."""

    slots = 1

    def __init__(self) -> None:
        self.stages: list[tuple[str, list[float], float]] = []

    def run(self, budget: Budget, doing: str, fn: Callable[[int], T], jobs: int) -> list[T]:
        """[fn(0), ..., fn(jobs - 1)] as tasks, each under `budget`; the first task's exception is raised here."""
        raise NotImplementedError


UNLIMITED = Budget(None)
_ACTIVE: ContextVar[Budget] = ContextVar("hkproof_budget", default=UNLIMITED)
_SPREAD: ContextVar[Spread | None] = ContextVar("hkproof_spread", default=None)


@contextmanager
def spread_on(spread: Spread | None) -> Iterator[Spread | None]:
    """Run the parts of `Budget.call_each` in this thread on `spread` (None: forked children, as without it)."""
    token = _SPREAD.set(spread)
    try:
        yield spread
    finally:
        _SPREAD.reset(token)


def parallel_parts(local: int) -> int:
    """How many parts to cut a computation into: `local` (the cores of this machine) without a spread, else four
    per slot of the spread (the scheduler queues them: finer parts balance the load across workers)."""
    spread = _SPREAD.get()
    return local if spread is None else max(local, 4 * spread.slots)


def spread_slots() -> int | None:
    """The slots of the active spread (None: parts run as forked children on this machine)."""
    spread = _SPREAD.get()
    return None if spread is None else spread.slots


def current() -> Budget:
    """The budget active in this thread (UNLIMITED outside any `Budget.active()`)."""
    return _ACTIVE.get()


def check(doing: str) -> None:
    """`current().check(doing)`: the one line a long loop needs.

    >>> with Budget(0.0).active():
    ...     check("a long loop")
    Traceback (most recent call last):
    hkproof.errors.BudgetExhausted: the time budget of 0 s ran out while a long loop (give a larger budget to go further)
    """
    _ACTIVE.get().check(doing)
