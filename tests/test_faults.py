"""Faults and bad input, second round (issue 23, items 4 and 6): limits are exit 4 with their own JSON, special files
and special targets are refused, output errors are clean, numbers are ASCII and exact up to the documented limits,
names do not shadow, workers never outnumber tasks. Every test is fast; those that could hang run in a subprocess
with a generous guard."""
from __future__ import annotations

import argparse
import json
import os
import signal
import stat
import subprocess
import sys
from pathlib import Path

import pytest

from hkproof.cli import main
from hkproof.errors import OutputError, ResourceLimitError

ROOT = Path(__file__).resolve().parents[1]
BENGALI_FOUR = "\u09ea"
BASIS = "x1**2, x2**2, x3**2, 1"


def run_json(capsys, *args: str) -> tuple[int, dict]:
    code = main([*args, "--json"])
    return code, json.loads(capsys.readouterr().out)


def hk(*args: str, stdout=subprocess.PIPE, timeout: float = 120) -> subprocess.CompletedProcess:
    """The command line in a child process (for what could hang or must reach a real file descriptor)."""
    return subprocess.run([sys.executable, "-m", "hkproof.cli", *args], stdout=stdout, stderr=subprocess.PIPE,
                          text=True, timeout=timeout, cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})


# ---- exit code 4: a limit is not bad input -------------------------------------------------------------------
def test_candidate_cofactor_limit_is_a_resource_limit():
    from hkproof.hk.darboux import Cofactor, candidate_cofactors
    with pytest.raises(ResourceLimitError, match="432 candidate cofactors") as err:
        candidate_cofactors(Cofactor((2, 2, 3, 3, 2)))          # 3 * 3 * 4 * 4 * 3 = 432 > 400
    assert err.value.limit == "400 candidate cofactors" and "no option" in err.value.raise_with


def test_a_limit_exits_4_with_its_json(capsys, monkeypatch):
    import hkproof.commands.measure as measure

    def too_large(*args, **kwargs):
        raise ResourceLimitError("too large", limit="400 candidate cofactors", raise_with="no option raises it")

    monkeypatch.setattr(measure, "search_darboux", too_large)
    code, payload = run_json(capsys, "measure", "lotka-volterra")
    assert code == 4
    assert payload == {"error": "ResourceLimitError", "message": "too large", "limit": "400 candidate cofactors",
                       "raise_with": "no option raises it"}
    assert main(["measure", "lotka-volterra"]) == 4
    assert capsys.readouterr().err == "hkproof: error: too large\n"


def test_an_exhausted_budget_names_its_limit():
    from hkproof.budget import Budget
    from hkproof.errors import BudgetExhausted
    with pytest.raises(BudgetExhausted) as err:
        Budget(0.0, raise_with="--seconds S").check("testing")
    assert err.value.limit == "a time budget of 0 s" and err.value.raise_with == "--seconds S"


def test_out_of_memory_is_a_limit_not_a_bug(capsys, monkeypatch):
    import hkproof.commands.maps as maps

    def exhausted(name):
        raise MemoryError

    monkeypatch.setattr(maps, "kahan_map", exhausted)
    code, payload = run_json(capsys, "map", "euler-top")
    assert code == 4 and payload["error"] == "ResourceLimitError" and "out of memory" in payload["message"]


def test_a_keyboard_interrupt_without_a_signal_is_not_an_interrupt(capsys, monkeypatch):
    """numpy's OpenBLAS raises KeyboardInterrupt when it cannot start its threads under a tight limit."""
    import hkproof.commands.maps as maps

    def library_gives_up(name):
        raise KeyboardInterrupt

    monkeypatch.setattr(maps, "kahan_map", library_gives_up)
    code, payload = run_json(capsys, "map", "euler-top")
    assert code == 4 and "no interrupt signal" in payload["message"]


# ---- report --write --------------------------------------------------------------------------------------------
def test_report_write_refuses_what_is_not_a_regular_file(tmp_path, capsys):
    link = tmp_path / "link.md"
    link.symlink_to(tmp_path / "elsewhere.md")
    fifo = tmp_path / "fifo.md"
    os.mkfifo(fifo)
    for target, why in ((link, "symbolic link"), (fifo, "not a regular file"), (Path(os.devnull), "not a regular")):
        assert main(["report", "--write", str(target)]) == 2
        assert why in capsys.readouterr().err
    assert link.is_symlink() and stat.S_ISFIFO(fifo.lstat().st_mode) and stat.S_ISCHR(os.stat(os.devnull).st_mode)


@pytest.mark.skipif(not Path("/proc/self").exists(), reason="needs /proc")
def test_report_write_tries_to_create_a_file_up_front(capsys):
    """Root passes every access() check, yet /proc takes no new file: the check creates one."""
    assert main(["report", "--write", "/proc/hkproof-theorems.md"]) == 2
    assert "no file can be created" in capsys.readouterr().err


def _disk_full(monkeypatch, tmp_path: Path) -> Path:
    """Make the temporary file of write_atomically a file on a full device (/dev/full); its path is returned."""
    import hkproof.commands.report as report
    temporary = tmp_path / ".theorems.md.x.tmp"

    def mkstemp(**kwargs):
        temporary.write_text("")
        return os.open("/dev/full", os.O_WRONLY), str(temporary)

    monkeypatch.setattr(report.tempfile, "mkstemp", mkstemp)
    return temporary


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_full_disk_during_report_write_is_a_clean_limit(tmp_path, monkeypatch, capsys):
    from hkproof.commands.report import write_atomically
    target = tmp_path / "theorems.md"
    target.write_text("old")
    temporary = _disk_full(monkeypatch, tmp_path)
    with pytest.raises(ResourceLimitError, match="No space left"):
        write_atomically(target, "new" * 10_000)
    assert target.read_text() == "old" and not temporary.exists()


def test_an_interrupted_write_leaves_no_temporary_file(tmp_path, monkeypatch):
    from hkproof.commands import report
    from hkproof.orchestration.interrupts import Interrupted

    def killed(src, dst):
        raise Interrupted(signal.SIGTERM)

    monkeypatch.setattr(report.os, "replace", killed)
    target = tmp_path / "theorems.md"
    with pytest.raises(KeyboardInterrupt):
        report.write_atomically(target, "text")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
@pytest.mark.parametrize("flag", ["--json", None])
def test_output_to_a_full_device_is_a_clean_error(flag):
    with open("/dev/full", "w") as full:
        out = hk("systems", *([flag] if flag else []), stdout=full)
    assert out.returncode == 4 and "Traceback" not in out.stderr and "Exception ignored" not in out.stderr
    assert out.stderr.startswith("hkproof: error: cannot write the standard output: No space left")


def test_an_output_error_that_is_no_full_disk_is_exit_2():
    import errno

    from hkproof.orchestration.output import output_error
    assert isinstance(output_error(OSError(errno.EBADF, "Bad file descriptor"), "x"), OutputError)
    assert isinstance(output_error(OSError(errno.ENOSPC, "No space left on device"), "x"), ResourceLimitError)


def _waits_on(kernel_function: str, pid: int) -> bool | None:
    """Whether the process `pid` sleeps in a kernel function named like `kernel_function` (Linux /proc/PID/wchan:
    pipe_write, or anon_pipe_write on newer kernels); None where that cannot be seen (no /proc, or a kernel that
    hides where a process sleeps), and then the caller cannot wait for the state."""
    try:
        wchan = Path(f"/proc/{pid}/wchan").read_text().strip()
        state = Path(f"/proc/{pid}/stat").read_text().rpartition(")")[2].split()[0]
    except (OSError, IndexError):
        return None
    if kernel_function in wchan:
        return True
    return None if state == "S" and wchan in ("", "0") else False


def test_a_line_is_written_whole_when_a_signal_interrupts_it():
    """CPython's text layer drops the rest of a long line when a signal interrupts the write to a full pipe."""
    child = ("import signal, sys, time\n"
             "from hkproof.orchestration.output import emit\n"
             "signal.signal(signal.SIGUSR1, lambda s, f: None)\n"
             "emit('ready')\n"
             "emit('0' * 300000)\n")
    proc = subprocess.Popen([sys.executable, "-c", child], stdout=subprocess.PIPE, bufsize=0, cwd=ROOT,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert proc.stdout.readline() == b"ready\n"
    import time
    deadline = time.monotonic() + 300      # a hang guard, not a timing claim
    while (blocked := _waits_on("pipe_write", proc.pid)) is False and time.monotonic() < deadline:
        time.sleep(0.01)                   # until the child waits on the full pipe (a state, not a time)
    if blocked is None:
        time.sleep(0.5)                    # the state cannot be seen here: most likely reached by then
    proc.send_signal(signal.SIGUSR1)
    out, _ = proc.communicate(timeout=60)
    assert out == b"0" * 300000 + b"\n"


# ---- SYSTEM files: regular files of bounded size ---------------------------------------------------------------
def test_a_fifo_as_system_is_refused_at_once(tmp_path):
    fifo = tmp_path / "system.toml"
    os.mkfifo(fifo)
    out = hk("map", str(fifo), "--json", timeout=60)
    assert out.returncode == 2 and "not a regular file" in json.loads(out.stdout)["message"]


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_endless_devices_as_system_are_refused(device):
    if not Path(device).exists():
        pytest.skip(f"no {device}")
    out = hk("map", device, timeout=60)
    assert out.returncode == 2 and "not a regular file" in out.stderr


def test_a_huge_system_file_is_refused_before_it_is_read(tmp_path, capsys):
    big = tmp_path / "big.toml"
    with open(big, "wb") as fh:
        fh.truncate(10_000_001)               # sparse: no disk space used
    code, payload = run_json(capsys, "map", str(big))
    assert code == 2 and "more than 10000000 bytes" in payload["message"]


def test_deeply_nested_toml_is_bad_input(tmp_path, capsys):
    deep = tmp_path / "deep.toml"
    deep.write_text("variables = " + "[" * 5000 + "]" * 5000 + "\n")
    code, payload = run_json(capsys, "map", str(deep))
    assert code == 2 and payload["error"] == "ParseError" and "too deeply" in payload["message"]


def test_too_many_variables_is_a_documented_limit(tmp_path, capsys):
    names = [f"x{i}" for i in range(65)]
    system = tmp_path / "wide.toml"
    system.write_text(f"variables = {json.dumps(names)}\n[rhs]\n" + "".join(f'{v} = "{v}"\n' for v in names))
    code, payload = run_json(capsys, "map", str(system))
    assert code == 4 and payload["limit"] == "64 phase variables"


# ---- numbers: exact up to the documented 10 000 digits, ASCII only ----------------------------------------------
def test_literals_beyond_pythons_int_string_limit_are_read(capsys):
    code, payload = run_json(capsys, "integral", "euler-top", "x1 + " + "7" * 9_999)
    assert code == 1 and payload["verdict"] == "refuted"
    code, payload = run_json(capsys, "integral", "euler-top", "7" * 9_999 + "/3")
    import flint
    assert code == 0 and payload["expr"] == str(flint.fmpz("7" * 9_999) // 3)
    code, payload = run_json(capsys, "integral", "euler-top", "x1 + " + "7" * 10_001)
    assert code == 2 and payload["error"] == "FormulaTooLargeError"


@pytest.mark.parametrize("args", [
    ["integral", "euler-top", f"x1 + {BENGALI_FOUR}"],
    ["integral", "euler-top", "x1", "--param", f"a1={BENGALI_FOUR}"],
    ["integral", "euler-top", "x1", "--seed", BENGALI_FOUR],
    ["scan", "euler-top", "--basis", BASIS, "--points", BENGALI_FOUR],
    ["scan", "euler-top", "--basis", BASIS, "--seed", BENGALI_FOUR],
    ["prove", "lv-explicit-map", "--jobs", BENGALI_FOUR],
    ["depend", "euler-top", "--target", "T=x1", "--on", "U=x2", "--cap", f"U={BENGALI_FOUR}"],
])
def test_non_ascii_digits_are_no_numbers(capsys, args):
    code, payload = run_json(capsys, *args)
    assert code == 2 and set(payload) == {"error", "message"}


@pytest.mark.parametrize("text", ["nan", "-5", "0", "inf", "", "1e999", BENGALI_FOUR, "5 s"])
def test_a_time_budget_is_a_positive_number_of_seconds(text):
    from hkproof.commands import seconds
    with pytest.raises(argparse.ArgumentTypeError):
        seconds(text)


def test_time_budgets_in_decimals():
    from hkproof.commands import seconds
    assert seconds("2.5") == 2.5 and seconds("60") == 60.0


# ---- names of new quantities shadow nothing ---------------------------------------------------------------------
@pytest.mark.parametrize("args, why", [
    (["relations", "euler-top", "--basis", BASIS, "--names", "a2, a1, c3"], "already a name of the system"),
    (["relations", "euler-top", "--basis", BASIS, "--names", "eps, c2, c3"], "already a name of the system"),
    (["relations", "euler-top", "--basis", BASIS, "--names", "x1, c2, c3"], "already a name of the system"),
    (["relations", "euler-top", "--basis", BASIS, "--names", "c1, c1, c3"], "distinct"),
    (["depend", "euler-top", "--target", "T=x1**2", "--on", "T=x2**2"], "distinct"),
    (["depend", "euler-top", "--target", "T=x1**2", "--on", "U=x2**2", "--on", "U=x3"], "distinct"),
    (["depend", "euler-top", "--target", "a1=x1**2", "--on", "U=x2**2"], "already a name of the system"),
])
def test_names_that_shadow_or_repeat_are_refused(capsys, args, why):
    code, payload = run_json(capsys, *args)
    assert code == 2 and why in payload["message"]


# ---- run options ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize("address", ["", " ", "tcp://host:port", "tcp://host:70000", "tcp://", "a b"])
def test_a_malformed_scheduler_is_a_usage_error(capsys, address):
    code, payload = run_json(capsys, "prove", "lv-explicit-map", "--executor", "dask", "--scheduler", address)
    assert code == 2 and "scheduler address" in payload["message"]


def test_a_blank_scheduler_from_python_starts_no_cluster():
    pytest.importorskip("distributed")
    from hkproof.errors import HKProofError
    from hkproof.orchestration.execution import dask_client
    with pytest.raises(HKProofError, match="empty"):
        dask_client(1, "")


def test_workers_never_outnumber_tasks(monkeypatch):
    from hkproof.orchestration import execution
    with execution.map_executor("process", 8, None, 2) as pool:
        assert pool._max_workers == 2
    for tasks in (0, 1):
        with execution.map_executor("process", 8, None, tasks) as pool:
            assert pool is None
    assert isinstance(execution.make_executor("process", 8, None, 1), execution.InProcessExecutor)
    started = []
    monkeypatch.setattr(execution, "DaskExecutor",
                        lambda jobs, scheduler: started.append(jobs) or execution.InProcessExecutor())
    monkeypatch.setattr(execution, "dask_client", lambda jobs, scheduler: started.append(jobs) or (_Client(), None))
    execution.make_executor("dask", 8, None, 3)
    with execution.map_executor("dask", 8, None, 2):
        pass
    assert started == [3, 2]


class _Client:
    def get_executor(self):
        return None

    def nthreads(self):                 # DaskSpread counts the cluster's slots
        return {"worker": 1}

    def close(self):
        pass


def test_scan_hands_out_tasks_by_chunks():
    from hkproof.experiments.scan import parallel_tasks
    assert [parallel_tasks(n) for n in (1, 15, 16, 17, 100)] == [0, 0, 4, 5, 25]


# ---- mpmath at high precision ----------------------------------------------------------------------------------
@pytest.mark.parametrize("digits", ["170", "400"])
def test_mpmath_tolerances_follow_the_precision(capsys, digits):
    code, payload = run_json(capsys, "scan", "euler-top", "--basis", BASIS, "--arithmetic", "mpmath", "--digits",
                             digits, "--points", "2", "--eps", "1/3")
    assert code == 0 and payload["dimension"] == 2
