"""Speed against accuracy for algorithm (N) and recipe (E); numbers for docs/performance-experiments.md.

Run: python benchmarks/experiments_speed_accuracy.py [profiles] [pslq] [orbits] [timing]
Charts go to docs/figures/experiments_*.png, numbers to benchmarks/results/experiments.json.
"""
from __future__ import annotations

import json
import random
import statistics
import sys
import time
from fractions import Fraction
from pathlib import Path

import flint
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from hkproof.dynamics import kahan_map  # noqa: E402
from hkproof.experiments import ExactQ, Float64, Modular, MPMath, ProfileProblem, make_scene, parse_basis, scan  # noqa: E402
from hkproof.algebra.sampling import random_rationals  # noqa: E402
from hkproof.experiments.points import near_singular_point  # noqa: E402
from hkproof.experiments.pslq import agreement, pslq_relations  # noqa: E402
from hkproof.experiments.relations import find_relations  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
FIGS = ROOT / "docs" / "figures"
RESULTS = ROOT / "benchmarks" / "results" / "experiments.json"
VALUES = {"eps": "1/10", "w1": "1/10", "w2": "1/5", "w3": "3/10"}
PHI0 = "p1**2, p2**2, p3**2, 1"
MAX = "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, m1*p1, m2*p2, m3*p3, 1"
PSI = "p1**2, p2**2, p3**2, m1*p1, m2*p2, m3*p3"
FLOW2 = "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, 1"


def _fmpq(x):
    return [flint.fmpq(v.numerator, v.denominator) for v in x]


def profiles(n: int = 12) -> dict:
    """Time per point and share of points with the exact profile, per arithmetic and class of points."""
    f = kahan_map("clebsch")
    rng = random.Random(7)
    classes = {
        "easy (Phi0, eps 1/10)": (VALUES, PHI0, lambda sc: random_rationals(rng, len(f.variables))),
        "long orbits (10 functions)": (VALUES, MAX, lambda sc: random_rationals(rng, len(f.variables))),
        "large eps (10 functions, eps 1)": ({**VALUES, "eps": "1"}, MAX, lambda sc: random_rationals(rng, len(f.variables))),
        "near Delta = 0 (Phi0)": (VALUES, PHI0, lambda sc: near_singular_point(sc, rng, Fraction(1, 10**9))),
    }
    arithmetics = [ExactQ(), Modular(), Float64(), MPMath(30), MPMath(60), _named(MPMath(30, confirm="never"),
                                                                                  "mpmath(30), one precision")]
    out = {}
    for cname, (values, basis, draw) in classes.items():
        problem = ProfileProblem(make_scene(f, values), parse_basis(f.ring, basis))
        points = [draw(problem.scene) for _ in range(n)]
        reference = [problem.profile(x, ExactQ(), with_kernel=False).dims for x in points]
        out[cname] = {}
        for ar in arithmetics:
            times, right, wrong, undecided = [], 0, 0, 0
            for x, ref in zip(points, reference):
                t = time.perf_counter()
                p = problem.profile(x, ar, with_kernel=False)
                times.append(time.perf_counter() - t)
                if p.dims == ref:
                    right += 1
                elif p.verdict in ("ambiguous", "singular"):
                    undecided += 1
                else:
                    wrong += 1
            out[cname][ar.name] = {"seconds_per_point": statistics.median(times), "right": right / n,
                                   "wrong": wrong / n, "undecided": undecided / n}
            print(cname, ar.name, out[cname][ar.name], flush=True)
    plot_profiles(out)
    return out


def plot_profiles(out: dict) -> None:
    fig, ax = plt.subplots(figsize=(8, 5.5))
    names = list(next(iter(out.values())))
    markers = dict(zip(names, "osD^vx"))
    colors = dict(zip(out, ["tab:green", "tab:blue", "tab:orange", "tab:red"]))
    for cname, row in out.items():
        for aname, r in row.items():
            ax.scatter(r["seconds_per_point"], r["right"] + 0.01 * list(markers).index(aname), marker=markers[aname],
                       color=colors[cname], s=60, label=None)
            if r["wrong"]:
                ax.annotate(f"{r['wrong']:.0%} wrong", (r["seconds_per_point"], r["right"]), fontsize=7)
    for aname, m in markers.items():
        ax.scatter([], [], marker=m, color="gray", label=aname)
    for cname, c in colors.items():
        ax.scatter([], [], marker="s", color=c, label=cname)
    ax.set_xscale("log")
    ax.set_xlabel("median time per point [s] (Clebsch, one core)")
    ax.set_ylabel("share of points with the exact profile")
    ax.set_ylim(-0.05, 1.1)
    ax.legend(fontsize=7, loc="center right")
    ax.set_title("algorithm (N): speed against accuracy\n(points not right are 'ambiguous' unless marked 'wrong')")
    fig.tight_layout()
    fig.savefig(FIGS / "experiments_profiles_speed_accuracy.png", dpi=110)


def _named(arithmetic, name: str):
    arithmetic.name = name
    return arithmetic


def pslq(digit_list=(6, 8, 10, 12, 15, 20, 30)) -> dict:
    """PSLQ at several precisions against exact relation finding (time, share of relations right)."""
    cases = {"clebsch Phi0": ("clebsch", PHI0), "clebsch Psi": ("clebsch", PSI),
             "flow2 Phi0": ("clebsch-flow2", FLOW2)}
    at = {k: Fraction(v) for k, v in VALUES.items()}
    out = {}
    for cname, (system, basis) in cases.items():
        f = kahan_map(system)
        t = time.perf_counter()
        exact = find_relations(f, [basis])
        out[cname] = {"exact": {"seconds": time.perf_counter() - t, "dimension": exact.dimension,
                                "found": len(exact.relations)}}
        for digits in digit_list:
            p = pslq_relations(f, [basis], VALUES, digits=digits)
            right, recovered = agreement(p, exact.relations, at)
            out[cname][f"pslq {digits}"] = {"seconds": p.seconds, "share_recovered": recovered / exact.dimension,
                                            "wrong": len(p.relations) - right, "rejected": p.rejected}
            print(cname, digits, out[cname][f"pslq {digits}"], flush=True)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    for cname, row in out.items():
        ds = list(digit_list)
        a.plot(ds, [row[f"pslq {d}"]["share_recovered"] for d in ds], "o-", label=f"PSLQ, {cname}")
        b.plot(ds, [row[f"pslq {d}"]["seconds"] for d in ds], "o-", label=f"PSLQ, {cname}")
        b.axhline(row["exact"]["seconds"], ls="--", color=a.lines[-1].get_color(), label=f"exact, {cname}")
    a.axhline(1.0, color="k", lw=0.5)
    a.set_xlabel("PSLQ digits")
    a.set_ylabel("share of the exact relations recovered (none wrong)")
    b.set_xlabel("PSLQ digits")
    b.set_ylabel("seconds (PSLQ: one parameter point; exact: symbolic)")
    b.set_yscale("log")
    for ax in (a, b):
        ax.legend(fontsize=7)
    fig.suptitle("recipe (E): PSLQ at several precisions against exact relation finding")
    fig.tight_layout()
    fig.savefig(FIGS / "experiments_pslq_vs_exact.png", dpi=110)
    return out


def orbits(steps: int = 40) -> dict:
    """Float orbits against exact ones: error and cost per iterate, and the size of exact iterates."""
    f = kahan_map("clebsch")
    scene = make_scene(f, VALUES)
    x0 = _fmpq([Fraction(1, 2), Fraction(-1, 3), Fraction(2, 5), Fraction(3, 4), Fraction(-2, 7), Fraction(1, 3)])
    ex, fl = ExactQ(), Float64()
    pe, pf = ex.prepare(scene, []), fl.prepare(scene, [])
    exact, t_exact = [list(x0)], []
    for _ in range(steps):
        t = time.perf_counter()
        exact.append(ex.step(pe, exact[-1]))
        t_exact.append(time.perf_counter() - t)
    floats, t_float = [[float(v) for v in x0]], []
    for _ in range(steps):
        t = time.perf_counter()
        floats.append(fl.step(pf, floats[-1]))
        t_float.append(time.perf_counter() - t)
    estimate = fl.orbit_errors(pf, floats)[0]
    err = [float(np.linalg.norm(np.array(a) - np.array([float(v) for v in e])) /
                 np.linalg.norm([float(v) for v in e])) for a, e in zip(floats, exact)]
    bits = [max(int(v.p).bit_length() + int(v.q).bit_length() for v in x) for x in exact]
    ks = np.arange(steps + 1)
    quad = np.polyfit(ks, bits, 2)
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(14, 4.2))
    a.plot(ks, bits, "o", ms=3, label="exact iterate")
    a.plot(ks, np.polyval(quad, ks), "-", label=f"quadratic fit {quad[0]:.1f} k^2")
    a.set_xlabel("iterate k")
    a.set_ylabel("bits of the largest coordinate (num + den)")
    a.set_title("size of exact iterates")
    b.semilogy(ks, np.maximum(err, 1e-17), "o-", ms=3, label="float64: actual relative error")
    b.semilogy(ks, estimate, "--", label="hkproof's first-order estimate")
    b.set_xlabel("iterate k")
    b.set_title("error of float orbits")
    c.semilogy(ks[1:], t_exact, label="exact step (fmpq_mat solve)")
    c.semilogy(ks[1:], t_float, label="float64 step (numpy)")
    c.set_xlabel("iterate k")
    c.set_ylabel("seconds per step")
    c.set_title("cost per iterate")
    for ax in (a, b, c):
        ax.legend(fontsize=7)
    fig.suptitle("float orbits against exact orbits (Clebsch, eps = 1/10, omega = (1/10, 1/5, 3/10))")
    fig.tight_layout()
    fig.savefig(FIGS / "experiments_float_vs_exact_orbits.png", dpi=110)
    return {"bits": bits, "quadratic_fit": list(quad), "float_error": err, "estimate": estimate,
            "seconds_exact_step": t_exact, "seconds_float_step": t_float}


def timing(n: int = 20) -> dict:
    """The acceptance benchmark: the 10-function Clebsch basis at one point, exact and modular."""
    f = kahan_map("clebsch")
    problem = ProfileProblem(make_scene(f, VALUES), parse_basis(f.ring, MAX))
    rng = random.Random(11)
    points = [_fmpq(random_rationals(rng, len(f.variables))) for _ in range(n)]
    out = {}
    for name, ar in [("exact", ExactQ()), ("modular (2 primes)", Modular()), ("modular (1 prime)", Modular(checks=0)),
                     ("float", Float64()), ("mpmath(30)", MPMath(30))]:
        ar.profile(problem.scene, problem.compiled, points[0])      # warm the caches
        times = []
        for x in points:
            t = time.perf_counter()
            ar.profile(problem.scene, problem.compiled, x)
            times.append(time.perf_counter() - t)
        out[name] = {"median_ms": 1e3 * statistics.median(times), "max_ms": 1e3 * max(times)}
        print(name, out[name], flush=True)
    out["ratio exact / modular (2 primes)"] = out["exact"]["median_ms"] / out["modular (2 primes)"]["median_ms"]
    out["ratio exact / modular (1 prime)"] = out["exact"]["median_ms"] / out["modular (1 prime)"]["median_ms"]
    for label, executor in [("scan 32 points, serial", _Serial()), ("scan 32 points, process pool", None)]:
        t = time.perf_counter()
        scan("clebsch", MAX, points=32, values=VALUES, arithmetic="exact", with_kernel=False, executor=executor)
        out[label + " [s]"] = time.perf_counter() - t
        print(label, out[label + " [s]"], flush=True)
    return out


class _Serial:
    """An executor that runs submitted work at once (to time a scan without processes)."""

    def submit(self, fn, *args):
        from concurrent.futures import Future
        fut = Future()
        fut.set_result(fn(*args))
        return fut


def main() -> None:
    FIGS.mkdir(parents=True, exist_ok=True)
    RESULTS.parent.mkdir(parents=True, exist_ok=True)
    results = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    jobs = {"timing": timing, "profiles": profiles, "pslq": pslq, "orbits": orbits}
    if sys.argv[1:] == ["replot"]:
        plot_profiles(results["profiles"])
        return
    for name in sys.argv[1:] or jobs:
        results[name] = jobs[name]()
        RESULTS.write_text(json.dumps(results, indent=1, default=float))


if __name__ == "__main__":
    main()
