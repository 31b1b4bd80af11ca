"""The two routes of a row check with an iterate (`hk.row_check`): Horner's scheme expanded in every variable against
the same identity at the points of a unisolvent lattice in the parameters (`algebra.lattice_identity`), each row
of a real proof checked both ways side by side in one run, with the cost model's estimates. Writes
docs/performance-row-check.md.

    python benchmarks/row_routes.py                  # so(4) Manakov (discover) and the second Clebsch flow (prove)
    python benchmarks/row_routes.py --flow2          # also the commuting so(4) flow with a symbolic (about 40 min)

Each row identity is the one the proof meets (`hk.block_system.verify_candidate`); the expansion is stopped after
`--horner-seconds` (it does not finish on the commuting flow: tens of GB).
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

from hkproof.algebra import lattice_identity
from hkproof.budget import Budget
from hkproof.errors import BudgetExhausted
from hkproof.hk import block_system, row_check
from hkproof.orchestration.registry import get_claim
from hkproof.pipelines.discover import discover

DOC = Path(__file__).resolve().parents[1] / "docs" / "performance-row-check.md"
ROWS: list[dict] = []


def timed_row_holds(horner_seconds: float):
    """A row_holds that checks each row with an iterate by both routes and records the times."""
    honest = row_check.row_holds

    def both(kmap, basis, target, i, solution, route="auto"):
        if i == 0:
            return honest(kmap, basis, target, i, solution)
        plans: list = []
        plan_lattice = lattice_identity.plan_lattice

        def spy(*args):
            plans.append(plan_lattice(*args))
            return plans[-1]
        row_check.plan_lattice = spy
        try:
            start = time.perf_counter()
            lattice = honest(kmap, basis, target, i, solution, route="lattice")
            lattice_seconds = time.perf_counter() - start
        finally:
            row_check.plan_lattice = plan_lattice
        start = time.perf_counter()
        try:
            with Budget(horner_seconds).active():
                horner = honest(kmap, basis, target, i, solution, route="horner").holds
        except BudgetExhausted:
            horner = None
        horner_seconds_taken = time.perf_counter() - start
        plan = plans[-1]
        ROWS.append({"system": kmap.field.name, "i": i, "plan": plan, "lattice": lattice_seconds,
                     "horner": horner_seconds_taken, "horner_holds": horner, "lattice_holds": lattice.holds})
        print(ROWS[-1], flush=True)
        return lattice
    return both


def markdown(horner_seconds: float) -> str:
    out = ["# Row checks: expanded, or at the points of a lattice", "",
           "Measured by `benchmarks/row_routes.py` in one run on the shared 2-core machine: each row with an iterate "
           "that a block proof meets, checked by both routes of `hk.row_check` one after the other (Horner's scheme "
           "expanded in every variable; the same identity with eps and one parameter set to 1 by the weighted "
           "homogeneity and the other parameters on the principal lattice of their degree bound, the points shared "
           f"by two forked children). The expansion is stopped after {horner_seconds:g} s. `work` is the cost "
           "model's estimate (term products) that chooses the route.", "",
           "| system | row | lattice (names, degree, points) | model: lattice / expanded | lattice | expanded | "
           "ratio | verdicts |", "|---|---|---|---|---|---|---|---|"]
    for r in ROWS:
        p = r["plan"]
        expanded = f"{r['horner']:.1f} s" if r["horner_holds"] is not None else f"> {r['horner']:.0f} s (stopped)"
        ratio = f"{r['horner'] / r['lattice']:.2f}" if r["horner_holds"] is not None else "-"
        out.append(f"| {r['system']} | i = {r['i']} | {', '.join(p.lattice)}; {p.degree}; {p.points} | "
                   f"{p.work:.2e} / {p.plain_work:.2e} | {r['lattice']:.1f} s | {expanded} | {ratio} | "
                   f"{r['lattice_holds']} / {r['horner_holds']} |")
    out += ["", "Ratio: expanded / lattice (above 1: the lattice is faster). The automatic route takes the lattice "
            "when the model's estimate is lower."]
    return "\n".join(out) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--flow2", action="store_true", help="also the commuting so(4) flow (about 40 minutes)")
    parser.add_argument("--horner-seconds", type=float, default=900.0)
    args = parser.parse_args()
    block_system.row_holds = timed_row_holds(args.horner_seconds)
    discover("so4-euler-top", 2, budget=Budget(1200))
    get_claim("flow-second-bases-345").prove()
    if args.flow2:
        discover("so4-euler-top-flow2", 2, budget=Budget(4000))
    DOC.write_text(markdown(args.horner_seconds))
    print(f"wrote {DOC}")


if __name__ == "__main__":
    main()
