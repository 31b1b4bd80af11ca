"""Benchmark (not a test) of section 6, part I: proofs and heavy stages, beside Maple (paper), Singular and sympy.

    python benchmarks/clebsch_part1.py [--f2] [--out docs/performance-clebsch.md]

--f2 adds the second iterate (several minutes). Singular runs when the `Singular` binary is on PATH; sympy
stages run in a subprocess capped at --sympy-seconds (default 600).
"""
from __future__ import annotations

import argparse
import platform
import resource
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import singular_peer
from hkproof.algebra.fraction import Frac, homogenized_compose
from hkproof.algebra.linalg import cleared_system, cramer, solve_cleared
from hkproof.dynamics.catalogue import get_system, kahan_map
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.reduced import Relation, hk_row
from hkproof.hk.second_iterate import interpolated_gcd
from hkproof.orchestration.registry import get_claim, proven, select
from hkproof.theorems._clebsch import CYCLIC_SHIFT, TRANSLATION, X, named, recall
from hkproof.theorems.clebsch_bases import THETA_BASIS, THETA_TARGET, theta_relation
from hkproof.theorems.clebsch_f2 import OMEGA_POINTS, w_form_degree

GROUPS = ["clebsch-map", "clebsch-bases", "clebsch-kernels"]
# the claims of items 1, 2, 4, 5, 6 of the issue (the continuous system, the map, Th. "dC basis 1", "dC basis 2",
# "dC Theta" with the dependence of g_k on J, d7, d8)
ITEMS = ["dc-continuous-integrals", "dc-map-equations", "dc-explicit-map", "dc-map-symmetries", "dc-reversibility",
         "dc-complexity", "dc-basis1-relations", "dc-basis1-even", "dc-basis2", "dc-basis2-independence",
         "dc-theta", "dc-theta-dependence"]
PAPER = {"Cramer solve, dC basis 1 (one relation + Prop. even)": "22.33 s, 32.43 MB (Maple, Core Duo 1.83 GHz)"}


NOTES = """\
- Proof times: a claim that cites another reuses its certificate (computed once per process), so e.g.
  dc-max-basis-bounds shows only its own steps; the all-in figure above counts each claim once.
- Th. "dC Theta": the Clebsch system depends on w only through w_i - w_j, so the proof solves and checks the
  reduced system on the slice w3 = 0 (every ingredient is checked to be invariant) and lifts the solution by
  w_k -> w_k - w3; the two Cramer rows above are the same computation in the full ring and on the slice. The
  Singular column runs det, the Cramer numerator of g1 and its gcd with det on the very matrix hkproof solves.
- The paper's only timing (Th. "dC basis 1", route (D): 22.33 s, 32.43 MB in Maple on a 1.83 GHz Core Duo)
  compares with the rows and the Cramer solve of that system here together (the note of the solve row). The
  Singular column of a solve row times the same thing as the hkproof column: det, the Cramer numerators and
  their gcds on rows built from the same N (Singular builds its rows before its timer starts, as hkproof does
  in the separate rows row).
- f^2: Singular composes with one ring map (Delta homogenized in (m, p) only), and finds the same 1 542 462
  terms. A direct FLINT gcd of Delta_h(N, Delta) and P1_h(N, Delta) took 444-587 s in exploratory runs on
  this (loaded) machine, slower than Singular's direct gcd; hkproof does not use it: it interpolates g from
  16 gcds at numeric w and proves it by exact division and coprimality (the interpolation and one division
  are the f^2 rows above; the coprimality test takes under a second).
- sympy: det M and the six Cramer numerators of f (Berkowitz, expanded) finish in seconds; earlier versions of
  this page reported the numerators as unfinished, because the benchmark's sympy script crashed (an in-place
  column deletion returned None) and a crash was counted as a timeout. A crash now stops the benchmark.
  f^2 was not attempted in sympy.
"""


def timed(fn):
    start = time.perf_counter()
    value = fn()
    return value, time.perf_counter() - start


def stages(with_f2: bool) -> tuple[list[tuple[str, float, str]], dict]:
    """Our heavy stages: (name, seconds, note), and the polynomials the peers recompute."""
    rows = []
    kmap = KahanMap(get_system("clebsch"))  # fresh: nothing cached
    _, t = timed(lambda: kmap.matrix)
    rows.append(("the Kahan equations and the matrix M", t, "eq. \"dC\""))
    (nums, delta), t = timed(lambda: kmap.explicit)
    rows.append(("f = M^-1 (m, p): det M and Cramer numerators", t, f"Delta {len(delta)} terms; with the gcd check"))
    r = kmap.ring
    p2 = [named(kmap, v) for v in ("p1**2", "p2**2", "p3**2")]
    rel = Relation([Frac(r, 1), Frac(r, -1), Frac(r, 0)], named(kmap, "eps**2*(w1 - w2)"))
    systems = {
        "Cramer solve, dC basis 1 (one relation + Prop. even)": (p2, Frac(r, 1), rel, None),
        "Cramer solve, dC basis 2 (eq. dC ansatz_2_final)": (
            [named(kmap, v) for v in ("m1*p1", "m2*p2", "m3*p3")], named(kmap, "H3"),
            Relation([named(kmap, v) for v in ("w2 - w3", "w3 - w1", "w1 - w2")], Frac(r, 0)), None),
    }
    for name, (basis, target, relation, cols) in systems.items():
        rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        (rws, rhs), t_rows = timed(lambda: tuple(zip(*(hk_row(kmap, basis, target, i) for i in (0, 1)))))
        _, t = timed(lambda: cramer(list(rws) + [relation.coefficients], list(rhs) + [relation.rhs], columns=cols))
        rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        rows.append((f"rows i = 0, 1 of the {name.split(', ')[1]} system (pullbacks by f, lowest terms)", t_rows, ""))
        rows.append((name, t, f"rows and solve {t_rows + t:.3f} s; peak RSS {rss / 1024:.0f} MB "
                              f"(+{(rss - rss0) / 1024:.0f} MB)"))
    polys = {"nums": nums, "delta": delta}
    if with_f2:
        for key, p in (("Delta_h(N, Delta)", delta), ("P1_h(N, Delta)", nums[3]), ("M1_h(N, Delta)", nums[0])):
            q, t = timed(lambda: homogenized_compose(r, p, X, nums, delta)[0])
            rows.append((f"f^2 plain compose: {key}", t, f"{len(q)} terms"))
            polys[key] = q
        g, t = timed(lambda: interpolated_gcd(kmap, delta, nums[3], OMEGA_POINTS, w_form_degree, CYCLIC_SHIFT,
                                              TRANSLATION))
        rows.append((f"f^2 common factor g (gcds at {len(OMEGA_POINTS)} numeric w, their index-shift orbits moved to "
                     "w3 = 0, interpolation)", t, f"{len(g)} terms"))
        (_, rem), t = timed(lambda: divmod(polys["Delta_h(N, Delta)"], g))
        rows.append(("f^2: exact division Delta_h / g", t, "remainder 0" if rem.is_zero() else "NOT exact"))
    return rows, polys


def theta_stages(seconds: int) -> list[tuple[str, float, str, float | None]]:
    """Th. "dC Theta": one Cramer component with its cancellation, in the full ring and on the slice w3 = 0, in
    FLINT and in Singular on the same cleared matrix [A | b]: (stage, FLINT s, note, Singular s)."""
    kmap = kahan_map("clebsch")
    r = kmap.ring
    b2 = proven("dc-basis2")
    rel = theta_relation(kmap, get_claim("dc-theta").claimed["additional"],
                         {k: recall(b2, k, r) for k in ("d7", "d8", "d9")})
    basis, target = [named(kmap, t) for t in THETA_BASIS], named(kmap, THETA_TARGET)
    out = []
    for where, f, restrict in (("full ring", kmap, lambda h: h),
                               (f"slice {TRANSLATION.pivot} = 0", TRANSLATION.slice_map(kmap), TRANSLATION.restrict)):
        rows, rhs = zip(*(hk_row(f, [restrict(b) for b in basis], restrict(target), i) for i in (0, 1)))
        a, b, common = cleared_system(list(rows) + [[restrict(c) for c in rel.coefficients]],
                                      list(rhs) + [restrict(rel.rhs)])

        ((g1,), d), t = timed(lambda: solve_cleared(f.ring, a, b, common, [0]))
        out.append((f"Cramer component g1, dC Theta, {where}", t,
                    f"det {len(d)} terms; g1 {len(g1.num)}/{len(g1.den)} terms",
                    singular_peer.cramer_seconds(f.ring.names, a, b, [0], seconds)))
    return out


def items_from_scratch() -> float:
    """Wall seconds, in a fresh process (imports excluded), to prove every claim of items 1, 2, 4, 5, 6 once,
    with the claims they cite."""
    code = textwrap.dedent(f"""
        import time
        from hkproof.orchestration.registry import load_all, proven
        load_all()
        t = time.perf_counter()
        assert all(proven(c).status.label == "verified" for c in {ITEMS!r})
        print(time.perf_counter() - t)
    """)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return float(res.stdout.strip().splitlines()[-1])


def proofs() -> list[tuple[str, float, str]]:
    out = []
    for c in select(groups=GROUPS):
        cert = proven(c.id)
        out.append((c.id, cert.seconds, cert.status.label))
    return out


# ---- peers ---------------------------------------------------------------------------------------------------
def singular_script(with_f2: bool) -> str:
    """The same stages in Singular: det M, the Cramer numerators of f, and (with f2) f^2 and its gcd."""
    m = "matrix M[6][6] = 1,0,0,0,eps*(w2-w3)*p3,eps*(w2-w3)*p2, 0,1,0,eps*(w3-w1)*p3,0,eps*(w3-w1)*p1, " \
        "0,0,1,eps*(w1-w2)*p2,eps*(w1-w2)*p1,0, 0,eps*p3,-eps*p2,1,-eps*m3,eps*m2, " \
        "-eps*p3,0,eps*p1,eps*m3,1,-eps*m1, eps*p2,-eps*p1,0,-eps*m2,eps*m1,1;"
    return textwrap.dedent(f"""
        system("--ticks-per-sec", 1000);
        ring R = 0, (m1,m2,m3,p1,p2,p3,eps,w1,w2,w3), dp;
        {m}
        int t0 = rtimer; poly D = det(M); int t1 = rtimer;
        print("STAGE det M " + string(t1 - t0) + " " + string(size(D)));
        matrix b[6][1] = m1,m2,m3,p1,p2,p3;
        t0 = rtimer; list N; int j; matrix Mj[6][6];
        int i; for (j = 1; j <= 6; j++) {{ Mj = M; for (i = 1; i <= 6; i++) {{ Mj[i, j] = b[i, 1]; }} N[j] = det(Mj); }}
        t1 = rtimer;
        print("STAGE Cramer numerators of f " + string(t1 - t0) + " " + string(size(N[4])));
        proc cramer3(matrix A, matrix B)
        {{
          poly d = det(A); int k; int l; matrix Ak[3][3]; poly n; poly g;
          for (k = 1; k <= 3; k++) {{ Ak = A; for (l = 1; l <= 3; l++) {{ Ak[l, k] = B[l, 1]; }}
                                     n = det(Ak); g = gcd(n, d); }}
          return(size(d));
        }}
        matrix A[3][3] = p1^2, p2^2, p3^2, N[4]^2, N[5]^2, N[6]^2, 1, -1, 0;
        matrix B[3][1] = 1, D^2, eps^2*(w1 - w2);
        t0 = rtimer; int sz = cramer3(A, B); t1 = rtimer;
        print("STAGE Cramer solve, dC basis 1 " + string(t1 - t0) + " " + string(sz));
        A = m1*p1, m2*p2, m3*p3, N[1]*N[4], N[2]*N[5], N[3]*N[6], w2 - w3, w3 - w1, w1 - w2;
        B = p1^2 + p2^2 + p3^2, N[4]^2 + N[5]^2 + N[6]^2, 0;
        t0 = rtimer; sz = cramer3(A, B); t1 = rtimer;
        print("STAGE Cramer solve, dC basis 2 " + string(t1 - t0) + " " + string(sz));
        {f2_block(with_f2)}
        quit;
    """)


def f2_block(with_f2: bool) -> str:
    if not with_f2:
        return ""
    # Delta(N/Delta) Delta^5: Delta homogenized in (m, p) only (weights 1 on m, p), then one ring map (h -> Delta)
    return textwrap.dedent("""
        ring S = 0, (m1,m2,m3,p1,p2,p3,eps,w1,w2,w3,h), dp;
        poly D = imap(R, D); list N = imap(R, N);
        intvec wv = 1,1,1,1,1,1,0,0,0,0,0;
        proc homogmp(poly q, int d)
        {
          poly r = 0; int k;
          for (k = 0; k <= d; k++) { r = r + (jet(q, k, wv) - jet(q, k - 1, wv)) * h^(d - k); }
          return(r);
        }
        poly Dh = homogmp(D, 5);
        map phi = S, N[1], N[2], N[3], N[4], N[5], N[6], eps, w1, w2, w3, D;
        int t2 = rtimer; poly C = phi(Dh); int t3 = rtimer;
        print("STAGE f^2 plain compose: Delta_h(N, Delta) " + string(t3 - t2) + " " + string(size(C)));
        poly Ph = homogmp(N[4], 5);
        t2 = rtimer; poly P = phi(Ph); t3 = rtimer;
        print("STAGE f^2 plain compose: P1_h(N, Delta) " + string(t3 - t2) + " " + string(size(P)));
        link l = "ssi:w /tmp/hkproof_singular_f2.ssi"; write(l, C); write(l, P); close(l);
    """)


GCD_SCRIPT = """
system("--ticks-per-sec", 1000);
ring S = 0, (m1,m2,m3,p1,p2,p3,eps,w1,w2,w3,h), dp;
link l = "ssi:r /tmp/hkproof_singular_f2.ssi"; poly C = read(l); poly P = read(l); close(l);
int t2 = rtimer; poly G = gcd(C, P); int t3 = rtimer;
print("STAGE f^2 common factor g (direct gcd) " + string(t3 - t2) + " " + string(size(G)));
quit;
"""


def run_singular(with_f2: bool, seconds: int) -> dict[str, float]:
    """Singular on the same stages (the gcd of f^2 in a second run, so that a timeout there loses nothing else)."""
    result = _stages(singular_peer.singular_stdout(singular_script(with_f2), seconds))
    if with_f2 and "f^2 plain compose: P1_h(N, Delta)" in result:
        result.update(_stages(singular_peer.singular_stdout(GCD_SCRIPT, seconds)))
    return result


def _stages(out: str) -> dict[str, float]:
    """The 'STAGE name milliseconds size' lines of a Singular run, in seconds."""
    result = {}
    for line in out.splitlines():
        if line.startswith("STAGE "):
            *name, ms, _size = line[6:].split()
            result[" ".join(name)] = int(ms) / 1000
    return result


SYMPY_STAGES = {
    "det M": "M.det(method='berkowitz').expand()",
    "Cramer numerators of f": "[replaced(j).det(method='berkowitz').expand() for j in range(6)]",
}


def run_sympy(seconds: int) -> dict[str, float | None]:
    """Seconds per sympy stage, None if it ran out of time (a crash of the script raises)."""
    out: dict[str, float | None] = {}
    for name, expr in SYMPY_STAGES.items():
        code = textwrap.dedent(f"""
            import time, sympy
            m1, m2, m3, p1, p2, p3, eps, w1, w2, w3 = sympy.symbols('m1 m2 m3 p1 p2 p3 eps w1 w2 w3')
            e = eps
            M = sympy.Matrix([[1, 0, 0, 0, e*(w2-w3)*p3, e*(w2-w3)*p2], [0, 1, 0, e*(w3-w1)*p3, 0, e*(w3-w1)*p1],
                              [0, 0, 1, e*(w1-w2)*p2, e*(w1-w2)*p1, 0], [0, e*p3, -e*p2, 1, -e*m3, e*m2],
                              [-e*p3, 0, e*p1, e*m3, 1, -e*m1], [e*p2, -e*p1, 0, -e*m2, e*m1, 1]])
            b = sympy.Matrix([m1, m2, m3, p1, p2, p3])
            def replaced(j):
                a = M.copy()
                a[:, j] = b
                return a
            t = time.perf_counter(); _ = {expr}; print(time.perf_counter() - t)
        """)
        try:
            res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=seconds)
        except subprocess.TimeoutExpired:
            out[name] = None
            continue
        lines = res.stdout.strip().splitlines()
        if res.returncode or not lines:   # a failure of the script is not a time: say so
            raise RuntimeError(f"the sympy stage {name!r} failed: {res.stderr.strip().splitlines()[-1:]}")
        out[name] = float(lines[-1])
    return out


def report(rows, proof_rows, singular, sympy_times, with_f2: bool, items: float) -> str:
    lines = ["# Performance: discrete Clebsch system, part I", "",
             f"Measured by `benchmarks/clebsch_part1.py{' --f2' if with_f2 else ''}` on {platform.machine()} "
             f"({platform.python_implementation()} {platform.python_version()}, python-flint), one run, a machine "
             "shared with other jobs (times are wall-clock and indicative).", "",
             "## Proofs (each claim, as run by `proofs/clebsch_part1.py`; citations of earlier claims are re-proved "
             "once and then cached)", "",
             f"Every claim of items 1, 2, 4, 5, 6 of the issue ({', '.join(ITEMS)}), each proven once with the "
             f"claims it cites (dc345-abcd for the dependence), in a fresh process: **{items:.2f} s**.", "",
             "| claim | status | seconds |", "|---|---|---:|"]
    lines += [f"| {cid} | {status} | {sec:.2f} |" for cid, sec, status in proof_rows]
    lines += ["", "## Heavy stages: hkproof beside Maple (paper), Singular and sympy", "",
              "| stage | hkproof (s) | note | paper (Maple) | Singular (s) | ratio Singular/hkproof | sympy (s) |",
              "|---|---:|---|---|---:|---:|---:|"]
    for name, sec, note in rows:
        sing = next((v for k, v in singular.items() if k in name or name.startswith("f = ") and k in
                     ("det M", "Cramer numerators of f")), None)
        sing_total = sum(v for k, v in singular.items() if k in ("det M", "Cramer numerators of f")) \
            if name.startswith("f = ") and singular else sing
        sym = (sum(sympy_times.values()) if all(v is not None for v in sympy_times.values()) else "unfinished") \
            if name.startswith("f = ") and sympy_times else None
        ratio = f"{sing_total / sec:.2f}" if sing_total and sec else ""
        lines.append(f"| {name} | {sec:.3f} | {note} | {PAPER.get(name, '')} | "
                     f"{'' if sing_total is None else f'{sing_total:.3f}'} | {ratio} | "
                     f"{'' if sym is None else sym if isinstance(sym, str) else f'{sym:.2f}'} |")
    for k, v in singular.items():
        if k.startswith("f^2 common factor"):
            lines.append(f"| {k} (Singular) | | | | {v:.1f} | | |")
    if not singular:
        lines += ["", "Singular was not found on PATH: its column is empty."]
    if sympy_times:
        lines += ["", "sympy (capped per stage): " + "; ".join(
            f"{k}: {'did not finish' if v is None else f'{v:.2f} s'}" for k, v in sympy_times.items())]
    lines += ["", "## Notes", "", NOTES]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--f2", action="store_true", help="include the second iterate (minutes)")
    parser.add_argument("--out", default="docs/performance-clebsch.md")
    parser.add_argument("--sympy-seconds", type=int, default=600)
    parser.add_argument("--singular-seconds", type=int, default=1800)
    args = parser.parse_args(argv)
    rows, _ = stages(args.f2)
    proof_rows = proofs()
    singular = run_singular(args.f2, args.singular_seconds)
    for name, sec, note, theirs in theta_stages(args.singular_seconds):
        rows.append((name, sec, note))
        if theirs is not None:
            singular[name] = theirs
    items = items_from_scratch()
    sympy_times = run_sympy(args.sympy_seconds)
    text = report(rows, proof_rows, singular, sympy_times, args.f2, items)
    Path(args.out).write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
