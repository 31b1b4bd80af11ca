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
