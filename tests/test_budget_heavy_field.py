"""Budgets and SIGTERM on a five-dimensional cubic Hamiltonian field (issue 36, item 6; docs/examples/
cubic-hamiltonian-5d.toml): `discover --degree 6` ends within --seconds plus a grace, the budget reported (it ran past
880 s with --seconds 100 while a loop of the dependence plan never checked the budget); `integral` of the modified
Hamiltonian stops with exit 4 at a small --seconds; a SIGTERM ends a long `integral` at once (its FLINT computation
runs in a forked child of Budget.call, and the parent waits where a signal reaches it).

The time bounds are generous on purpose: they separate "stopped by the budget or the signal" from "ran to the end"
(minutes), never a fast machine from a slow one. The SIGTERM tests wait for a state (the forked child exists), not
for a time, so that they pass on a loaded machine."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from hkproof.budget import Budget

ROOT = Path(__file__).resolve().parents[1]
FIELD = str(ROOT / "docs" / "examples" / "cubic-hamiltonian-5d.toml")
H = "x1*x2*x3 + x3*x4*x5 + x1**2*x4 - x2*x5**2 + x1*x5"
CONSOLE_SCRIPT = "import sys; from hkproof.cli import main; sys.exit(main())"
GRACE = 120.0          # seconds past --seconds: startup, the stages after a stop, a loaded machine (not a timing claim)
STARTED_WITHIN = 600   # seconds: a hang guard while waiting for a state
STOPPED_WITHIN = 60    # seconds after a SIGTERM: "a few seconds", with room for a loaded machine


@pytest.fixture(scope="module")
def h_tilde() -> str:
    """H~ of the field (288 terms of degree 7 over a quartic): h o f = h is one FLINT computation of about 25 s (a
    compose of 2.7 million terms and a cross-multiplication); building H~ takes about a second."""
    from hkproof.algebra.fraction import Frac
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.hk.modified_hamiltonian import modified_hamiltonian
    f = kahan_map(FIELD)
    return str(modified_hamiltonian(f, Frac.parse(f.ring, H)))


def _run(argv: list[str]) -> tuple[int, str, str, float]:
    start = time.monotonic()
    proc = subprocess.run([sys.executable, "-c", CONSOLE_SCRIPT, *argv], cwd=ROOT, capture_output=True, text=True,
                          timeout=STARTED_WITHIN)
    return proc.returncode, proc.stdout, proc.stderr, time.monotonic() - start


def _children(pid: int) -> list[int]:
    try:
        return [int(c) for c in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        return []


def _gone(pid: int) -> bool:
    """No such process, or a zombie (reaped by init once its parent has ended)."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().split(")")[-1].split()[0] == "Z"
    except OSError:
        return True


def test_discover_on_the_five_dimensional_field_ends_within_its_budget():
    code, out, err, elapsed = _run(["discover", FIELD, "--degree", "6", "--seconds", "20", "--json"])
    assert code == 0, err[-800:]
    report = json.loads(out)
    assert report["complete"] is False
    assert any("the time budget of 20 s ran out" in line for line in report["covered"])
    assert elapsed < 20 + GRACE


def test_integral_of_the_modified_hamiltonian_stops_with_exit_4(h_tilde):
    code, out, err, elapsed = _run(["integral", FIELD, h_tilde, "--seconds", "3", "--json"])
    payload = json.loads(out)
    assert code == 4 and payload["error"] == "BudgetExhausted", err[-800:]
    assert "time budget of 3 s" in payload["limit"] and "--seconds" in payload["raise_with"]
    assert elapsed < 3 + GRACE


def test_sigterm_ends_a_long_integral_at_once(h_tilde):
    """No --seconds: the check still runs in a forked child (the command line answers SIGTERM by a handler), which is
    the state waited for; the SIGTERM is answered by the parent at once and the child is killed."""
    if not Path(f"/proc/{os.getpid()}/task/{os.getpid()}/children").exists():
        pytest.skip("needs Linux /proc to see the forked child")
    proc = subprocess.Popen([sys.executable, "-c", CONSOLE_SCRIPT, "integral", FIELD, h_tilde], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + STARTED_WITHIN
    children: list[int] = []
    while not children:
        if proc.poll() is not None:
            pytest.fail(f"integral ended (exit {proc.returncode}) before forking: {proc.communicate()[1][-800:]!r}")
        assert time.monotonic() < deadline, "integral never forked its check"
        children = _children(proc.pid)
        time.sleep(0.02)
    sent = time.monotonic()
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=STARTED_WITHIN)
    assert time.monotonic() - sent < STOPPED_WITHIN
    assert proc.returncode == 130, err.decode()[-800:]
    assert "interrupted (SIGTERM)" in err.decode() and "Traceback" not in err.decode()
    assert all(_gone(c) for c in children)


def _signal_parent_then_wait() -> None:
    os.kill(os.getppid(), signal.SIGTERM)
    time.sleep(600)


class _Stopped(Exception):
    pass


def _stop(signum, frame):
    raise _Stopped


def test_budget_call_forks_where_sigterm_is_handled_and_answers_it_at_once():
    """Without a deadline Budget.call runs inline, unless SIGTERM runs a Python handler: then in a child, so that a
    SIGTERM (here sent by the child itself: a state, not a time) reaches the parent's handler at once."""
    assert Budget(None).call("asking where", os.getpid) == os.getpid()
    previous = signal.signal(signal.SIGTERM, _stop)
    try:
        assert Budget(None).call("asking where", os.getpid) != os.getpid()
        start = time.monotonic()
        with pytest.raises(_Stopped):
            Budget(None).call("waiting for a signal", _signal_parent_then_wait)
        assert time.monotonic() - start < STOPPED_WITHIN
    finally:
        signal.signal(signal.SIGTERM, previous)
    assert not _children(os.getpid())
