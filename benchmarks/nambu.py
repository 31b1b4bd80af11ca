"""Nambu structures P W(grad I) (hkproof.hk.nambu) across the atlas: per system the cost of the integrals
(`discover`), of the density (`measure`), of the Nambu proof (the universal identities included, once per process),
and where Pi is small enough to expand, the direct route beside it (the substitution identity of invariance and the
Schouten bracket, expanded: `hk.poisson.invariance_holds`, `is_poisson`). Each system runs in a fresh process (its peak
RSS is its own). Writes the block "nambu" of docs/performance-poisson.md.

    python benchmarks/nambu.py            # about 5 minutes on 2 cores
"""
from __future__ import annotations

import argparse
import json
import platform
import resource
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import flint

from docs_section import write_section

DOC = Path(__file__).resolve().parents[1] / "docs" / "performance-poisson.md"
SYSTEMS = (("euler-top", 4), ("volterra-3", 4), ("volterra-4", 4), ("zhukovsky-volterra-1", 4), ("gaudin-2", 4),
           ("clebsch", 6), ("kirchhoff", 6), ("lagrange-top", 6))
DIRECT_TERMS = 2000
"""The direct route runs when the expanded Pi has at most this many terms (Gaudin's, 143 000 terms, had taken 9.6 GB
in invariance_holds when it was stopped). Pi itself is expanded only where hk.nambu expands it (EXPAND_TERMS)."""


def one(system: str, degree: int) -> dict[str, Any]:
    """The measurements of one system (run in its own process)."""
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.hk.nambu import nambu_bivector, prove_nambu
    from hkproof.hk.poisson import invariance_holds, is_poisson
    from hkproof.pipelines.darboux import search_darboux
    from hkproof.pipelines.discover import discover
    from hkproof.pipelines.poisson import nambu_densities

    kmap = kahan_map(system)
    started = time.perf_counter()
    found = [(i.name, i.frac, i.status) for i in discover(kmap.field, 2).integrals if i.frac is not None]
    integrals = time.perf_counter() - started
    started = time.perf_counter()
    densities = nambu_densities(kmap, search_darboux(kmap, degree))
    measure = time.perf_counter() - started
    row: dict[str, Any] = {"system": system, "n": len(kmap.variables), "integrals": len(found),
                           "integrals_s": integrals, "degree": degree, "measure_s": measure,
                           "densities": len(densities)}
    if densities:
        started = time.perf_counter()
        out = prove_nambu(kmap, found, densities[0])
        row.update(nambu_s=time.perf_counter() - started, status=out.status.label, rank=out.rank,
                   casimirs=[n for n, _ in out.casimirs], hamiltonians=[n for n, _ in out.hamiltonians],
                   density_terms=len(densities[0][1]), la=out.liouville_arnold)
        row["integral_terms"] = sum(len(h.num) + len(h.den) for _, h in out.casimirs)
        pi = out.bivector
        if pi is None:
            return {**row, "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}
        started = time.perf_counter()
        nambu_bivector(kmap.ring, kmap.variables, [h for _, h in out.casimirs], densities[0][1])
        row.update(expand_s=time.perf_counter() - started, terms=sum(len(q) for q in pi.upper) + len(pi.denominator),
                   degree_pi=int(pi.degree()))
        if row["terms"] <= DIRECT_TERMS:
            started = time.perf_counter()
            row["direct"] = invariance_holds(kmap, pi) and is_poisson(pi)
            row["direct_s"] = time.perf_counter() - started
    row["rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return row


def measured(system: str, degree: int) -> dict[str, Any]:
    """`one` in a fresh process."""
    script = (f"import json, sys; sys.path.insert(0, {str(Path(__file__).parent)!r}); from nambu import one; "
              f"print(json.dumps(one({system!r}, {degree})))")
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def section(rows: list[dict[str, Any]]) -> list[str]:
    out = [f"## Nambu structures across the atlas (`python benchmarks/nambu.py`, {time.strftime('%Y-%m-%d')})", "",
           f"Measured in one run on {platform.node() or 'this machine'} (python-flint {flint.__version__}), each system "
           "in a fresh process one after the other: the integrals of `discover` at degree 2, the densities 1/P of "
           "`measure` at the degree shown, the Nambu proof of `hk.nambu` (the three universal identities of the "
           "dimension included) and, to compare, Pi expanded over one denominator and, when it has at most "
           f"{DIRECT_TERMS} terms, the direct route (invariance by substitution and the Schouten bracket, expanded).",
           "", "| system | n | integrals | discover | measure (degree) | densities | Nambu proof | status, rank | "
           "Casimirs; further | Pi expanded (degree, terms) | direct route | peak RSS |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if not r["densities"]:
            out.append(f"| {r['system']} | {r['n']} | {r['integrals']} | {r['integrals_s']:.1f} s | "
                       f"{r['measure_s']:.1f} s ({r['degree']}) | 0 | – | – | – | – | – | {r['rss_mb']:.0f} MB |")
            continue
        direct = (f"{r['direct_s']:.3f} s ({'holds' if r['direct'] else 'FAILS'})" if "direct" in r else "not run")
        further = ", ".join(r["hamiltonians"]) or "none"
        expanded = (f"{r['expand_s']:.2f} s ({r['degree_pi']}, {r['terms']})" if "terms" in r else
                    f"not expanded (integrals of {r['integral_terms']} terms)")
        out.append(f"| {r['system']} | {r['n']} | {r['integrals']} | {r['integrals_s']:.1f} s | "
                   f"{r['measure_s']:.1f} s ({r['degree']}) | {r['densities']} | {r['nambu_s']:.3f} s | "
                   f"{r['status']}, {r['rank']} | {', '.join(r['casimirs'])}; {further} | {expanded} | {direct} | "
                   f"{r['rss_mb']:.0f} MB |")
    return out


def main() -> None:
    argparse.ArgumentParser(description=__doc__).parse_args()
    rows = []
    for system, degree in SYSTEMS:
        rows.append(measured(system, degree))
        print(rows[-1], flush=True)
    print(write_section(DOC, "nambu", section(rows)))


if __name__ == "__main__":
    main()
