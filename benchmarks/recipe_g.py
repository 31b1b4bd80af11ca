"""Recipe (G) against direct substitution: which wins, when. Writes docs/performance-recipe-g.md.

Methods: substitution (h(N/Delta) - h in lowest terms), recipe (G) by elimination of x~ (cofactors built, then the
identity det M^k delta = sum lambda_i E_i checked by expansion), and recipe (G) literally: a Groebner basis of the
Kahan ideal by FLINT's Buchberger plus a normal form (parameters fixed to numbers; stopped at a size limit).
"""
from __future__ import annotations

import argparse
import time
from pathlib import Path

import singular_peer
from docs_section import write_section
from timebox import in_child

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.integrals import check_integral
from hkproof.hk.recipe_g import adjugate_data, delta_polynomial, groebner_membership, recipe_g
from hkproof.theorems._clebsch import named
from hkproof.theorems.clebsch_flows.data import yz_map
from hkproof.theorems.clebsch_flows.general import E_PAPER, GENERAL_CLAIM, GENERAL_NAMES, SECOND

J = "(p1**2 + p2**2 + p3**2)/(1 - eps**2*(w1*p1**2 + w2*p2**2 + w3*p3**2))"
C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"
D1 = "a2*(1 - eps**2*a3*a1*x2**2)/(a2*x1**2 - a1*x2**2)"
GB_LIMITS = (400, 4000, 4096)


def _general_l(kmap):
    known = {k: named(kmap, v, {}) for k, v in GENERAL_NAMES.items() if k.startswith("c")}
    known.update({k: named(kmap, v, known) for k, v in GENERAL_NAMES.items() if k.startswith("E")})
    a, d = named(kmap, GENERAL_CLAIM["A"], known), named(kmap, GENERAL_CLAIM["D"], known)
    return a / d


def cases(full: bool):
    """(label, map, integral, fixed parameters or None)."""
    et = kahan_map("euler-top")
    out = [("Euler top c1 (a symbolic)", et, Frac.parse(et.ring, C1), None),
           ("Euler top d1 (a symbolic)", et, Frac.parse(et.ring, D1), None)]
    et_fixed = kahan_map(et.field.specialize({"a1": 2, "a2": 3, "a3": -5}))
    out.append(("Euler top c1 (a = 2, 3, -5)", et_fixed,
                Frac.parse(et.ring, C1).specialize({"a1": 2, "a2": 3, "a3": -5}, et_fixed.ring), "fixed"))
    cl = kahan_map("clebsch")
    out.append(("Clebsch flow 1, J (w symbolic)", cl, Frac.parse(cl.ring, J), None))
    w = {"w1": 2, "w2": -3, "w3": 5}
    cl_fixed = kahan_map(cl.field.specialize(w))
    out.append(("Clebsch flow 1, J (w = 2, -3, 5)", cl_fixed, Frac.parse(cl.ring, J).specialize(w, cl_fixed.ring),
                "fixed"))
    f2 = kahan_map("clebsch-flow2")
    l2 = named(f2, SECOND["L"], {k: Frac.parse(f2.ring, v) for k, v in E_PAPER.items()})
    out.append(("Clebsch flow 2, L (w symbolic)", f2, l2, None))
    f2_fixed = kahan_map(f2.field.specialize(w))
    out.append(("Clebsch flow 2, L (w = 2, -3, 5)", f2_fixed, l2.specialize(w, f2_fixed.ring), "fixed"))
    g = yz_map()
    g_fixed = kahan_map(g.field.specialize(w))
    out.append(("general flow, L_b (w = 2, -3, 5; y, z symbolic)", g_fixed, _general_l(g).specialize(w, g_fixed.ring),
                None))
    if full:
        out.append(("general flow, L_b (w, y, z symbolic)", g, _general_l(g), None))
    return out


def _timed(fn):
    start = time.perf_counter()
    value = fn()
    return value, time.perf_counter() - start


def _gb_worker(label, queue):
    for lab, kmap, h, fixed in cases(False):
        if lab == label:
            queue.put(_timed(lambda: groebner_membership(kmap, h, 2, GB_LIMITS)))


def groebner_with_timeout(label: str, seconds: float):
    """Buchberger in a child process, killed after `seconds` (its own pid, nothing else)."""
    return in_child(_gb_worker, (label,), seconds) or (None, seconds)


def singular_membership(kmap, h, power: int, seconds: int) -> tuple[float | None, float | None]:
    """Singular's lift and std + reduce on the same Kahan ideal and the same target det M^k delta."""
    _, delta, _ = adjugate_data(kmap)
    return singular_peer.membership_seconds(kmap.field.tilde_ring.names, list(kmap.equations),
                                            delta ** power * delta_polynomial(kmap, h), seconds)


def run(full: bool, gb_seconds: float) -> list[dict]:
    rows = []
    for label, kmap, h, fixed in cases(full):
        sub, t_sub = _timed(lambda: check_integral(kmap, h).status.label)
        res, t_g = _timed(lambda: recipe_g(kmap, h))
        lift, std = singular_membership(kmap, h, res.power, int(gb_seconds))
        row = {"case": label, "substitution": t_sub, "sub_verdict": sub, "recipe_g": t_g,
               "cofactors": res.seconds["cofactors"], "check": res.seconds["check"], "terms": res.certificate_terms,
               "g_verdict": res.status.label, "gb": None, "gb_verdict": "-", "lift": lift, "std": std}
        if fixed:
            verdict, t_gb = groebner_with_timeout(label, gb_seconds)
            row["gb"], row["gb_verdict"] = t_gb, {True: "in I", False: "not in I", None: "stopped"}[verdict]
        rows.append(row)
        print(row, flush=True)
    return rows


def _ratio(row: dict, limit: float) -> str:
    """Singular's faster route over recipe (G); a lower bound where neither finished (Singular times are in ms)."""
    done = [t for t in (row["lift"], row["std"]) if t is not None]
    ours = max(row["recipe_g"], 1e-4)
    if not done:
        return f"> {limit / ours:.0f}x"
    best = max(min(done), 0.001)
    return f"{best / ours:.1f}x" if min(done) > 0 else "< 1 ms both"


def write_markdown(rows: list[dict], path: Path, gb_seconds: float) -> None:
    lines = ["Generated by `python benchmarks/recipe_g.py` (2-core machine shared with other jobs; one run, wall "
             "seconds). Every verdict is exact. *substitution*: h(N/Delta) - h = 0 in lowest terms. *recipe (G)*: "
             "cofactors of det M^k delta = sum lambda_i E_i built by eliminating x~ (adjugate of M, divided "
             "differences) in the factored form lambda = adj(M)^T q, then the identity expanded as "
             "sum_j q_j (adj(M) E)_j; *Buchberger*: FLINT `buchberger_naive` + `autoreduction` "
             f"on the Kahan ideal with the parameters fixed, normal form of det M^2 delta (limit {GB_LIMITS}, "
             f"killed after {gb_seconds:.0f} s). *Singular* (the peer, same ideal and same target det M^k delta, "
             "variables as ring variables, dp): `lift` (cofactors) and `std` + `reduce` (normal form), each in its "
             f"own run, stopped after {gb_seconds:.0f} s (—: did not finish; n/a: Singular not installed).", "",
             "| case | substitution (s) | recipe (G) total (s) | cofactors / check (s) | terms of q and adj(M) | "
             "Buchberger + normal form (s) | Singular lift (s) | Singular std + reduce (s) | Singular's best / recipe (G) |",
             "|---|---|---|---|---|---|---|---|---|"]
    have = singular_peer.singular_executable() is not None
    for r in rows:
        gb = "-" if r["gb"] is None else f"{r['gb']:.3f} ({r['gb_verdict']})"
        peer = [("n/a" if not have else f"> {gb_seconds:.0f}" if t is None else f"{t:.3f}") for t in (r["lift"], r["std"])]
        lines.append(f"| {r['case']} | {r['substitution']:.3f} | {r['recipe_g']:.3f} | {r['cofactors']:.3f} / "
                     f"{r['check']:.3f} | {r['terms']} | {gb} | {peer[0]} | {peer[1]} | "
                     f"{_ratio(r, gb_seconds) if have else 'n/a'} |")
    print(write_section(path, "recipe-g", lines))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--full", action="store_true",
                        help="also recipe (G) for the general flow with w, y, z symbolic (slow, large)")
    parser.add_argument("--gb-seconds", type=float, default=60.0)
    parser.add_argument("--out", default=str(Path(__file__).resolve().parents[1] / "docs" / "performance-recipe-g.md"))
    args = parser.parse_args()
    rows = run(args.full, args.gb_seconds)
    write_markdown(rows, Path(args.out), args.gb_seconds)
