"""`discover` in random affine charts against the catalogue's chart, side by side in one run. Writes
docs/performance-coordinates.md.

For each integrable system of the catalogue (degree 2) and each kind of change (a dense T with entries in [-2, 2], a
signed permutation with scalings, a translation, a dense T with a translation; one seed each), the independent
proven integrals and the wall time of `discover` in the catalogue's chart and in the transformed one, and their
ratio; also the transformed chart with the normal form switched off (charts=False), the behaviour before issue 37.
Each run has a budget of --seconds (a run that hits it says so). The section "What the table says" of the page is
kept when the table is rewritten.
"""
from __future__ import annotations

import argparse
import os
import random
import time
from pathlib import Path

from hkproof.budget import Budget
from hkproof.dynamics.catalogue import get_system
from hkproof.hk.affine_chart import CHANGE_KINDS, random_change, transformed
from hkproof.hk.normal_form import field_size
from hkproof.pipelines.discover import discover

SYSTEMS = ["euler-top", "clebsch", "zhukovsky-volterra-1", "volterra-3", "volterra-4", "gaudin-2",
           "lagrange-top", "kirchhoff", "toda-3", "so4-euler-top", "so4-euler-top-split"]
NOTES = "## What the table says"      # a hand-written reading below the table, kept when the table is rewritten


def run(field, seconds: float, charts: bool = True) -> tuple[int, float, bool, int]:
    """Independent proven integrals, wall seconds, whether the search finished, and the size of the field searched
    (hk.normal_form.field_size: the normal form's when discover changed chart)."""
    start = time.perf_counter()
    report = discover(field, 2, budget=Budget(seconds), charts=charts)
    searched = report.chart.searched if report.chart is not None else field
    return report.independent, time.perf_counter() - start, report.complete, field_size(searched)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seconds", type=float, default=200)
    ap.add_argument("--systems", nargs="*", default=SYSTEMS)
    ap.add_argument("--without-charts", action="store_true", help="also time the transformed chart as given")
    ap.add_argument("--out", default="docs/performance-coordinates.md")
    args = ap.parse_args()
    rows = []
    for name in args.systems:
        field = get_system(name)
        base = run(field, args.seconds)
        for kind in CHANGE_KINDS:
            moved = transformed(field, random_change(len(field.variables), random.Random(7), kind), f"{name}-{kind}")
            got = run(moved, args.seconds)
            old = run(moved, args.seconds, charts=False) if args.without_charts else None
            rows.append((name, kind, base, got, old, field_size(moved)))
            print(rows[-1], flush=True)
    lines = ["# `discover` in any coordinates (benchmarks/coordinates.py)", "",
             f"One run, {time.strftime('%Y-%m-%d')}, {os.cpu_count()} cores, budget {args.seconds:g} s per search, degree 2, seed 7 for the "
             "random change. Columns: independent proven integrals and wall seconds in the catalogue's chart, the "
             "same in the transformed chart (normal form on, the default), their time ratio, the size of the "
             "right-hand sides (characters) in the catalogue's chart, in the transformed one and in the chart searched"
             + (", and the transformed chart searched as given (`charts=False`)" if args.without_charts else "")
             + ". A `*` marks a search stopped by the budget.", "",
             "| system | change | catalogue | transformed | ratio | field size (catalogue, given, searched) |"
             + (" as given |" if args.without_charts else ""),
             "|---|---|---|---|---|---|" + ("---|" if args.without_charts else "")]

    def cell(r: tuple[int, float, bool, int]) -> str:
        return f"{r[0]} in {r[1]:.2f} s{'' if r[2] else ' *'}"
    for name, kind, base, got, old, given in rows:
        lines.append(f"| {name} | {kind} | {cell(base)} | {cell(got)} | {got[1] / base[1]:.1f} | "
                     f"{base[3]}, {given}, {got[3]} |" + (f" {cell(old)} |" if old else ""))
    out = Path(args.out)
    kept = out.read_text().split(NOTES, 1) if out.exists() else []
    out.write_text("\n".join(lines) + "\n" + (f"\n{NOTES}{kept[1]}" if len(kept) == 2 else ""))


if __name__ == "__main__":
    main()
