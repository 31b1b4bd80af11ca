"""Kernel coordinates made formulas: dense reconstruction from exact samples, or recipe (E) when that is too large.

A chosen ratio c_k / c_j is sampled exactly (kernels over Q at rational points, eps and the parameters varying;
names that scaling symmetries allow are set to 1 and restored by weighted homogeneity) and fitted by a dense ansatz
h Q - P = 0. When the ansatz is too large, the paper's relation-driven route runs on the basis instead: relations
among its kernel coordinates found exactly, the rows i = 0, 1 solved and certified by Prop. "prop: even". Every
formula is proven before it is called an integral (hkproof.hk.discover).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.modular import rank_mod_p
from hkproof.algebra.monomials import Exponents, text
from hkproof.errors import HKProofError
from hkproof.experiments.profiles import ProfileProblem, kernel_vector
from hkproof.experiments.reconstruction import dense_size, line_degrees, reconstruct_rational
from hkproof.experiments.relations import find_relations
from hkproof.experiments.scene import make_scene
from hkproof.experiments.weights import Weights
from hkproof.hk.discover import certify, is_phase_constant, solve_by_evenness
from hkproof.hk.reduced import Relation
from hkproof.pipelines.discover.candidates import Candidate, modular_sampler
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.report import DiscoveryReport, FoundIntegral
from hkproof.proof.status import Status

__all__ = ["MAX_RELATION_BASIS", "Reconstructed", "reconstruct_candidates", "restore_weights"]

MAX_RELATION_BASIS = 8      # recipe (E) is tried on minimal bases of at most this many functions


@dataclass
class BasisSolution:
    """Recipe (E) on one basis: its kernel vector (c_l = -1 left out), the status of the proof and how."""

    solution: list[Frac] | None
    status: Status
    method: str
    seconds: float


@dataclass
class Skipped:
    """A kernel coordinate left out, with its report entry (basis, coordinate, degrees, reason)."""

    entry: dict


@dataclass
class Reconstructed:
    """The integrals of the reconstruction stage, the coordinates skipped as too large, and a coverage note."""

    integrals: list[FoundIntegral] = field(default_factory=list)
    skipped: list[dict] = field(default_factory=list)
    covered: str = ""


def restore_weights(h: Frac, weights: Weights, weight: Sequence[flint.fmpq]) -> Frac | None:
    """h sampled with the normalized names set to 1, made weighted homogeneous of `weight` again (None if no
    integer exponents do it)."""
    if not weights.normalized:
        return h
    ring = h.ring
    names = ring.names
    terms = []
    for which, poly in (("num", h.num), ("den", h.den)):
        for m, c in poly.to_dict().items():
            terms.append((which, {n: e for n, e in zip(names, m, strict=True) if e}, c))
    den_terms = [t for t in terms if t[0] == "den"]
    base = weights.of_monomial(den_terms[0][1])
    targets = {"den": base, "num": [a + b for a, b in zip(base, weight, strict=True)]}
    extra = []
    for which, exps, _ in terms:
        e = weights.restore(exps, [flint.fmpq(0)] * len(base), targets[which])
        if e is None or any(v.q != 1 for v in e.values()):
            return None
        extra.append(e)
    shift = {n: min(int(e.get(n, 0)) for e in extra) for n in weights.normalized}
    data: dict[str, dict] = {"num": {}, "den": {}}
    for (which, exps, c), e in zip(terms, extra, strict=True):
        mono = [0] * len(names)
        for n, v in exps.items():
            mono[ring.index(n)] += v
        for n in weights.normalized:
            mono[ring.index(n)] += int(e.get(n, 0)) - shift[n]
        data[which][tuple(mono)] = c
    return Frac(ring, ring.ctx.from_dict(data["num"]), ring.ctx.from_dict(data["den"]))


def reconstruct_candidates(ctx: SearchContext, report: DiscoveryReport, candidates: list[Candidate], target: int,
                           p: int) -> Reconstructed:
    """Reconstruct and certify kernel coordinates, one per new independent gradient, simplest bases first (the
    integrals are also appended to `report` as they are found, so that a budget running out keeps them)."""
    out = Reconstructed()
    accepted: list[list[int]] = []
    solved: dict[tuple[str, ...], BasisSolution] = {}
    count = 0
    for cand in candidates:
        if len(accepted) >= target:
            break
        if rank_mod_p(accepted + [cand.gradient], p) <= len(accepted):
            continue
        texts = [text(ctx.kmap.variables, e) for e in cand.basis]
        if cand.estimate > ctx.max_unknowns:
            if _by_relations(ctx, report, cand, texts, solved, accepted):
                continue
            out.skipped.append({"basis": texts, "coordinate": cand.label, "degrees": None,
                                "reason": f"dense ansatz of about {cand.estimate} unknowns along a line "
                                          f"(limit {ctx.max_unknowns})" if cand.estimate < 10**9 else
                                          "degree > 12 along a line"})
            continue
        ctx.budget.check(f"reconstructing integral {len(accepted) + 1} of {target}")
        found = _dense(ctx, report, cand, texts, p)
        if isinstance(found, Skipped):
            if _by_relations(ctx, report, cand, texts, solved, accepted):
                continue
            out.skipped.append(found.entry)
            continue
        count += 1
        report.integrals.append(found)
        if found.frac is not None and found.status >= Status.VERIFIED_SPECIALIZED and \
                not is_phase_constant(found.frac, ctx.kmap.variables):
            accepted.append(cand.gradient)
        if found.frac is not None:
            ctx.stages.say(f"{found.name} = {found.frac}: {found.status.label}")
    by_relations = sum(1 for i in report.integrals if i.method.startswith("recipe (E)"))
    out.covered = (f"reconstructed {count} kernel coordinates chosen for new independent gradients and solved "
                   f"{by_relations} by recipe (E); {len(out.skipped)} skipped as too large for dense reconstruction")
    return out


def _dense(ctx: SearchContext, report: DiscoveryReport, cand: Candidate, texts: list[str],
           p: int) -> FoundIntegral | Skipped:
    """The dense route for one candidate: degrees along two lines mod p, exact samples, the ansatz, the proof;
    Skipped when the ansatz is too large."""
    kmap, rng = ctx.kmap, ctx.rng
    sampler = _exact_sampler(ctx, texts, cand.k, cand.j)
    ctx.stages.start("reconstruction", f"degrees of coordinate {cand.k + 1} of the kernel of ({', '.join(texts)})")
    start = time.perf_counter()
    fast = modular_sampler(kmap, cand.basis, (cand.k, cand.j), ctx.weights, ctx.free, p)
    lines = [line_degrees(fast, ctx.free, ctx.inner, max_degree=ctx.max_degree, seed=rng.randint(0, 10**6),
                          modulus=p) for _ in range(2)]
    measured = [d for d in lines if d is not None]
    degrees = (max(d[0] for d in measured), max(d[1] for d in measured)) if len(measured) == len(lines) else None
    size = None if degrees is None else dense_size(len(ctx.free) + len(ctx.inner), degrees)
    if degrees is None or size is None or size > ctx.max_unknowns:
        return Skipped({"basis": texts, "coordinate": cand.label,
                        "degrees": None if degrees is None else list(degrees),
                        "reason": (f"degree > {ctx.max_degree} along a line" if degrees is None else
                                   f"dense ansatz of {size} unknowns (limit {ctx.max_unknowns})")})
    name = f"I{len(report.integrals) + 1}"
    ctx.stages.say(f"{name}: coordinate {cand.k + 1} of the kernel of ({', '.join(texts)}), degrees {degrees}, "
                   f"{size} unknowns")
    rec = reconstruct_rational(kmap.ring, ctx.free, ctx.inner, sampler, degrees, seed=rng.randint(0, 10**6))
    notes = list(rec.notes)
    h = None
    if rec.frac is not None:
        weight = [a - b for a, b in zip(ctx.weights.of_monomial(_exps(kmap.variables, cand.basis[cand.j])),
                                        ctx.weights.of_monomial(_exps(kmap.variables, cand.basis[cand.k])),
                                        strict=True)]
        h = restore_weights(rec.frac, ctx.weights, weight)
        notes.append("the interpolant is not weighted homogeneous: not restored" if h is None else
                     f"P/Q with degrees {list(degrees)} from {rec.samples} exact samples, checked at "
                     f"{rec.checks} fresh ones")
    if h is None:
        return FoundIntegral(name, None, Status.UNKNOWN, "kernel coordinate", texts, cand.label,
                             time.perf_counter() - start, "reconstruction failed", notes)
    ctx.stages.start("proofs", f"{name}: exact substitution h(f(x)) = h(x)")
    status, method = certify(ctx.full_map, h, ctx.fixed)
    return FoundIntegral(name, h.to_ring(ctx.full_map.ring), status, "kernel coordinate", texts, cand.label,
                         time.perf_counter() - start, method, notes)


def _by_relations(ctx: SearchContext, report: DiscoveryReport, cand: Candidate, texts: list[str],
                  solved: dict[tuple[str, ...], BasisSolution], accepted: list[list[int]]) -> bool:
    """A kernel coordinate too large for dense interpolation, by the paper's recipe (E) instead: relations among the
    basis's kernel coordinates found exactly (symbolic in eps and the parameters), then the rows i = 0, 1 solved
    and certified by Prop. "prop: even" (hk.discover.solve_by_evenness). True if it gave an integral."""
    kmap = ctx.kmap
    key = tuple(texts)
    if key not in solved:
        if len(texts) > MAX_RELATION_BASIS:
            solved[key] = BasisSolution(None, Status.UNKNOWN, "basis too large for the relation search", 0.0)
        else:
            ctx.budget.check(f"recipe (E) on ({', '.join(texts)})")
            ctx.stages.start("relations", f"recipe (E) on ({', '.join(texts)})")
            start = time.perf_counter()
            basis = [Frac.parse(kmap.ring, t) for t in texts]
            try:
                search = find_relations(kmap, [basis])
                rels = [Relation(r.coefficients, r.rhs) for r in search.relations]
                solution, status, method = solve_by_evenness(kmap, basis, rels, ctx.fixed)
                solved[key] = BasisSolution(solution, status, method, time.perf_counter() - start)
            except HKProofError as exc:
                solved[key] = BasisSolution(None, Status.UNKNOWN, f"recipe (E) failed: {exc}",
                                            time.perf_counter() - start)
            ctx.stages.say(f"recipe (E) on ({', '.join(texts)}): {solved[key].method}")
    verdict = solved[key]
    if verdict.solution is None:
        return False
    c = [*verdict.solution, Frac(kmap.ring, -1)]
    if c[cand.j].is_zero():
        return False
    h = c[cand.k] / c[cand.j]
    name = f"I{len(report.integrals) + 1}"
    report.integrals.append(FoundIntegral(name, h.to_ring(ctx.full_map.ring), verdict.status, "kernel coordinate",
                                          texts, cand.label, verdict.seconds, verdict.method,
                                          ["too large for dense interpolation along a line; solved symbolically "
                                           "instead"]))
    if verdict.status >= Status.VERIFIED_SPECIALIZED and not is_phase_constant(h, kmap.variables):
        accepted.append(cand.gradient)
    ctx.stages.say(f"{name}: {verdict.status.label} by recipe (E)")
    return True


def _exps(variables: Sequence[str], e: Exponents) -> dict[str, int]:
    return {v: k for v, k in zip(variables, e, strict=True) if k}


def _exact_sampler(ctx: SearchContext, texts: list[str], k: int, j: int) -> Callable:
    """Exact values of c_k / c_j for the kernel of a minimal basis (recipe (B): c_l = -1), at given free values."""
    kmap, weights, free = ctx.kmap, ctx.weights, ctx.free
    basis = [Frac.parse(kmap.ring, t) for t in texts]
    cache = ctx.caches.setdefault(tuple(texts), {})

    def sample(outer: dict, points: list[dict]) -> list:
        vals = {m: flint.fmpq(1) for m in weights.normalized} | {m: outer[m] for m in free}
        key = tuple(sorted((m, str(v)) for m, v in vals.items()))
        problem = cache.get(key)
        if problem is None:
            try:
                problem = ProfileProblem(make_scene(kmap, vals), basis)
            except HKProofError:
                return [None] * len(points)
            cache.clear()
            cache[key] = problem
        out = []
        for pt in points:
            c = kernel_vector(problem, [pt[v] for v in kmap.variables])
            ok = c is not None and c[-1] == -1 and c[j] != 0          # -1 last: recipe (B)'s normalization
            out.append(c[k] / c[j] if ok and c is not None else None)
        return out
    return sample
