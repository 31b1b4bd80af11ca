"""The parts of one proof on Dask workers (`budget.spread_on`, `orchestration.execution.DaskSpread`): a real lattice
identity checked by forked children and by a local Dask cluster of 1 and 2 workers, its finest task graph (one
task per value of the first lattice name) timed task by task, and what 4 to 64 workers would give by that graph's
critical path; and the whole `discover` command on 1 and 2 Dask workers. Writes the section "Beyond one machine"
of docs/performance-frontier.md (between its markers).

    python benchmarks/spread.py          # about 5 minutes on 2 cores

The identity is the first row with an iterate that `discover so4-euler-top` meets (row i = 1, captured from the
run; eps and a1 set to 1 by the weighted homogeneity, a2, a3 on the principal lattice). Every check runs in this
process one after the other, each with a fresh cluster; times are wall clock.
"""
from __future__ import annotations

import argparse
import heapq
import platform
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import flint

from hkproof.algebra.lattice_identity import plan_lattice, vanishes_on_lattice
from hkproof.algebra.ring import cores
from hkproof.budget import Budget, spread_on
from hkproof.hk import row_check
from hkproof.orchestration.execution import DaskSpread, dask_client
from hkproof.pipelines.discover import discover

from docs_section import write_section

DOC = Path(__file__).resolve().parents[1] / "docs" / "performance-frontier.md"
SECTION = "## Beyond one machine"
WORKERS = (1, 2, 4, 8, 16, 64)
HONEST = row_check.decide_identity
CONSOLE_SCRIPT = "import sys; from hkproof.cli import main; sys.exit(main())"


class _Captured(BaseException):
    """Carries the first row identity with parameters out of the discover run (nothing catches a BaseException)."""


def capture() -> tuple[Any, ...]:
    """(terms, factors, names, free) of the first row identity with parameters that `discover so4-euler-top` meets."""
    def spy(terms, factors, names, free, route, what, where):
        if free[1:]:
            raise _Captured(terms, factors, names, free, what)
        return HONEST(terms, factors, names, free, route, what, where)
    row_check.decide_identity = spy
    try:
        discover("so4-euler-top", 2, budget=Budget(1200))
    except _Captured as found:
        return found.args
    finally:
        row_check.decide_identity = HONEST
    raise SystemExit("discover so4-euler-top met no row identity with parameters")


def timed(fn, *args, **kwargs) -> tuple[Any, float]:
    start = time.perf_counter()
    value = fn(*args, **kwargs)
    return value, time.perf_counter() - start


def on_dask(workers: int, terms, factors, plan, parts: int) -> tuple[bool, float, list[float]]:
    """(verdict, wall, seconds of each task) of the lattice on a fresh local cluster of `workers` processes."""
    client, cluster = dask_client(workers, None)
    try:
        spread = DaskSpread(client)
        with spread_on(spread):
            (holds, _), wall = timed(vanishes_on_lattice, terms, factors, plan, jobs=parts)
        return holds, wall, spread.stages[-1][1]
    finally:
        client.close()
        cluster.close()


def makespan(tasks: list[float], workers: int) -> float:
    """Longest-processing-time-first schedule of `tasks` on `workers`: the time of the busiest worker."""
    loads = [0.0] * workers
    for t in sorted(tasks, reverse=True):
        heapq.heapreplace(loads, loads[0] + t)
    return max(loads)


def command(jobs: int) -> float:
    """Wall time of `hkproof discover so4-euler-top --executor dask --jobs N` (a fresh process)."""
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", CONSOLE_SCRIPT, "discover", "so4-euler-top", "--executor", "dask",
                    "--jobs", str(jobs), "--no-progress", "--seconds", "1200"], check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - start


def section(rows: dict[str, Any]) -> str:
    plan, tasks = rows["plan"], rows["tasks"]
    overhead = max(0.0, rows["fine"][1] - makespan(tasks, 2))
    out = [SECTION, "",
           f"Measured by `benchmarks/spread.py` in one run on {platform.node() or 'this machine'} ({cores()} cores, "
           f"python-flint {flint.__version__}), {time.strftime('%Y-%m-%d')}. The identity: {rows['what']} of "
           f"`discover so4-euler-top` ({rows['sizes'][0]} terms in its largest T, {rows['sizes'][1]} in its largest "
           f"factor), by the lattice route: {plan.describe()}. Each Dask run starts a fresh local cluster (its start "
           "is not counted); the polynomials travel to the workers as data (`hkproof.algebra.pickling`), scattered "
           "once per worker.", "",
           "| where the lattice's parts run | parts | wall | verdict |", "|---|---|---|---|"]
    for label, (holds, wall, parts) in rows["runs"]:
        out.append(f"| {label} | {parts} | {wall:.2f} s | {holds} |")
    out += ["", f"The finest task graph (one task per value of {plan.lattice[0]}, {len(tasks)} tasks on 2 workers: "
            f"{rows['fine'][1]:.2f} s wall) took {sum(tasks):.2f} s of work in all, the longest task "
            f"{max(tasks):.2f} s: the graph's critical path is that task plus the fixed cost of the run (scatter, "
            f"scheduling: {overhead:.2f} s here, the wall time less the two workers' schedule). What more workers "
            "would give, by the measured tasks (longest first on the least loaded worker, plus that fixed cost):", "",
            "| workers | " + " | ".join(str(w) for w in WORKERS) + " |",
            "|---|" + "---|" * len(WORKERS),
            "| projected wall | " + " | ".join(f"{overhead + makespan(tasks, w):.2f} s" for w in WORKERS) + " |",
            "", "The whole command on a local Dask cluster (`hkproof discover so4-euler-top --executor dask`): "
            f"{rows['command'][1]:.1f} s with 1 worker, {rows['command'][2]:.1f} s with 2 "
            f"({rows['command'][1] / rows['command'][2]:.2f}x)."]
    return "\n".join(out) + "\n"


def main() -> None:
    argparse.ArgumentParser(description=__doc__).parse_args()
    terms, factors, names, free, what = capture()
    plan = plan_lattice(terms, factors, names, free, tuple(free[1:]))
    first = min([plan.degree, *plan.degrees[:1]]) + 1
    rows: dict[str, Any] = {"plan": plan, "what": what, "runs": [],
                            "sizes": (max(len(t) for t in terms.values()), max(len(f) for f in factors))}
    for jobs in (1, 2):
        (holds, _), wall = timed(vanishes_on_lattice, terms, factors, plan, jobs=jobs)
        rows["runs"].append(("this process" if jobs == 1 else "2 forked children", (holds, wall, jobs)))
    for workers in (1, 2):
        holds, wall, _ = on_dask(workers, terms, factors, plan, 4 * workers)
        rows["runs"].append((f"Dask, {workers} worker{'s' if workers > 1 else ''}", (holds, wall, 4 * workers)))
    holds, wall, tasks = on_dask(2, terms, factors, plan, first)
    rows["runs"].append(("Dask, 2 workers, one task per value", (holds, wall, first)))
    rows["fine"], rows["tasks"] = (holds, wall), tasks
    print(rows["runs"], flush=True)
    rows["command"] = {jobs: command(jobs) for jobs in (1, 2)}
    print(write_section(DOC, "spread", section(rows).rstrip("\n").split("\n")))
    print(f"wrote {DOC}")


if __name__ == "__main__":
    main()
