"""Kernel coordinates made integrals: a small one by dense reconstruction and substitution, a big one with its whole
basis by Prop. "prop: even" (hkproof.pipelines.discover.solve), never by expanding a big h o f.

Candidates are taken simplest first while they add a new independent gradient. A ratio c_k / c_j whose dense ansatz
is small is rebuilt from its values mod primes by the dense method of hkproof.algebra.reconstruction (few values of
eps and the parameters, many points each; names that scaling symmetries allow are set to 1 and restored by weighted
homogeneity), and proven by exact substitution. Any
other is proven with its basis: relations with the integrals proven so far, the coordinates by sparse reconstruction
over prime fields, the proof by Prop. "prop: even". A basis that needs integrals not yet proven waits, and is tried
again whenever a new integral is proven. When a pass proves nothing new, a last pass rebuilds each ratio still open
(dense ansatz at most SPARSE_LIMIT unknowns; one ratio per basis, SPARSE_TRIES bases) by sparse reconstruction and
proves it by substitution if it has at most SUBSTITUTION_LIMIT terms. Every formula is proven before it is called an
integral.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Sequence


from hkproof import budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.modular import rank_mod_p
from hkproof.algebra.dense_reconstruction import ansatz_size, line_degrees
from hkproof.algebra.monomials import Exponents, text
from hkproof.algebra.reconstruction import Batch, reconstruct
from hkproof.errors import BudgetExhausted, HKProofError, ResourceLimitError
from hkproof.hk.certified_integrals import certify, is_phase_constant
from hkproof.pipelines.discover.candidates import Candidate, modular_sampler
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.report import DiscoveryReport, FoundIntegral
from hkproof.pipelines.discover.solve import BasisProof, Postponed, prove_basis
from hkproof.pipelines.discover.symbolic import kernel_ratio
from hkproof.proof.status import Status

__all__ = ["Reconstructed", "reconstruct_candidates"]



SPARSE_LIMIT = 20000     # the last resort (sparse reconstruction, substitution) is tried on ratios whose dense ansatz
                         # has at most this many unknowns (Henon-Heiles' modified energy: 4 290)
SPARSE_TRIES = 8         # bases the last resort tries (one ratio each)
SUBSTITUTION_LIMIT = 300     # terms of h above which h o f is not expanded (one uninterruptible compose: the
                             # commuting so(4) flow's 1 100-1 300-term ratios take about 100 s each; Henon-Heiles'
                             # 65 terms 0.01 s)
DENSE_FIRST = 300    # a ratio whose dense ansatz has at most this many unknowns is fitted first (fast when small);
                     # a larger one is proven with its basis, densely only if that waits for integrals not yet proven


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


@dataclass
class _Progress:
    """What the stage has: accepted gradients, the proven integrals of the searched map (the K of the relations), the
    bases proven or postponed (with how many integrals were known when they were postponed)."""

    accepted: list[list[int]] = field(default_factory=list)
    known: dict[str, Frac] = field(default_factory=dict)
    proofs: dict[tuple[Exponents, ...], BasisProof] = field(default_factory=dict)
    postponed: dict[tuple[Exponents, ...], tuple[int, str]] = field(default_factory=dict)
    skipped: dict[tuple, dict] = field(default_factory=dict)
    reported: set[tuple[Exponents, ...]] = field(default_factory=set)
    dense: int = 0
    sparse: set[tuple] = field(default_factory=set)     # candidates tried by sparse reconstruction and substitution
    rescued: set[tuple] = field(default_factory=set)    # ... and proven that way


def reconstruct_candidates(ctx: SearchContext, report: DiscoveryReport, candidates: list[Candidate], target: int,
                           p: int, proven: Sequence[list[int]] = ()) -> Reconstructed:
    """Prove kernel coordinates, one per new independent gradient, simplest first (`proven`: gradients of integrals
    proven before, which candidates must go beyond); passes repeat while a pass proves a new integral (a postponed
    basis may go through then). The integrals are appended to `report` as they are found, so that a budget running
    out keeps them."""
    state = _Progress(accepted=list(proven), known={i.name: i.frac.to_ring(ctx.kmap.ring) for i in report.integrals
                             if i.frac is not None and i.status >= Status.VERIFIED_SPECIALIZED
                             and not is_phase_constant(i.frac, ctx.full_map.variables)
                             and set(i.frac.variables()) <= set(ctx.kmap.ring.names)})
    last_resort = False
    while len(state.accepted) < target:
        before = len(state.known)
        _pass(ctx, report, candidates, target, p, state, last_resort)
        if len(state.known) > before:
            last_resort = False
        elif last_resort:
            break
        else:
            last_resort = True          # one more pass, with sparse reconstruction and substitution for what is left
    out = Reconstructed(skipped=[entry for key, entry in state.skipped.items() if key not in state.rescued])
    out.skipped += [{"basis": [text(ctx.kmap.variables, e) for e in b], "coordinate": None, "degrees": None,
                     "reason": reason} for b, (_, reason) in state.postponed.items()
                    if b not in state.proofs and not any(key[0] == b for key in state.rescued)]
    out.covered = (f"reconstructed {state.dense} kernel coordinates densely and proved {len(state.proofs)} bases "
                   f"whole by Prop. \"prop: even\" (sparse reconstruction, relations with proven integrals); "
                   f"{len(state.sparse)} ratios tried by sparse reconstruction and substitution; "
                   f"{len(out.skipped)} left out")
    return out


def _pass(ctx: SearchContext, report: DiscoveryReport, candidates: list[Candidate], target: int, p: int,
          state: _Progress, last_resort: bool) -> None:
    for cand in candidates:
        if len(state.accepted) >= target:
            return
        if rank_mod_p(state.accepted + [cand.gradient], p) <= len(state.accepted):
            continue
        budget.check(f"proving integral {len(state.accepted) + 1} of {target}")
        found = _dense_or_skip(ctx, report, cand, p, state) if cand.estimate <= DENSE_FIRST else None
        if found is None:
            found = _from_basis(ctx, report, cand, state)
        if found is None and DENSE_FIRST < cand.estimate <= ctx.max_unknowns:
            found = _dense_or_skip(ctx, report, cand, p, state)
        if found is None and last_resort:
            found = _sparse(ctx, report, cand, state)
        if found is None:
            continue
        report.integrals.append(found)
        if found.frac is not None and found.status >= Status.VERIFIED_SPECIALIZED and \
                not is_phase_constant(found.frac, ctx.kmap.variables):
            state.accepted.append(cand.gradient)
            state.known[found.name] = found.frac.to_ring(ctx.kmap.ring)
        if found.frac is not None:
            ctx.stages.say(f"{found.name} = {found.frac}: {found.status.label}")


def _dense_or_skip(ctx: SearchContext, report: DiscoveryReport, cand: Candidate, p: int,
                   state: _Progress) -> FoundIntegral | None:
    """The dense route for a candidate (once: a candidate found too large is remembered)."""
    key = (tuple(cand.basis), cand.k, cand.j)
    if key in state.skipped:
        return None
    dense = _dense(ctx, report, cand, [text(ctx.kmap.variables, e) for e in cand.basis], p)
    if isinstance(dense, Skipped):
        state.skipped[key] = dense.entry
        return None
    state.dense += 1
    return dense


def _from_basis(ctx: SearchContext, report: DiscoveryReport, cand: Candidate, state: _Progress) -> FoundIntegral | None:
    """c_k / c_j from the proof of its whole basis (proven once; postponed while the known integrals do not grow)."""
    key = tuple(cand.basis)
    if key not in state.proofs:
        waited = state.postponed.get(key)
        if waited is not None and waited[0] == len(state.known):
            return None
        ctx.stages.start("bases", f"proving the basis ({', '.join(text(ctx.kmap.variables, e) for e in key)})")
        result = prove_basis(ctx, cand.basis, state.known, ctx.rng)
        if isinstance(result, Postponed):
            state.postponed[key] = (len(state.known), result.reason)
            return None
        state.proofs[key] = result
    proof = state.proofs[key]
    if proof.status < Status.VERIFIED_SPECIALIZED:
        if key in state.reported:
            return None                  # the basis's failed proof is reported once
        state.reported.add(key)
    top, bottom = proof.coordinate(cand.basis[cand.k]), proof.coordinate(cand.basis[cand.j])
    if bottom.is_zero():
        return None
    h = top / bottom
    name = f"I{len(report.integrals) + 1}"
    proof.certificate.formula(name, h)
    status = proof.status
    return FoundIntegral(name, h.to_ring(ctx.full_map.ring), status, "kernel coordinate", proof.basis, cand.label,
                         proof.seconds, f"Prop. \"prop: even\" on the whole basis ({len(proof.relations)} relations "
                         "with proven integrals, coordinates by sparse reconstruction over prime fields)",
                         [] if status >= Status.VERIFIED_SPECIALIZED else [proof.certificate.error],
                         certificate=proof.certificate, proof=proof)


def _sparse(ctx: SearchContext, report: DiscoveryReport, cand: Candidate, state: _Progress) -> FoundIntegral | None:
    """The last resort for a ratio too large to fit densely whose basis no square system proves: c_k / c_j by sparse
    reconstruction over prime fields, proven by exact substitution h(f(x)) = h(x) when it is small enough (one ratio
    per basis, SPARSE_TRIES bases at most; a ratio too large to substitute is listed as skipped)."""
    key = (tuple(cand.basis), cand.k, cand.j)
    if cand.estimate > SPARSE_LIMIT or len(state.sparse) >= SPARSE_TRIES or \
            any(tried[0] == key[0] for tried in state.sparse):
        return None
    state.sparse.add(key)
    texts = [text(ctx.kmap.variables, e) for e in cand.basis]
    name = f"I{len(report.integrals) + 1}"
    ctx.stages.start("sparse ratios", f"{name}: coordinate {cand.k + 1} of the kernel of ({', '.join(texts)}) by "
                     "sparse reconstruction")
    start = time.perf_counter()
    try:
        h = kernel_ratio(ctx, cand.basis, cand.k, cand.j, ctx.rng)
    except BudgetExhausted:
        raise
    except HKProofError as exc:
        state.skipped[key] = {"basis": texts, "coordinate": cand.label, "degrees": None,
                              "reason": f"sparse reconstruction failed: {exc}"}
        return None
    size = len(h.num) + len(h.den)
    if size > SUBSTITUTION_LIMIT:
        state.skipped[key] = {"basis": texts, "coordinate": cand.label, "degrees": None,
                              "reason": f"sparse reconstruction gave {size} terms, more than the {SUBSTITUTION_LIMIT} "
                                        "an exact substitution h(f(x)) = h(x) is tried on, and no square system of its "
                                        "basis was found for Prop. \"prop: even\""}
        return None
    ctx.stages.start("proofs", f"{name}: exact substitution h(f(x)) = h(x)")
    cert = certify(ctx.full_map, h.to_ring(ctx.full_map.ring), ctx.fixed, name)
    if cert.status >= Status.VERIFIED_SPECIALIZED:
        state.rescued.add(key)
    return FoundIntegral(name, h.to_ring(ctx.full_map.ring), cert.status, "kernel coordinate", texts, cand.label,
                         time.perf_counter() - start, cert.steps[-1].detail or cert.error,
                         [f"sparse reconstruction over prime fields ({len(h.num)} + {len(h.den)} terms), then exact "
                          "substitution"], certificate=cert)


def _dense(ctx: SearchContext, report: DiscoveryReport, cand: Candidate, texts: list[str],
           p: int) -> FoundIntegral | Skipped:
    """The dense route for one candidate: degrees along two lines mod p, the dense ansatz on values mod primes (few
    values of eps and the parameters, many points each), the proof; Skipped when the ansatz is too large."""
    kmap, rng = ctx.kmap, ctx.rng
    box, names = _ratio_box(ctx, cand), [*ctx.free, *ctx.inner]
    ctx.stages.start("reconstruction", f"degrees of coordinate {cand.k + 1} of the kernel of ({', '.join(texts)})")
    start = time.perf_counter()
    try:
        lines = [line_degrees(box, p, len(names), 1, rng, ctx.max_degree)[0] for _ in range(2)]
        degrees: tuple[int, int] | None = (max(d[0] for d in lines), max(d[1] for d in lines))
    except ResourceLimitError:
        degrees = None
    size = None if degrees is None else ansatz_size(len(names), degrees)
    if degrees is None or size is None or size > ctx.max_unknowns:
        return Skipped({"basis": texts, "coordinate": cand.label,
                        "degrees": None if degrees is None else list(degrees),
                        "reason": (f"degree > {ctx.max_degree} along a line" if degrees is None else
                                   f"dense ansatz of {size} unknowns (limit {ctx.max_unknowns})")})
    name = f"I{len(report.integrals) + 1}"
    ctx.stages.say(f"{name}: coordinate {cand.k + 1} of the kernel of ({', '.join(texts)}), degrees {degrees}, "
                   f"{size} unknowns")
    weight = [a - b for a, b in zip(ctx.weights.of_monomial(_exps(kmap.variables, cand.basis[cand.j])),
                                    ctx.weights.of_monomial(_exps(kmap.variables, cand.basis[cand.k])), strict=True)]
    try:
        rebuilt = reconstruct(box, len(names), 1, method="dense", rng=rng, max_degree=ctx.max_degree,
                              degrees=[degrees], shared=len(ctx.free))[0]
        h = ctx.weights.restore_frac(rebuilt.to_frac(kmap.ring, names), weight)
        notes = ["the interpolant is not weighted homogeneous: not restored" if h is None else
                 f"P/Q with degrees {list(degrees)} by the dense ansatz on values mod primes, checked at a fresh "
                 "prime"]
    except (BudgetExhausted, MemoryError):
        raise
    except HKProofError as exc:
        h, notes = None, [f"no P/Q with degrees <= {list(degrees)} fits: {exc}"]
    if h is None:
        return FoundIntegral(name, None, Status.UNKNOWN, "kernel coordinate", texts, cand.label,
                             time.perf_counter() - start, "reconstruction failed", notes)
    ctx.stages.start("proofs", f"{name}: exact substitution h(f(x)) = h(x)")
    cert = certify(ctx.full_map, h.to_ring(ctx.full_map.ring), ctx.fixed, name)
    return FoundIntegral(name, h.to_ring(ctx.full_map.ring), cert.status, "kernel coordinate", texts, cand.label,
                         time.perf_counter() - start, cert.steps[-1].detail or cert.error, notes, certificate=cert)


def _exps(variables: Sequence[str], e: Exponents) -> dict[str, int]:
    return {v: k for v, k in zip(variables, e, strict=True) if k}


def _ratio_box(ctx: SearchContext, cand: Candidate) -> Batch:
    """c_k / c_j of the kernel of the candidate's basis mod p at points (free names, then phase variables), the
    normalized names set to 1: the black box of the dense route (points sharing their free values share one
    specialized map)."""
    samplers: dict[int, Callable] = {}
    split = len(ctx.free)

    def box(p: int, points: Sequence[Sequence[int]]) -> list[list[int] | None]:
        if p not in samplers:
            samplers[p] = modular_sampler(ctx.kmap, cand.basis, (cand.k, cand.j), ctx.weights, ctx.free, p)
        groups: dict[tuple[int, ...], list[int]] = {}
        for i, x in enumerate(points):
            groups.setdefault(tuple(x[:split]), []).append(i)
        out: list[list[int] | None] = [None] * len(points)
        for outer, members in groups.items():
            values = samplers[p](dict(zip(ctx.free, outer, strict=True)),
                                 [dict(zip(ctx.inner, points[i][split:], strict=True)) for i in members])
            for i, v in zip(members, values, strict=True):
                out[i] = None if v is None else [int(v) % p]
        return out
    return box

