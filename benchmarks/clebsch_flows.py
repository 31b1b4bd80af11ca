"""Benchmark (not a test) of the group `clebsch-flows` from scratch, and of the two ideas that made it fast.

    python benchmarks/clebsch_flows.py [--out docs/performance-clebsch-flows.md] [--no-peers]

1. Every claim of the group, proven in one fresh process in dependency order (cited claims of other groups, such as
   `dc-theta`, are proven on the way and timed in the row of the claim that needs them first).
2. Side by side on the same objects: the substitution of the second flow's Theta kernel into its rows
   (`hk.reduced.check_solution`, products with the big rows phi o f) against `hk.row_check` (Horner in the small
   numerators of f); and L_b o f = L_b for every flow by substitution (`check_integral`) against its transport
   from the second flow (`hk.transport`). `--no-peers` skips these (they take about two minutes).
"""
from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.integrals import check_integral
from hkproof.hk.reduced import check_solution
from hkproof.hk.row_check import check_solution_by_rows
from hkproof.orchestration.registry import REGISTRY, load_all, proven
from hkproof.theorems._clebsch import named, recall
from hkproof.theorems.clebsch_flows.data import yz_map
from hkproof.theorems.clebsch_flows.general import (FLOW2, GROUP, REDUCTION_CLAIM, THETA_NAMES, reduction_substitutions)

ORDER = ["flow-general-map", "flow-reduction", "flow-second-theorem", "flow-second-recipe-g", "flow-general-phi0",
         "flow-second-theta", "flow-theta-all", "flow-second-relations-found", "flow-second-l-relations-found",
         "flow-second-bases-345", "flow-conjecture"]


def claims_table() -> tuple[list[str], float]:
    """Each claim of the group once, in ORDER (then any other claim of the group), with its wall time."""
    load_all()
    ids = ORDER + sorted(c for c, cl in REGISTRY.items() if cl.group == GROUP and c not in ORDER)
    rows = ["| claim | status | own steps (s) | wall (s), cited claims included |", "|---|---|---|---|"]
    total = 0.0
    for cid in ids:
        t = time.perf_counter()
        cert = proven(cid)
        wall = time.perf_counter() - t
        total += wall
        slow = " (slow)" if REGISTRY[cid].slow else ""
        rows.append(f"| `{cid}`{slow} | {cert.status.label} | {cert.seconds:.2f} | {wall:.2f} |")
    return rows, total


def both_cores() -> tuple[float, int]:
    """The group as the scheduler runs it on this machine: `hkproof prove --group clebsch-flows --jobs 2` in a fresh
    process (independent claims at once; cited claims of other groups included); (wall seconds, exit code)."""
    t = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "hkproof.cli", "prove", "--group", GROUP, "--jobs", "2", "--jsonl"],
                          capture_output=True, text=True, check=False)
    return time.perf_counter() - t, done.returncode


def timed(fn, *args):
    t = time.perf_counter()
    out = fn(*args)
    return out, time.perf_counter() - t


def peers() -> list[str]:
    """The two side-by-side comparisons, on the same objects in the same process."""
    f = kahan_map(FLOW2)
    r = f.ring
    theta = proven("flow-second-theta")
    sol = [recall(theta, k, r) for k in THETA_NAMES]
    basis, h4 = [named(f, i) for i in ("I1", "I2", "I3")], named(f, "H4")
    ok_new, t_new = timed(check_solution_by_rows, f, basis, h4, [1], [], sol)
    ok_old, t_old = timed(check_solution, f, basis, h4, [1], [], sol)
    g = yz_map()
    sigma, _ = reduction_substitutions(REDUCTION_CLAIM)
    l2 = Frac.parse(r, proven("flow-second-theorem").formulas["L"])
    l_b, t_transport = timed(lambda: Frac(g.ring, g.ring.gen("z") ** 3) * sigma.apply(l2))
    verdict, t_subst = timed(check_integral, g, l_b)
    return [
        "| task | method | result | seconds | ratio |", "|---|---|---|---|---|",
        f"| second flow, Theta kernel in row i = 1 | `check_solution` (g times phi o f) | {ok_old} | {t_old:.1f} | 1 |",
        f"| same | `row_check` (Horner in N_j) | {ok_new} | {t_new:.1f} | {t_old / t_new:.1f}x faster |",
        f"| L_b o f = L_b, every flow | substitution in Q(x, eps, w, y, z) | {verdict.status.label} | {t_subst:.1f} | 1 |",
        f"| same | L_b = z^3 sigma(L_2), transported | exact | {t_transport:.3f} | "
        f"{t_subst / max(t_transport, 1e-3):.0f}x faster (or more) |",
    ]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default="docs/performance-clebsch-flows.md")
    parser.add_argument("--no-peers", action="store_true")
    args = parser.parse_args()
    load = os.getloadavg()
    rows, total = claims_table()
    parallel, code = both_cores()
    lines = ["# Performance: the Clebsch flows (group `clebsch-flows`)", "",
             f"Measured by `python benchmarks/clebsch_flows.py` on {platform.machine()} with {os.cpu_count()} cores "
             f"(shared, so single timings are noisy: compare rows measured in the same run), Python "
             f"{platform.python_version()}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; load average "
             f"before the run {load[0]:.1f} (other users' jobs share the cores).", "",
             f"## The group from scratch: {total:.1f} s", "",
             "Cited claims of other groups (part I's `dc-theta` and its own citations) are proven inside the first "
             "row that needs them. Without the slow claims (`--no-slow`) the group is the sum of the unmarked rows. "
             "The slow ones: "
             "the proof of Phi1, Phi2, Phi3 with w symbolic (the candidate over factored denominators, the row i = 1 "
             "by Horner) and the conjecture for every flow (its transport); the Theta proof for the second flow "
             "(about 20 s) and the discovery of the 23 relations in L (recipe (E) on six bases, about 13 s) are in "
             "the default suite, and `flow-general-phi0` and `flow-theta-all` cost little of their own.", "",
             *rows, "",
             f"## Both cores: {parallel:.1f} s", "",
             f"`hkproof prove --group {GROUP} --jobs 2` in a fresh process (exit code {code}): the scheduler runs "
             "independent claims at once, so the wall time is bounded below by the longest chain of citations "
             "(Theta, then Phi1..Phi3, then the conjecture), not by the sum above.", ""]
    if not args.no_peers:
        lines += ["## Side by side", "", *peers(), ""]
    Path(args.out).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
