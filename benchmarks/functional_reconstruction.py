"""Benchmark of the sparse functional reconstruction engine (not a test): probes, primes and seconds per stage for
numerators of about T = 100, 1000, 10 000 terms in 6, 8 and 10 variables, with a cheap black box.

The black box is f = (A B) / (D E) with random sparse factors (A, B of degree 6 with about sqrt(T) terms each,
D, E with a tenth of that), evaluated mod p by FLINT: cheap to evaluate, and about T terms once expanded, which is
what the engine must find. Writes the table to docs/reconstruction.md (between the markers), all measured in one run.

Run: PYTHONPATH=. python benchmarks/functional_reconstruction.py [--quick]
"""
from __future__ import annotations

import math
import platform
import random
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "benchmarks")]

from docs_section import write_section

from hkproof.algebra.sparse_reconstruction import sparse as reconstruct_rational
from tests.test_sparse_reconstruction import RationalBox, multiply, primitive, random_sparse_polynomial

DOC = ROOT / "docs" / "reconstruction.md"
SIZES = [(n, t) for t in (100, 1000, 10000) for n in (6, 8, 10)]


def target(n: int, terms: int, seed: int) -> tuple[RationalBox, dict, dict]:
    """The cheap black box for about `terms` numerator terms in n variables, and its expanded normal form."""
    rng = random.Random(seed)
    side, den_side = max(2, round(math.sqrt(terms))), max(2, round(math.sqrt(terms / 10)))
    a, b = (random_sparse_polynomial(rng, n, 6, side, height=2 ** 15) for _ in range(2))
    d, e = (random_sparse_polynomial(rng, n, 6, den_side, height=2 ** 15) for _ in range(2))
    return RationalBox(n, [a, b], [d, e]), *primitive(multiply(a, b), multiply(d, e))


def points_per_piece(poly: dict) -> tuple[int, int]:
    """z-points the pieces of poly need, the most over its homogeneous pieces (all pieces share the lines):
    Ben-Or–Tiwari 2T + 2 (early termination), and Zippel counted from the support (not run): with z_0 = 1, variable
    k costs (deg_k + 2) transposed Vandermonde solves of the size of the support projected on z_1..z_{k-1}."""
    bot = zippel = 0
    for r in {sum(m) for m in poly}:
        support = [m[1:] for m in poly if sum(m) == r]
        bot = max(bot, 2 * len(support) + 2)
        count = 0
        for k in range(len(support[0])):
            projected = len({m[:k] for m in support})
            count += (max(m[k] for m in support) + 2) * projected
        zippel = max(zippel, count)
    return bot, zippel


def run(n: int, terms: int) -> dict:
    box, num, den = target(n, terms, seed=1000 * n + terms)
    start = time.perf_counter()
    result = reconstruct_rational(box, n, rng=random.Random(n))
    wall = time.perf_counter() - start
    assert (result.numerator, result.denominator) == (num, den), f"wrong result for n = {n}, T = {terms}"
    s = result.stats
    engine = wall - s.seconds["probes"]
    bot, zippel = (max(a, b) for a, b in zip(points_per_piece(num), points_per_piece(den)))
    return {"bot_points": bot, "zippel_points": zippel, "n": n, "terms": f"{len(num)} / {len(den)}",
            "all_terms": len(num) + len(den), "probes": s.probes,
            "lines": s.lines, "primes": len(s.primes_used), "wall": wall, "engine": engine,
            "box_us": 1e6 * s.seconds["probes"] / s.probes, "overhead_rate": s.probes / engine,
            "stages": s.seconds, "by_stage": s.probes_by_stage, "shift": any(s.shift)}


def main() -> None:
    sizes = SIZES[:6] if "--quick" in sys.argv else SIZES
    rows = []
    for n, terms in sizes:
        row = run(n, terms)
        rows.append(row)
        print(row, file=sys.stderr)
    lines = [(f"Measured in one run on {platform.machine()} / Python {platform.python_version()}, one process "
              f"(default mapper), {time.strftime('%Y-%m-%d')}; "
              "`PYTHONPATH=. python benchmarks/functional_reconstruction.py`."),
             "", ("| n | terms P / Q | probes | probes per term | lines | primes | black box µs/probe | "
                  "engine probes/s | probes s | univariate s | sparse s | crt s | check s | total s |"),
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        st = r["stages"]
        lines.append(f"| {r['n']} | {r['terms']} | {r['probes']} | {r['probes'] / r['all_terms']:.2f} |"
                     f" {r['lines']} | {r['primes']} | {r['box_us']:.0f} | {r['overhead_rate']:.0f} |"
                     f" {st['probes']:.2f} |"
                     f" {st['univariate']:.2f} | {st['sparse']:.2f} | {st['crt']:.2f} | {st['check']:.2f} |"
                     f" {r['wall']:.2f} |")
    lines += ["", ("Points z_j of the first prime, Ben-Or–Tiwari (2T + 2 for the largest piece) against Zippel "
                   "counted from the same supports (not run; each point is a whole line of probes):"), ""]
    lines += [f"- n = {r['n']}, {r['terms']} terms: Ben-Or–Tiwari {r['bot_points']}, Zippel {r['zippel_points']}"
              for r in rows]
    lines += ["", "Probes by stage (degrees / shift scan / support prime / further primes / check):", ""]
    lines += [f"- n = {r['n']}, {r['terms']} terms: " + ", ".join(f"{k} {v}" for k, v in r["by_stage"].items())
              for r in rows]
    write_section(DOC, "reconstruction-benchmark", lines)


if __name__ == "__main__":
    main()
