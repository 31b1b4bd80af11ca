"""Benchmark of `hkproof poisson` (docs/performance-poisson.md): unknowns, rows and seconds per system, D and degree.

python benchmarks/poisson.py [SYSTEM DEGREE ...]   (default: lotka-volterra 2, euler-top 3, clebsch 5)
"""
from __future__ import annotations

import sys
import time

from hkproof.budget import Budget
from hkproof.dynamics.catalogue import kahan_map
from hkproof.pipelines.poisson import search_poisson


def run(system: str, degree: int, seconds: float = 1200.0) -> None:
    start = time.perf_counter()
    with Budget(seconds).active():
        report = search_poisson(kahan_map(system), degree)
    total = time.perf_counter() - start
    print(f"## {system}, D = 1, deg Q <= {degree}: {len(report.structures)} structure(s), "
          f"{len(report.excluded)} exclusion(s), {total:.2f} s; stages "
          + ", ".join(f"{k} {v:.2f} s" for k, v in report.seconds.items()) + (f"; STOPPED: {report.stopped}"
                                                                              if report.stopped else ""))
    print("| degree | unknowns | blocks | rows | kernel | seconds (rows + rank mod p) |")
    print("|---|---|---|---|---|---|")
    for c in report.costs:
        print(f"| {c['degree']} | {c['columns']} | {c['blocks']} | {c['rows']} | {c['kernel']} | {c['seconds']:.2f} |")
    for s in report.structures:
        print(f"- {s.status.label}: poisson {s.poisson}, rank {s.rank}; proof steps "
              + ", ".join(f"{st.name} {st.seconds:.2f} s" for st in s.certificate.steps))
    sys.stdout.flush()


if __name__ == "__main__":
    args = sys.argv[1:] or ["lotka-volterra", "2", "euler-top", "3", "clebsch", "5"]
    for name, deg in zip(args[::2], args[1::2]):
        run(name, int(deg))
