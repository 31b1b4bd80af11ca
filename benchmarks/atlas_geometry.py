"""The atlas beside its integrals: degree growth and invariant measures of each atlas system (not a test).

    python benchmarks/atlas_geometry.py [--iterates 8] [--degree 2] [--seconds 120]

For every system of docs/atlas.md: deg f^n for n = 1..iterates (`hkproof degrees`: random lines mod large primes,
evidence) and the Darboux polynomials / invariant densities of degree <= degree (`hkproof measure`). Each system
runs in its own process under a time limit. Writes the block `atlas-geometry` of docs/atlas.md.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

from docs_section import write_section

DOC = Path(__file__).resolve().parent.parent / "docs" / "atlas.md"
SYSTEMS = ("volterra-3", "volterra-4", "volterra-5", "toda-3", "gaudin-2", "kirchhoff", "so4-euler-top",
           "so4-euler-top-flow2")


def hkproof(args: list[str], seconds: float) -> tuple[dict | None, float]:
    """The JSON answer of one hkproof command (None if it did not finish in time) and its wall time."""
    start = time.perf_counter()
    try:
        out = subprocess.run([sys.executable, "-m", "hkproof.cli", *args, "--json"], capture_output=True, text=True,
                             timeout=seconds)
    except subprocess.TimeoutExpired:
        return None, seconds
    return (json.loads(out.stdout) if out.stdout.strip() else None), time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--iterates", type=int, default=8)
    parser.add_argument("--degree", type=int, default=2)
    parser.add_argument("--seconds", type=float, default=120.0)
    args = parser.parse_args()
    rows = []
    for name in SYSTEMS:
        deg, t_deg = hkproof(["degrees", name, "--iterates", str(args.iterates)], args.seconds)
        mea, t_mea = hkproof(["measure", name, "--degree", str(args.degree)], args.seconds)
        degrees = "stopped" if deg is None else ", ".join(map(str, deg["degrees"]))
        growth = "—" if deg is None else deg.get("formula") or deg.get("growth", "?")
        if mea is None:
            found = f"not finished in {args.seconds:.0f} s"
        else:
            dens = [f"{d['expr']} ({d['status']})" for d in mea.get("densities", [])]
            found = "; ".join(dens) if dens else "none up to this degree"
        rows.append(f"| `{name}` | {degrees} | {growth} | {t_deg:.1f} s | {found} | {t_mea:.1f} s |")
        print(rows[-1], flush=True)
    lines = ["## Degree growth and invariant measures", "",
             f"Measured by `python benchmarks/atlas_geometry.py --iterates {args.iterates} --degree {args.degree}` "
             f"({time.strftime('%Y-%m-%d')}, one process per command, {args.seconds:.0f} s limit). Degrees are "
             "evidence(exact) (random lines mod large primes, two runs); a density's status is the one `hkproof "
             "measure` proves (verified: exact identity with eps and parameters symbolic). Polynomial (here "
             "quadratic) degree growth is the mark of integrability in the sense of algebraic entropy; exponential "
             "growth excludes it.", "",
             "| system | deg f^n, n = 1.. | growth | time | invariant densities 1/P (degree <= "
             f"{args.degree}) | time |", "|---|---|---|---|---|---|", *rows]
    print(write_section(DOC, "atlas-geometry", lines))


if __name__ == "__main__":
    main()
