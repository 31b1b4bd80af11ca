"""Benchmark of `hkproof poisson` (docs/performance-poisson.md, docs/poisson.md): unknowns, rows and seconds per
system, class D and degree.

python benchmarks/poisson.py [SYSTEM DEGREE ...]          D = 1 only (default: lotka-volterra 2, euler-top 3, clebsch 5)
python benchmarks/poisson.py --classes [SYSTEM DEGREE ...] every candidate D (hkproof.pipelines.poisson_candidates)
"""
from __future__ import annotations

import resource
import sys
import time

from hkproof.budget import Budget
from hkproof.dynamics.catalogue import kahan_map
from hkproof.pipelines.poisson import search_poisson, with_integrals


def run(system: str, degree: int, classes: bool, seconds: float = 36000.0) -> None:
    start = time.perf_counter()
    with Budget(seconds).active():
        report = with_integrals(kahan_map(system), degree) if classes else search_poisson(kahan_map(system), degree)
    total = time.perf_counter() - start
    peak = max(resource.getrusage(who).ru_maxrss for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)) / 2**20
    print(f"## {system}, deg Q <= {degree}: {len(report.structures)} structure(s), {len(report.excluded)} "
          f"exclusion(s), {total:.2f} s, peak RSS {peak:.2f} GB (the process or a rank's child); stages "
          + ", ".join(f"{k} {v:.2f} s" for k, v in report.seconds.items()) + (f"; STOPPED: {report.stopped}"
                                                                              if report.stopped else ""))
    print("| D | degree | unknowns | blocks | rows | kernel | seconds (rows + rank mod p) |")
    print("|---|---|---|---|---|---|---|")
    for c in report.costs:
        print(f"| {c['denominator']} | {c['degree']} | {c['columns']} | {c['blocks']} | {c['rows']} | {c['kernel']} | "
              f"{c['seconds']:.2f} |")
    for e in report.excluded:
        print(f"- excluded ({e.certificate.status.label}): D = {e.name}, deg Q <= {e.degree}")
    for s in report.structures:
        print(f"- {s.status.label}: D = {s.bivector.denominator}, poisson {s.poisson}, rank {s.rank}; proof steps "
              + ", ".join(f"{st.name} {st.seconds:.2f} s" for st in s.certificate.steps))
    sys.stdout.flush()


if __name__ == "__main__":
    argv = sys.argv[1:]
    by_class = "--classes" in argv
    args = [a for a in argv if a != "--classes"] or ["lotka-volterra", "2", "euler-top", "3", "clebsch", "5"]
    for name, deg in zip(args[::2], args[1::2]):
        run(name, int(deg), by_class)
