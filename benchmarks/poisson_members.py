"""The Poisson members mod p of a class whose kernel `hkproof poisson --screen` cannot exclude (its brackets are
dependent): which members c (sum c_a Pi_a) satisfy Jacobi mod p, their rank, and how they sit against the integrals
that `discover` proves (Casimirs, involution). Everything is at the screen's prime and parameter values: evidence
about one specialization, not a theorem.

The members are the screen's own (its no-poisson stage is watched: `brackets_independent_mod` is wrapped to keep
its arguments). The relations among the brackets come from `hk.poisson.bracket_relations_mod`; a member c is Poisson
mod p iff c c^T lies in their span, i.e. on the zeros of quadrics q_t(c) (the functionals vanishing on the span).
The candidate space U is spanned by the rank-one relations; U is inside the zero set when u u^T and u v^T + v u^T are
in the span for a basis of U (then the whole U is a pencil of compatible Poisson members), and the zero set is
inside U when the quadrics have no common zero off U over the algebraic closure of F_p (sympy's Groebner bases
modulo p, one affine chart per coordinate of a complement of U: a Groebner basis [1] in each). Writes the block
"poisson-members" of docs/performance-poisson.md.

    python benchmarks/poisson_members.py gaudin-2 F2*F5 --degree 7      # about 5-10 minutes
"""
from __future__ import annotations

import argparse
import platform
import random
import resource
import sys
import time
from pathlib import Path
from typing import Any

import flint
import sympy

from docs_section import write_section

DOC = Path(__file__).resolve().parents[1] / "docs" / "performance-poisson.md"


def _in_span(vectors: list[list[int]], target: list[int], p: int) -> bool:
    return flint.nmod_mat(vectors + [target], p).rank() == flint.nmod_mat(vectors, p).rank()


def _sym(c: list[int], d: list[int], r: int, p: int) -> list[int]:
    """c d^T + d c^T as the vector of its entries a <= b (2 c c^T when c is d): [sum c v, sum d v] is 0 mod p iff it
    lies in the span of the relation forms."""
    return [(c[a] * d[b] + d[a] * c[b]) % p for a in range(r) for b in range(a, r)]


def poisson_members(forms: list[list[list[int]]], p: int) -> dict[str, Any]:
    """The rank-one relations' members U, whether U is a pencil of compatible Poisson members, and whether every
    Poisson member lies in U (Groebner bases modulo p)."""
    r = len(forms[0])
    vec = [[w[a][b] for a in range(r) for b in range(a, r)] for w in forms]
    basis: list[list[int]] = []
    for w in forms:
        if flint.nmod_mat(w, p).rank() == 1:
            col = next(j for j in range(r) if any(w[i][j] for i in range(r)))
            c = [w[i][col] for i in range(r)]
            lead = pow(next(x for x in c if x), -1, p)
            basis.append([x * lead % p for x in c])
    pencil = all(_in_span(vec, _sym(u, v, r, p), p) for k, u in enumerate(basis) for v in basis[k:])
    # a complement of U: coordinates c = sum s_k u_k + sum_j d_j e_j over the e_j not among U's pivots
    pivots = [next(i for i, x in enumerate(u) if x) for u in basis]
    free = [j for j in range(r) if j not in pivots]
    cs = sympy.symbols(f"c0:{r}")
    s = sympy.symbols(f"s0:{max(len(basis), 1)}")
    d = {j: sympy.Symbol(f"d{j}") for j in free}
    kernel, dim = flint.nmod_mat(vec, p).nullspace()
    idx = [(a, b) for a in range(r) for b in range(a, r)]
    quadrics = [sum(int(kernel[i, t]) * cs[a] * cs[b] for i, (a, b) in enumerate(idx) if int(kernel[i, t]))
                for t in range(dim)]
    sub = {cs[i]: sum(s[k] * basis[k][i] for k in range(len(basis))) + (d[i] if i in d else 0) for i in range(r)}
    outside = []
    for n, j in enumerate(free):
        eqs = [sympy.expand(q.subs(sub).subs(d[j], 1)) for q in quadrics] + [d[k] for k in free[:n]]
        gens = [*s[:len(basis)], *(d[k] for k in free if k != j)]
        eqs = [e for e in eqs if e != 0]
        outside.append(bool(eqs) and list(sympy.groebner(eqs, *gens, modulus=p, order="grevlex").exprs) != [1])
    return {"basis": basis, "pencil": pencil, "all_in_pencil": not any(outside), "relations": len(forms)}


def member_facts(kmap: Any, values: dict, p: int, members: list, c: list[int], integrals: list,
                 points: int = 8) -> dict[str, Any]:
    """Rank, which dI_k are Casimir covectors, the dimension of span(dI) among them, and {I_k, I_l}, at random
    points mod p (the screen's parameter values)."""
    from hkproof.hk.poisson import pairs
    rng, n, ring = random.Random(1), len(kmap.variables), kmap.ring
    at = {k: int(v.p) * pow(int(v.q), -1, p) % p for k, v in values.items()}
    ranks, casimir, inside, brackets = set(), [True] * len(integrals), set(), set()
    for _ in range(points):
        x = {v: rng.randrange(p) for v in kmap.variables}
        xs = [flint.fmpz(x[v]) for v in kmap.variables]
        matrix = [[0] * n for _ in range(n)]
        for ca, m in zip(c, members):
            if ca:
                inv = pow(int(m.denominator(*xs)) % p, -1, p)
                for k, (i, j) in enumerate(pairs(n)):
                    matrix[i][j] = (matrix[i][j] + ca * inv * int(m.upper[k](*xs))) % p
                    matrix[j][i] = -matrix[i][j] % p
        ranks.add(flint.nmod_mat(matrix, p).rank())
        full = [flint.fmpz({**x, **at}[name]) for name in ring.names]
        grads = []
        for h in integrals:
            num, den = int(h.num(*full)) % p, int(h.den(*full)) % p
            grads.append([(int(h.num.derivative(ring.index(v))(*full)) * den
                           - num * int(h.den.derivative(ring.index(v))(*full))) * pow(den, -2, p) % p
                          for v in kmap.variables])
        images = [[sum(matrix[i][j] * g[j] for j in range(n)) % p for i in range(n)] for g in grads]
        casimir = [ok and not any(w) for ok, w in zip(casimir, images)]
        inside.add(len(integrals) - flint.nmod_mat([list(r) for r in zip(*images)], p).rank())
        brackets |= {(k, l) for k in range(len(grads)) for l in range(k + 1, len(grads))
                     if sum(grads[k][i] * images[l][i] for i in range(n)) % p}
    return {"ranks": sorted(ranks), "casimirs": [f"I{k + 1}" for k, ok in enumerate(casimir) if ok],
            "span_dI_in_casimirs": sorted(inside), "brackets_nonzero": sorted(brackets)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("system")
    parser.add_argument("classes", nargs="+")
    parser.add_argument("--degree", type=int, default=7)
    parser.add_argument("--darboux-degree", type=int, default=4)
    args = parser.parse_args()
    import hkproof.pipelines.poisson as pipeline
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.hk.poisson import bracket_relations_mod
    from hkproof.pipelines.discover import discover
    kmap = kahan_map(args.system)
    integrals = [i.frac for i in discover(kmap.field, 2).integrals if i.frac is not None and i.status.is_verified]
    rows = []
    for name in args.classes:
        seen: list[tuple[list, int]] = []
        original = pipeline.brackets_independent_mod

        def watched(members: list, p: int) -> bool:
            seen.append((list(members), p))
            return original(members, p)
        pipeline.brackets_independent_mod = watched
        start = time.perf_counter()
        try:
            report = pipeline.with_integrals(kmap, args.degree, darboux_degree=args.darboux_degree, screen=True,
                                             only=[name])
        finally:
            pipeline.brackets_independent_mod = original
        screen = time.perf_counter() - start
        kernel = next((k for k in report.kernels if k.name == name and k.member is not None), None)
        if kernel is None or not seen:
            rows.append({"class": name, "note": "no kernel member at this degree (excluded or not tested)",
                         "screen": screen})
            continue
        members, p = seen[-1]
        start = time.perf_counter()
        forms = bracket_relations_mod(members, p)
        found = poisson_members(forms, p)
        facts = [member_facts(kmap, kernel.member.values, p, members, c, integrals) for c in found["basis"]]
        pencil = [sum(cs) % p for cs in zip(*found["basis"])] if len(found["basis"]) > 1 else None
        if pencil:
            facts.append(member_facts(kmap, kernel.member.values, p, members, pencil, integrals))
        rows.append({"class": name, "lowest": kernel.degree, "kernel": len(members), "prime": p, **found,
                     "facts": facts, "screen": screen, "analysis": time.perf_counter() - start})
        print(rows[-1], flush=True)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    lines = [f"## Poisson members of undecided classes (`python benchmarks/poisson_members.py {args.system} "
             f"{' '.join(args.classes)} --degree {args.degree}`, {time.strftime('%Y-%m-%d')})", "",
             f"Measured in one run on {platform.node()} (python-flint {flint.__version__}), peak RSS {peak:.0f} MB. "
             "Mod p at the screen's prime and parameter values (evidence about one specialization). `members`: the "
             "Poisson members spanned by the rank-one relations among the brackets; `pencil`: every combination of "
             "them is Poisson (the cross terms are relations too); `all`: no other Poisson member over the "
             "algebraic closure of F_p (Groebner bases modulo p). Per member (and, for a pencil, the sum of its "
             "basis): ranks at 8 random points, the integrals whose differentials it annihilates (Casimirs), the "
             "dimension of span(dI_k) among its Casimir covectors, and the pairs {I_k, I_l} that are not 0.", "",
             f"| class | lowest degree with a kernel | kernel at degree {args.degree} | bracket relations | Poisson "
             "members | pencil | all in it | per member | screen | analysis |", "|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        if "facts" not in row:
            lines.append(f"| {row['class']} | — | — | — | — | — | — | {row['note']} | {row['screen']:.0f} s | — |")
            continue
        per = "; ".join(f"rank {'/'.join(map(str, f['ranks']))}, Casimirs {', '.join(f['casimirs']) or 'none'}, "
                        f"span(dI) {'/'.join(map(str, f['span_dI_in_casimirs']))}, "
                        f"{'involution' if not f['brackets_nonzero'] else 'brackets ' + str(f['brackets_nonzero'])}"
                        for f in row["facts"])
        lines.append(f"| {row['class']} | {row['lowest']} | {row['kernel']} | {row['relations']} | "
                     f"{len(row['basis'])} | {'yes' if row['pencil'] else 'no'} | "
                     f"{'yes' if row['all_in_pencil'] else 'no'} | {per} | {row['screen']:.0f} s | "
                     f"{row['analysis']:.1f} s |")
    print(write_section(DOC, "poisson-members", lines))


if __name__ == "__main__":
    sys.exit(main())
