"""The three exact routes of `hk.row_check.decide_identity` side by side in one run: Horner's scheme expanded over Z,
at the points of a unisolvent lattice in the parameters, and modulo word-size primes beyond twice a proven
coefficient bound, each on the same row identities that real block proofs meet, with the cost model's estimates,
time and peak memory. Writes the section "Three routes for exact identities" of docs/performance-frontier.md.

    python benchmarks/routes.py            # so(4) Manakov (discover) and the second Clebsch flow (prove), ~15 min

The identities are captured from `discover so4-euler-top` and the claim `flow-second-bases-345` (each row with an
iterate is checked by all three routes where the proof meets it); one more is the first so(4) row with a2 set to
10^12 + 39 (a specialization of that identity, so a true identity, with coefficients of hundreds of bits). Each
route runs in a forked child; its memory is the child's peak resident set (with its own children) less its size at
the fork.
"""
from __future__ import annotations

import argparse
import os
import pickle
import platform
import re
import resource
import time
from pathlib import Path
from typing import Any

import flint

from hkproof.algebra.ring import cores
from hkproof.budget import Budget
from hkproof.hk import row_check
from hkproof.orchestration.registry import get_claim
from hkproof.pipelines.discover import discover

DOC = Path(__file__).resolve().parents[1] / "docs" / "performance-frontier.md"
SECTION = "## Three routes for exact identities"
ROUTES: tuple[row_check.Route, ...] = ("horner", "lattice", "modular")
ROWS: list[dict[str, Any]] = []
BIG = {"a2": 10 ** 12 + 39}
CURRENT = {"system": ""}                                # the proof whose identities are being captured
HONEST = row_check.decide_identity                      # the spy below takes its place in the module


def _rss_kb() -> int:
    with open("/proc/self/status") as status:
        return next(int(line.split()[1]) for line in status if line.startswith("VmRSS:"))


def in_child(route: row_check.Route, terms, factors, names, free) -> tuple[bool, float, float]:
    """(verdict, seconds, peak MB above the size at the fork) of one route, in a forked child."""
    read_end, write_end = os.pipe()
    pid = os.fork()
    if pid == 0:
        os.close(read_end)
        base = _rss_kb()
        start = time.perf_counter()
        holds = HONEST(terms, factors, names, free, route, "row", "N").holds
        seconds = time.perf_counter() - start
        peak = max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss,
                   resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
        with os.fdopen(write_end, "wb") as out:
            pickle.dump((holds, seconds, (peak - base) / 1024), out)
        os._exit(0)
    os.close(write_end)
    with os.fdopen(read_end, "rb") as answer:
        result = pickle.load(answer)
    os.waitpid(pid, 0)
    return result


def measure(label: str, terms, factors, names, free) -> dict[str, Any]:
    costs = row_check.RouteCosts(terms, factors, names, free)
    row: dict[str, Any] = {"label": label, "costs": costs.costs, "bits": costs.modular.bound.bit_length(),
                           "primes": len(costs.modular.primes), "chosen": costs.cheapest,
                           "plan": costs.lattice, "sizes": (max(len(t) for t in terms.values()),
                                                               max(len(f) for f in factors))}
    for route in ROUTES:
        row[route] = in_child(route, terms, factors, names, free)
    ROWS.append(row)
    print({k: v for k, v in row.items() if k != "plan"}, flush=True)
    return row


def spy():
    """decide_identity that times every route on each row identity with parameters; the proof goes on with the
    verdict of the expansion over Z measured there (an exact check, not run twice)."""
    def each(terms, factors, names, free, route, what, where):
        if not free[1:]:
            return HONEST(terms, factors, names, free, route, what, where)
        system = CURRENT["system"]
        row = measure(f"{system}, {what}", terms, factors, names, free)
        if system.startswith("so4") and not any(r["label"].startswith("so4, a2") for r in ROWS):
            specialized = [{mu: t.subs(BIG) for mu, t in terms.items()}, [f.subs(BIG) for f in factors]]
            measure(f"so4, a2 = 10^12 + 39, {what}", *specialized, names, tuple(n for n in free if n not in BIG))
        return row_check.RowCheck(row["horner"][0], f"{what} by Horner's scheme in {where}, expanded", "horner")
    return each


def table() -> str:
    out = [SECTION, "",
           f"Measured by `benchmarks/routes.py` in one run on {platform.node() or 'this machine'} ({cores()} cores, "
           f"python-flint {flint.__version__}): every row identity with an iterate that `discover so4-euler-top` and "
           "the claim `flow-second-bases-345` meet, decided by each of the three exact routes of "
           "`hk.row_check.decide_identity` one after the other, each in a forked child (memory: its peak resident "
           "set above its size at the fork). The modular route's primes are the largest below 2^63, as many as make "
           "their product exceed twice the proven coefficient bound; the primes are shared by two children. `model` "
           "is the cost model's estimate (term products, weighted; `hk.row_check.RouteCosts`) for expanded / "
           "lattice / modular, and `chosen` what the automatic route takes.", "",
           "| identity | largest T, F (terms) | bound (bits), primes | lattice (names; degrees; points) | model: "
           "expanded / lattice / modular | chosen | expanded | lattice | modular | verdicts |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for r in ROWS:
        p = r["plan"]
        lattice = f"{', '.join(p.lattice)}; {p.degree} ({', '.join(map(str, p.degrees))}); {p.points}" if p else "-"
        model = " / ".join(f"{r['costs'][k]:.2e}" if k in r["costs"] else "-" for k in ROUTES)
        cells = [f"{r[k][1]:.1f} s, {r[k][2]:.0f} MB" for k in ROUTES]
        verdicts = " / ".join(str(r[k][0]) for k in ROUTES)
        out.append(f"| {r['label']} | {r['sizes'][0]}, {r['sizes'][1]} | {r['bits']}, {r['primes']} | {lattice} | "
                   f"{model} | {r['chosen']} | {' | '.join(cells)} | {verdicts} |")
    return "\n".join(out) + "\n"


def write(section: str) -> None:
    """Replace (or add) the section in docs/performance-frontier.md, keeping the rest of the page."""
    text = DOC.read_text() if DOC.exists() else "# Performance at the frontier\n\n"
    pattern = re.compile(re.escape(SECTION) + r"\n.*?(?=\n## |\Z)", re.S)
    text = pattern.sub(lambda _: section.rstrip("\n") + "\n", text) if SECTION in text else \
        text.rstrip("\n") + "\n\n" + section
    DOC.write_text(text)


def main() -> None:
    argparse.ArgumentParser(description=__doc__).parse_args()
    row_check.decide_identity = spy()
    CURRENT["system"] = "so4"
    discover("so4-euler-top", 2, budget=Budget(1200))
    CURRENT["system"] = "clebsch-flow2"
    get_claim("flow-second-bases-345").prove()
    section = table()
    write(section)
    print(section)
    print(f"wrote {DOC}")


if __name__ == "__main__":
    main()
