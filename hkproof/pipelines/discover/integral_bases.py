"""Bases made of monomials and integrals of the continuous flow, solved together: the last stage of `discover`.

The paper builds bases from integrals of the continuous flow (Th. "dC Theta": I1, I2, I3 and H4) and proves
several bases at once with relations across them (Th. "dC bases 345"). Both ideas, driven by the search:

1. The polynomial integrals of the continuous flow of degree <= D, exactly, and their circuits
   (hkproof.hk.flow_integrals).
2. Bases with one circuit, and 3. groups of them that give a square system, mod p (hkproof.pipelines.discover.groups).
4. The relations and coordinates with eps and the parameters symbolic (hkproof.pipelines.discover.group_coordinates),
   and the proof: Prop. "prop: even" for the whole block system (hkproof.hk.block_system.prove_blocks, which falls
   back to evidence at exact points when the budget stops it). Nothing is called an integral before that proof.
"""
from __future__ import annotations

import random
import time
from typing import Sequence

from hkproof.algebra.fraction import Frac
from hkproof.algebra.monomials import Exponents
from hkproof.hk.block_system import BlockSymmetry, BlockSystem, prove_blocks
from hkproof.hk.certified_integrals import independent_subset, jacobian_points
from hkproof.hk.flow_integrals import continuous_integral_circuits
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.group_coordinates import group_coordinates, lift_group_relations
from hkproof.pipelines.discover.groups import Group, carried_by_symmetry, find_group, integral_bases
from hkproof.pipelines.discover.report import FoundIntegral
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

__all__ = ["prove_group", "prove_with_integral_bases"]


def prove_group(ctx: SearchContext, group: Group, rng: random.Random) -> tuple[list[Frac], Certificate, str]:
    """Relations and coordinates made exact, then Prop. "prop: even" for the whole block system
    (hk.block_system.prove_blocks): the candidate, the certificate, and why the budget stopped the proof ("")."""
    labels = ["; ".join(f"({', '.join(group.labels(m))})" for m in group.members)]
    cert = Certificate(f"bases {labels[0]}", f"the kernel coordinates of the bases {labels[0]}, solved together, are "
                       "integrals", 'Prop. "prop: even" (block system)',
                       f"Each basis has a one-dimensional kernel; its coordinates, normalized by the last function "
                       "(-1), are integrals of the Kahan map. Functions I<k> are integrals of the continuous flow "
                       "(circuits of the kernel of its Lie derivative).",
                       fixed={k: str(v) for k, v in ctx.fixed.items()})
    with cert.step("basis functions", "monomials and integrals of the continuous flow (free of eps)",
                   ctx.kmap.ring) as s:
        for m in group.members:
            for name, f in zip(group.labels(m), group.order(m), strict=True):
                if name.startswith(("I", "s(")):
                    s.note(f"{name} = {f}")
    relations = lift_group_relations(ctx, group, rng)
    candidate = group_coordinates(ctx, group, rng)
    system = BlockSystem(ctx.kmap, tuple(tuple(group.order(m)) for m in group.members), tuple(relations), (0, 1))
    symmetry = None
    if group.symmetry is not None:
        sigma = group.symmetry
        symmetry = BlockSymmetry(sigma.apply, sigma.commutes,
                                 tuple((src, dst, tuple(range(len(group.order(group.members[src])))))
                                       for src, dst in group.images))
        carried = ", ".join(f"block {src + 1} to block {dst + 1}" for src, dst in group.images)
        cert.notes.append(f"s = ({sigma}) is a symmetry of the field; it carries {carried}: those blocks' "
                          "coordinates are images, their rows follow")
    cert, stopped = prove_blocks(cert, system, group.unknown_names(), candidate, symmetry,
                                 random.Random(rng.random()))
    return candidate, cert, stopped


def prove_with_integral_bases(ctx: SearchContext, monomials: Sequence[Exponents], known: dict[str, Frac],
                              degree: int, start_name: int) -> list[FoundIntegral]:
    """The stage: circuits, bases, a group, its proof; the coordinates that raise the exact Jacobian rank of the
    integrals proven so far, as found integrals (named I<start_name>, ...)."""
    rng = ctx.rng
    start = time.perf_counter()
    ctx.stages.start("integral bases", "bases with integrals of the continuous flow, solved together")
    circuits = continuous_integral_circuits(ctx.kmap, degree, rng)
    if not circuits:
        ctx.stages.say("the continuous flow has no polynomial integral of this degree")
        return []
    bases = integral_bases(ctx, monomials, circuits, list(known.values()), rng)
    ctx.stages.say(f"{len(circuits)} integral circuits of the flow; {len(bases)} minimal bases with one of them, "
                   f"{sum(b.new for b in bases)} carrying a new integral (gradients mod p)")
    group = find_group(ctx, bases, rng) if any(b.new for b in bases) else None
    if group is None:
        ctx.stages.say("no group of these bases gives a square system (mod p)")
        return []
    group = carried_by_symmetry(ctx, group)
    labels = [f"({', '.join(group.labels(m))})" for m in group.members]
    ctx.stages.say(f"{len(group.members)} bases solved together, {group.width} unknowns: {'; '.join(labels)}")
    if group.symmetry is not None:
        ctx.stages.say(f"the symmetry s = ({group.symmetry}) of the field carries "
                       + ", ".join(f"basis {src + 1} to basis {dst + 1}" for src, dst in group.images)
                       + ": their coordinates and rows are images")
    candidate, cert, stopped = prove_group(ctx, group, rng)
    if stopped:
        ctx.stages.say(f"{stopped}; the candidates are checked at random exact points instead (evidence)")
    if cert.status < Status.EVIDENCE_EXACT or (cert.status < Status.VERIFIED_SPECIALIZED and not stopped):
        ctx.stages.say(f"the block system was not proven: {cert.error or cert.steps[-1].detail}")
        return []
    full = ctx.full_map
    proven = [h.to_ring(full.ring) for h in known.values()]
    order = sorted(range(len(candidate)), key=lambda k: len(candidate[k].num) + len(candidate[k].den))
    trial = proven + [candidate[k].to_ring(full.ring) for k in order]
    chosen = independent_subset(trial, list(full.variables), jacobian_points(full.ring.names))
    labels_flat = [f"a{b + 1}_{k + 1} ({name})" for b, m in enumerate(group.members)
                   for k, name in enumerate(group.labels(m)[:-1])]
    out: list[FoundIntegral] = []
    for idx in chosen:
        if idx < len(proven):
            continue
        k = order[idx - len(proven)]
        name = f"I{start_name + len(out)}"
        cert.formula(name, candidate[k])
        method = (f"Prop. \"prop: even\" on {_bases_text(len(group.members))} (monomials and integrals of the "
                  f"continuous flow; {len(cert.steps)} steps)" if not stopped else
                  f"a candidate from {_bases_text(len(group.members))} (monomials and integrals of the continuous "
                  f"flow), constant at {cert.steps[-1].points} random exact points: evidence")
        out.append(FoundIntegral(name, candidate[k].to_ring(full.ring), cert.status, "kernel coordinate",
                                 labels, labels_flat[k], time.perf_counter() - start, method,
                                 [stopped] if stopped else [], certificate=cert))
    return out


def _bases_text(count: int) -> str:
    return "one basis" if count == 1 else f"{count} bases solved together"
