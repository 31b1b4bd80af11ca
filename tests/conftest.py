"""Shared fixtures, and a summary of every theorem's status and time at the end of the test report."""
from __future__ import annotations

THEOREM_RESULTS: list[tuple[str, str, float]] = []


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if not THEOREM_RESULTS:
        return
    terminalreporter.section("hkproof theorems")
    first = {}
    for claim_id, status, seconds in THEOREM_RESULTS:
        first.setdefault(claim_id, (status, seconds))
    width = max(len(i) for i in first)
    for claim_id, (status, seconds) in first.items():
        terminalreporter.write_line(f"{claim_id:<{width}}  {status:<22} {seconds:8.3f} s")


def run_group_script(group: str, monkeypatch, capsys) -> tuple[int, list[dict]]:
    """Run proofs/<group>.py in this process (its claims are proven once per test run, like every other test's) with
    --jobs 1 --no-slow --jsonl: the exit code and the JSON lines it printed (certificates, then the summary)."""
    import json
    import runpy
    from pathlib import Path

    import pytest

    script = Path(__file__).resolve().parents[1] / "proofs" / f"{group.replace('-', '_')}.py"
    monkeypatch.setattr("sys.argv", [str(script), "--jobs", "1", "--no-slow", "--jsonl"])
    with pytest.raises(SystemExit) as stop:
        runpy.run_path(str(script), run_name="__main__")
    lines = [json.loads(line) for line in capsys.readouterr().out.splitlines() if line.startswith("{")]
    return int(stop.value.code or 0), lines


def assert_group_certified(group: str, monkeypatch, capsys) -> None:
    """The group's script exits 0, prints one certificate per claim of the group (slow ones skipped), each at its
    promised status, and a summary line without failures."""
    from hkproof.orchestration.registry import select

    code, lines = run_group_script(group, monkeypatch, capsys)
    *certs, summary = lines
    assert code == 0 and summary["exit_code"] == 0 and not summary["failed"], summary
    assert {c["id"] for c in certs} == {c.id for c in select(groups=[group], include_slow=False)}
