"""Step 5d of `discover` (bases with integrals of the flow, solved together): members carried by a symmetry of the
field against every block rebuilt, and the coordinates on one process against a pool of two (--jobs 2), the same
search side by side in one run. Writes docs/performance-step5d.md.

Case: the Manakov top on so(4) in the coordinates m_ij (so4-euler-top, a1..a4 symbolic, searched on the slice
a4 = 0), whose group of three bases is carried by one 3-cycle of the indices with the parameters permuted.
"""
from __future__ import annotations

import argparse
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from hkproof.budget import Budget
from hkproof.pipelines.discover import discover

SYSTEM = "so4-euler-top"
BUDGET = 600.0


def run(label: str, **options) -> dict:
    start = time.perf_counter()
    report = discover(SYSTEM, 2, budget=Budget(BUDGET), **options)
    total = time.perf_counter() - start
    together = [i for i in report.integrals if "integrals of the continuous flow" in i.method]
    row = {"label": label, "total": total, "step5d": report.stages.get("integral bases", 0.0),
           "proof": max((i.certificate.seconds for i in together if i.certificate is not None), default=0.0),
           "independent": report.independent, "complete": report.complete}
    print(f"{label}: {total:.2f} s, step 5d {row['step5d']:.2f} s, {report.independent} independent", flush=True)
    return row


def markdown(rows: list[dict]) -> str:
    base = rows[0]["step5d"]
    out = ["# Step 5d of `discover`: symmetries and a pool of workers", "",
           f"Measured by `benchmarks/step5d.py` in one run on the shared 2-core machine: `discover {SYSTEM}` "
           "(a1..a4 symbolic, searched on the slice a4 = 0), the same search with each option. Step 5d solves three "
           "bases of monomials and integrals of the continuous flow together (12 unknowns); one symmetry of the "
           "field (a 3-cycle of the indices, a1 -> a2 -> a3 -> a1) carries the first basis to the other two, so only "
           "its 4 coordinates are rebuilt and only its rows are checked by Horner; the others are exact images.", "",
           "| run | total (s) | step 5d (s) | step 5d / first row | block proof (s) | independent integrals | "
           "complete |", "|---|---|---|---|---|---|---|"]
    out += [f"| {r['label']} | {r['total']:.2f} | {r['step5d']:.2f} | {r['step5d'] / base:.2f} | {r['proof']:.2f} | "
            f"{r['independent']} | {'yes' if r['complete'] else 'no (budget)'} |" for r in rows]
    out += ["", "The block proof column is the certificate time of the group (Prop. \"prop: even\": rank, evenness, "
            "relations, the rows of the source blocks, and the symmetry checked on the map when one is used).", ""]
    return "\n".join(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "performance-step5d.md"))
    args = parser.parse_args()
    rows = [run("every block rebuilt (symmetries=False)", symmetries=False),
            run("blocks carried by a symmetry (default)")]
    with ProcessPoolExecutor(2) as pool:
        rows.append(run("carried, coordinates on 2 workers (--jobs 2)", mapper=pool.map))
    Path(args.out).write_text(markdown(rows))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
