"""Benchmark of the geometry commands (not a test): degree growth mod p against symbolic iterates, the Darboux /
measure search, the modified Hamiltonian.  Writes docs/performance-geometry.md with every figure measured in this run.

Run from the repository root: PYTHONPATH=$PWD python benchmarks/geometry.py
"""
from __future__ import annotations

import multiprocessing as mp
import platform
import time
from pathlib import Path

import flint

from docs_section import write_section
from timebox import in_child

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.degree_growth import degree_growth
from hkproof.pipelines.darboux import search_darboux
from hkproof.hk.modified_hamiltonian import parse_matrix, verify

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "performance-geometry.md"
EXAMPLES = ROOT / "docs" / "examples"
PEER_LIMIT = 30.0


def timed(fn, *args, **kwargs):
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - start


def _symbolic_iterate(name: str, k: int, queue: mp.Queue) -> None:
    f = kahan_map(name)
    start = time.perf_counter()
    nums, den = f.iterate(k)
    idx = [f.ring.index(v) for v in f.variables]
    degree = max(max((sum(m[i] for i in idx) for m in p.monoms()), default=0) for p in (*nums, den))
    queue.put((time.perf_counter() - start, degree))


def symbolic_peer(name: str, k: int) -> tuple[float | None, int | None]:
    """KahanMap.iterate(k) with eps and the parameters symbolic (gcd cancelled), in a process stopped at PEER_LIMIT."""
    return in_child(_symbolic_iterate, (name, k), PEER_LIMIT) or (None, None)


def degrees_section() -> list[str]:
    lines = ["## Degree growth: `hkproof degrees` (mod p, two runs) against symbolic iterates", "",
             "| system | iterates | degrees | growth | seconds (2 runs) |", "|---|---|---|---|---|"]
    for name in ("euler-top", "clebsch", "clebsch-flow2", "lotka-volterra"):
        f = kahan_map(name)
        f.explicit
        res, sec = timed(degree_growth, f, 10)
        lines.append(f"| {name} | 10 | {res.degrees} | {res.growth.kind}: {res.growth.formula()} | {sec:.2f} |")
    lines += ["", "Peer: `KahanMap.iterate(n)` with eps and the parameters symbolic (all gcds cancelled), the route "
              f"the issue timed; stopped after {PEER_LIMIT:.0f} s. The degree in x of its result is the same number.",
              "",
              "| system | n | symbolic iterate: seconds | its degree in x | mod p, one run: seconds | ratio |",
              "|---|---|---|---|---|---|"]
    for name, ks in (("euler-top", (3, 4, 5)), ("lotka-volterra", (4, 5, 6)), ("clebsch", (2,))):
        f = kahan_map(name)
        for k in ks:
            peer, degree = symbolic_peer(name, k)
            ours, sec = timed(degree_growth, f, k, runs=1)
            peer_text = f"{peer:.2f}" if peer is not None else f"> {PEER_LIMIT:.0f} (stopped)"
            ratio = f"{peer / sec:.0f}x" if peer is not None else f"> {PEER_LIMIT / sec:.0f}x"
            lines.append(f"| {name} | {k} | {peer_text} | {degree if degree is not None else '-'} "
                         f"(mod p: {ours.degrees[-1]}) | {sec:.3f} | {ratio} |")
    return lines


def measure_section() -> list[str]:
    lines = ["", "## Darboux polynomials and measures: `hkproof measure`", "",
             "| system | degree | Darboux polynomials | densities | integrals | status | seconds |",
             "|---|---|---|---|---|---|---|"]
    for name, d in (("euler-top", 4), ("lotka-volterra", 4), (str(EXAMPLES / "cubic-oscillator.toml"), 3),
                    (str(EXAMPLES / "henon-heiles.toml"), 2), ("zhukovsky-volterra-1", 4), ("zhukovsky-volterra", 4),
                    ("clebsch", 4), ("clebsch", 6)):
        res, sec = timed(search_darboux, kahan_map(name), d)
        statuses = sorted({p.status.label for p in res.darboux}) or ["-"]
        lines.append(f"| {Path(name).stem} | {d} | {len(res.darboux)} | {len(res.densities())} | "
                     f"{len(res.integrals())} | {', '.join(statuses)} | {sec:.2f} |")
    return lines


def hamiltonian_section() -> list[str]:
    lines = ["", "## Modified Hamiltonian: `hkproof hamiltonian`", "",
             "| system | H~ o f = H~ | density | seconds |", "|---|---|---|---|"]
    cases = ((EXAMPLES / "cubic-oscillator.toml", "p**2/2 + q**2/2 + a*q**3/3", "0, 1; -1, 0"),
             (EXAMPLES / "henon-heiles.toml", "(p1**2 + p2**2)/2 + (q1**2 + q2**2)/2 + q1**2*q2 - q2**3/3",
              "0,0,1,0; 0,0,0,1; -1,0,0,0; 0,-1,0,0"))
    for path, h, j in cases:
        f = kahan_map(str(path))
        res, sec = timed(verify, f, Frac.parse(f.ring, h), parse_matrix(f, j))
        lines.append(f"| {path.stem} | {res.integral.label} | {res.measure.label} | {sec:.2f} |")
    return lines


def main() -> None:
    body = [f"Measured in one run by `benchmarks/geometry.py` on {platform.machine()}, Python "
            f"{platform.python_version()}, python-flint {flint.__version__} (a shared 2-core machine: ratios are more "
            "telling than seconds). Goals of issue 15: 10 iterates of the Euler top and of the first Clebsch flow "
            "under 2 s each; the measure search for the Euler top under 10 s.", ""]
    body += degrees_section() + measure_section() + hamiltonian_section()
    print(write_section(DOC, "geometry", body))


if __name__ == "__main__":
    main()
