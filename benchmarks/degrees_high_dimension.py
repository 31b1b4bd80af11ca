"""Benchmark of `hkproof degrees` in five and six dimensions (not a test): the dense Bareiss steps on a line
(hkproof.dynamics.line_iterates) against the route they replaced (the homogenized explicit map composed with the
line in FLINT's nmod_mpoly, gcd cancelled), and the growth class with the default options before and after (the
old cap of 50 000 and stride-1 ratios; the cap of 200 000 and strides 1 and 2). Writes docs/performance-degrees.md.

Run from the repository root: PYTHONPATH=$PWD python benchmarks/degrees_high_dimension.py
"""
from __future__ import annotations

import multiprocessing as mp
import platform
import random
import time
from pathlib import Path

import flint

from docs_section import write_section
from timebox import in_child

from hkproof.algebra.modular import random_prime
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.degree_growth import MAX_DEGREE, degree_growth, degrees_on_line, fit_growth
from hkproof.dynamics.field import EPS

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "performance-degrees.md"
EXAMPLES = ROOT / "docs" / "examples"
OLD_CAP = 50_000
PEER_LIMIT = 150.0
SYSTEMS = [str(EXAMPLES / "cubic-hamiltonian-5d.toml"), str(EXAMPLES / "volterra-6.toml"), "volterra-5", "toda-3",
           "euler-top", "clebsch", "lotka-volterra"]


def composition_route(system: str, iterates: int, cap: int) -> tuple[list[int], float]:
    """The route before: [W^d N(X/W) : W^d Delta(X/W)] composed with the line's polynomials in t (nmod_mpoly), the
    gcd of all entries cancelled, one run; stops when d times the last degree passes `cap`."""
    kmap = kahan_map(system)
    rng = random.Random(0)
    p = random_prime(rng)
    values = {name: rng.randrange(1, p) for name in kmap.field.control_names}
    start = time.perf_counter()
    hom, d = kmap.mod(p, values).homogenized()
    tctx = flint.nmod_mpoly_ctx.get(("t",), p, "lex")
    t = tctx.gen(0)
    point = [rng.randrange(p) + rng.randrange(1, p) * t for _ in kmap.variables] + [tctx.constant(1)]
    degrees: list[int] = []
    while len(degrees) < iterates and not (degrees and degrees[-1] * d > cap):
        point = [h.compose(*point, ctx=tctx) for h in hom]
        g = point[0]
        for q in point[1:]:
            g = g.gcd(q)
        point = [q / g for q in point]
        degrees.append(int(max(q.total_degree() for q in point)))
    return degrees, time.perf_counter() - start


def _composition_child(system: str, iterates: int, queue: mp.Queue) -> None:
    queue.put(composition_route(system, iterates, 10 ** 9))


def line_route(system: str, iterates: int) -> tuple[list[int], float]:
    """The route now (`degrees_on_line`, one run, no cap below the iterates asked for)."""
    kmap = kahan_map(system)
    rng = random.Random(0)
    p = random_prime(rng)
    values = {name: rng.randrange(1, p) for name in kmap.field.control_names}
    start = time.perf_counter()
    degrees = degrees_on_line(kmap, values, p, iterates, rng, max_degree=10 ** 9)
    return degrees, time.perf_counter() - start


def growth_text(degrees: list[int], strides: int = 2) -> str:
    g = fit_growth(degrees, strides=strides)
    if g.kind == "exponential":
        return f"exponential, lambda = {g.lam:.5g} +- {g.lam_error:.2g}"
    return g.kind if g.kind == "undecided" else f"{g.kind}: {g.formula()}"


def main() -> None:
    name = lambda s: Path(s).stem     # noqa: E731
    lines = [f"Measured in one run by `benchmarks/degrees_high_dimension.py` on {platform.machine()}, Python "
             f"{platform.python_version()}, python-flint {flint.__version__} (a shared 2-core machine, other jobs "
             "running: ratios are more telling than seconds).", "",
             "## The default options (`hkproof degrees SYSTEM`: 8 iterates, 2 runs), before and after", "",
             f"Before: the route below with its cap (a step stops when d times the last degree passes {OLD_CAP}), "
             f"ratios compared one step apart. After: two runs side by side, cap {MAX_DEGREE} on n times the last "
             "degree, ratios compared one or two steps apart.", "",
             "| system | before: degrees | before: growth | before: s (1 run) | after: degrees | after: growth | "
             "after: s (2 runs, wall) |", "|---|---|---|---|---|---|---|"]
    for system in SYSTEMS:
        old, old_sec = composition_route(system, 8, OLD_CAP)
        start = time.perf_counter()
        new = degree_growth(kahan_map(system), 8)
        new_sec = time.perf_counter() - start
        lines.append(f"| {name(system)} | {old} | {growth_text(old, strides=1)} | {old_sec:.1f} | {new.degrees} | "
                     f"{growth_text(new.degrees)} | {new_sec:.1f} |")
        print(lines[-1], flush=True)
    lines += ["", "## One run to the same number of terms: the composition route against the line route", "",
              f"The route before without its cap, in a child process stopped after {PEER_LIMIT:.0f} s; the route now "
              "without its cap; same prime, values and line.", "",
              "| system | terms | degrees (line route) | composition: s | line route: s | ratio | same degrees |",
              "|---|---|---|---|---|---|---|"]
    for system, terms in ((SYSTEMS[0], 8), (SYSTEMS[1], 7), ("volterra-5", 8), ("toda-3", 7)):
        new, new_sec = line_route(system, terms)
        peer = in_child(_composition_child, (system, terms), PEER_LIMIT)
        old_text = f"> {PEER_LIMIT:.0f} (stopped)" if peer is None else f"{peer[1]:.1f}"
        ratio = f"> {PEER_LIMIT / new_sec:.1f}x" if peer is None else f"{peer[1] / new_sec:.1f}x"
        same = "-" if peer is None else ("yes" if peer[0] == new else f"NO: {peer[0]}")
        lines.append(f"| {name(system)} | {terms} | {new} | {old_text} | {new_sec:.1f} | {ratio} | {same} |")
        print(lines[-1], flush=True)
    write_section(DOC, "degrees", lines)


if __name__ == "__main__":
    main()
