"""Benchmark (not a test): reading formulas with hkproof's exact parser against the old path through sympy.

    python benchmarks/parsing.py

The old path (sympy.sympify, together, fraction, Poly, then FLINT) is kept here only as the peer, on trusted text;
the package itself never evaluates a formula. Writes the block `parsing` of docs/performance.md.
"""
from __future__ import annotations

import platform
import statistics
import time
from pathlib import Path

import sympy
from docs_section import write_section

from hkproof.algebra.formula import parse_formula
from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.proof.registry import proven

DOC = Path(__file__).resolve().parent.parent / "docs" / "performance.md"


def sympy_path(ring, text: str) -> Frac:
    """The pre-parser route: sympify with the ring's symbols, then numerator and denominator through sympy.Poly."""
    syms = {n: sympy.Symbol(n) for n in ring.names}
    num, den = sympy.fraction(sympy.together(sympy.sympify(text, locals=syms)))

    def poly(e):
        p = sympy.Poly(sympy.expand(e), *syms.values(), domain="QQ")
        lcm = 1
        for _, c in p.terms():
            lcm = sympy.ilcm(lcm, sympy.Rational(c).q)
        return ring.ctx.from_dict({tuple(int(k) for k in m): int(sympy.Rational(c) * lcm) for m, c in p.terms()}), lcm
    (p, a), (q, b) = poly(num), poly(den)
    return Frac(ring, p * b, q * a)


def best(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    euler = kahan_map("euler-top").ring
    long_sum = " + ".join(f"{k}/{k + 1}*x1**{k % 4}*x2**{k % 3}*a{1 + k % 3}*eps**{k % 2}" for k in range(1000))
    clebsch = kahan_map("clebsch").ring
    d7 = proven("dc-basis2").formulas["d7"]
    cases = [("a sum of 1 000 terms (Euler-top ring)", euler, long_sum),
             (f"Clebsch d7 of Th. \"dC basis 2\" ({len(d7)} characters)", clebsch, d7)]
    rows = []
    for label, ring, text in cases:
        assert parse_formula(ring, text) == sympy_path(ring, text)
        ours = best(lambda: parse_formula(ring, text), 5)
        peer = best(lambda: sympy_path(ring, text), 3)
        rows.append(f"| {label} | {ours * 1000:.1f} ms | {peer * 1000:.1f} ms | {peer / ours:.1f}x |")
    lines = [f"Measured by `python benchmarks/parsing.py` on {platform.machine()}, Python "
             f"{platform.python_version()}, {time.strftime('%Y-%m-%d')}, in one run (medians; uncached reads). Both "
             "routes give the same Frac (checked).", "",
             "| formula | hkproof parser | sympy path (old) | parser faster by |", "|---|---:|---:|---:|", *rows]
    print(write_section(DOC, "parsing", ["## Reading formulas", "", *lines]))


if __name__ == "__main__":
    main()
