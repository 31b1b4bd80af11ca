"""Interrupt signals: Ctrl-C (SIGINT), SIGTERM and SIGHUP stop a command in the same way. Inside
`interrupts_raised()` each of them raises `Interrupted` (a KeyboardInterrupt naming the signal), so that workers are
stopped, the partial results printed and the exit code is 130. A signal that the process was started with ignored
(a background job of a non-interactive shell, `nohup`) stays ignored.

`interrupts_raised(hold=True)` holds them instead: a signal is recorded, and takes effect only inside
`interrupts_live()` (at its start if it came before). A command that proves claims runs held, and live only while
its claims are proven (`runner.execute`): an interrupt at any moment -- while the command line is read, between
claims, while the answer is printed -- then gives the same document, never an error object in its place nor a
document cut in half.

>>> Interrupted(signal.SIGTERM).label, Interrupted(signal.SIGINT).label, interrupt_label(KeyboardInterrupt())
('SIGTERM', 'Ctrl-C', 'Ctrl-C')
"""
from __future__ import annotations

import signal
import threading
from contextlib import contextmanager
from types import FrameType
from typing import Iterator

from hkproof.errors import Interrupted

__all__ = ["INTERRUPT_SIGNALS", "Interrupted", "as_worker", "from_signal", "interrupt_label", "interrupts_blocked",
           "interrupts_deferred", "interrupts_ignored", "interrupts_live", "interrupts_raised"]

INTERRUPT_SIGNALS: tuple[signal.Signals, ...] = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


def interrupt_label(exc: KeyboardInterrupt) -> str:
    """The label of an interrupt (a bare KeyboardInterrupt is Python's own Ctrl-C)."""
    return exc.label if isinstance(exc, Interrupted) else "Ctrl-C"


def from_signal(exc: KeyboardInterrupt, handled: frozenset[int]) -> bool:
    """Whether `exc` came from an interrupt signal: an Interrupted does; a bare KeyboardInterrupt only where Python's
    own Ctrl-C handler was left in place (`handled`, from interrupts_raised, lacks SIGINT). Otherwise a library
    raised it (numpy's OpenBLAS does when it cannot start its threads under a tight memory limit)."""
    if isinstance(exc, Interrupted):
        return True
    return signal.SIGINT not in handled and signal.getsignal(signal.SIGINT) is signal.default_int_handler


# the signals held since `interrupts_raised(hold=True)` (None: a signal raises at once); main thread only
_held: list[int] | None = None


def _on_interrupt(signum: int, frame: FrameType | None) -> None:
    if _held is not None:
        _held.append(signum)
        return
    raise Interrupted(signum)


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextmanager
def interrupts_raised(hold: bool = False) -> Iterator[frozenset[int]]:
    """Inside the block every interrupt signal left at its default raises Interrupted -- with `hold`, only inside
    `interrupts_live()`; yields the signals so handled (none outside the main thread, where Python cannot install
    handlers)."""
    global _held
    previous = {}
    held = _held
    if _in_main_thread():
        _held = [] if hold else None
        for s in INTERRUPT_SIGNALS:
            if signal.getsignal(s) in (signal.SIG_DFL, signal.default_int_handler):
                previous[s] = signal.signal(s, _on_interrupt)
    try:
        yield frozenset(previous)
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        if _in_main_thread():
            _held = held


@contextmanager
def interrupts_live() -> Iterator[None]:
    """Inside `interrupts_raised(hold=True)`: the interrupt signals raise Interrupted inside the block, and one held
    before it raises at its start. Elsewhere nothing changes."""
    global _held
    held = _held
    if held is None or not _in_main_thread():
        yield
        return
    _held = None
    try:
        if held:
            signum = held[0]
            held.clear()
            raise Interrupted(signum)
        yield
    finally:
        _held = held


def _handled() -> list[signal.Signals]:
    """The interrupt signals that currently run a Python handler (neither ignored nor at the default)."""
    return [s for s in INTERRUPT_SIGNALS if callable(signal.getsignal(s))]


@contextmanager
def interrupts_ignored() -> Iterator[None]:
    """A second interrupt while workers are being stopped is ignored (no traceback from the cleanup)."""
    if not _in_main_thread():
        yield
        return
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in _handled()}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)


@contextmanager
def interrupts_deferred() -> Iterator[None]:
    """An interrupt inside the block takes effect at its end (a line of output is never cut in half)."""
    if not _in_main_thread():
        yield
        return
    caught: list[int] = []
    previous = {s: signal.signal(s, lambda signum, frame: caught.append(signum)) for s in _handled()}
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
    if caught:
        raise Interrupted(caught[0])


@contextmanager
def interrupts_blocked() -> Iterator[None]:
    """Interrupt signals are held back inside the block and delivered at its end. A worker forked inside starts
    with them held, so that none reaches it before `as_worker` has set its own dispositions (it would otherwise run
    the parent's handler in the middle of starting up)."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, INTERRUPT_SIGNALS)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def as_worker() -> None:
    """In a worker process: Ctrl-C and SIGHUP (sent to the whole process group) are left to the parent, which stops
    the workers; SIGTERM (how the parent stops them) ends the worker at once. Then the signals held back since the
    fork (`interrupts_blocked`) come through."""
    for name in ("SIGINT", "SIGHUP"):
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, INTERRUPT_SIGNALS)
