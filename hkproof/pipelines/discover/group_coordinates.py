"""A group's relations and coordinates made exact, with eps and the parameters symbolic (step 4 of `discover`'s last
stage): the relations' entries rebuilt on shared probes (hkproof.algebra.reconstruction, method "dense"), the
coordinates one sparse reconstruction each (independent jobs: side by side on the executor), each restored
to its weight; a member carried by a symmetry gets the images of its source's coordinates. Candidates: the block
proof (hk.block_system.prove_blocks) decides."""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.reconstruction import Rebuilt, reconstruct
from hkproof.budget import Budget
from hkproof.errors import BudgetExhausted, HKProofError
from hkproof.hk.reduced import Relation
from hkproof.pipelines.discover.blackbox import KernelBlackBox
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.groups import SAMPLES_SPARE, Group, ModularScene, Sampler
from hkproof.pipelines.discover.symbolic import BATCH, PRIME_BITS, restored
from hkproof.algebra.modular import random_prime

__all__ = ["group_coordinates", "unknown_weights", "lift_group_relations"]

Weight = list[flint.fmpq]


def _weight(ctx: SearchContext, h: Frac) -> Weight:
    return ctx.weights.of_frac(h) if not h.is_constant() else [flint.fmpq(0)] * len(ctx.weights.basis)


def unknown_weights(ctx: SearchContext, group: Group) -> list[Weight]:
    """[a_k] = [phi_l] - [phi_k] for every unknown (a_k = -c_k / c_l, the last function normalized)."""
    out = []
    for m in group.members:
        fs = group.order(m)
        last = _weight(ctx, fs[-1])
        out += [[a - b for a, b in zip(last, _weight(ctx, f), strict=True)] for f in fs[:-1]]
    return out


def lift_group_relations(ctx: SearchContext, group: Group, rng: random.Random) -> list[Relation]:
    """The constant relations of the group with eps and the parameters symbolic: their entries rebuilt on shared
    probes (hkproof.algebra.reconstruction, method "dense"), each restored to its weight."""
    width = group.width
    count = width + SAMPLES_SPARE
    shape: list[tuple[int, ...]] = []

    def relations_at(p: int, t: Sequence[int]) -> list[list[int]] | None:
        controls = {n: 1 for n in ctx.weights.normalized} | dict(zip(ctx.free, t, strict=True))
        try:
            mod = ModularScene(ctx, p, controls)
            sampler = Sampler(mod, group.bases, count, random.Random(rng.random()))
        except HKProofError:
            return None
        return sampler.relations(group.members)

    def box(p: int, t: Sequence[int]) -> list[int] | None:
        found = relations_at(p, t)
        if found is None:
            return None
        free = tuple(next(k for k, v in enumerate(r) if v == p - 1) for r in found)
        if not shape:
            shape.append(free)
        if free != shape[0]:
            return None
        return [v for r in found for k, v in enumerate(r) if k not in free]
    p0 = random_prime(rng, PRIME_BITS)
    first = box(p0, [rng.randrange(1, p0) for _ in ctx.free])
    if first is None:
        raise HKProofError("the relations of the group could not be sampled")
    flat = iter(reconstruct(lambda p, ts: [box(p, t) for t in ts], len(ctx.free), len(first), method="dense",
                            rng=rng)) if first else iter(())
    weights = unknown_weights(ctx, group) + [[flint.fmpq(0)] * len(ctx.weights.basis)]
    ring = ctx.kmap.ring
    out = []
    for free in shape[0]:
        entries: list[Frac] = []
        for k in range(width + 1):
            if k == free:
                entries.append(Frac(ring, -1))
            elif k in shape[0]:
                entries.append(Frac(ring, 0))
            else:
                target = [a - b for a, b in zip(weights[free], weights[k], strict=True)]
                entries.append(restored(ctx, next(flat), ctx.free, target))
        out.append(Relation(entries[:width], -entries[width]))
    return out


@dataclass(frozen=True)
class _Coordinate:
    """One unknown of a group rebuilt by sparse reconstruction over prime fields: a picklable job, so that the
    coordinates of a group can run side by side on the executor (each one's probes then run in its job)."""
    box: KernelBlackBox
    seed: int
    budget: Budget

    def __call__(self) -> Rebuilt | BudgetExhausted:
        """The reconstruction, or the BudgetExhausted that stopped it (returned, so that the others are kept)."""
        rng = random.Random(self.seed)
        try:
            return reconstruct(self.box, len(self.box.inputs), rng=rng, budget=self.budget, bits=PRIME_BITS,
                               batch_size=BATCH)[0]
        except BudgetExhausted as exc:
            return exc


def _rebuild(job: _Coordinate) -> Rebuilt | BudgetExhausted:
    return job()


def group_coordinates(ctx: SearchContext, group: Group, rng: random.Random) -> list[Frac]:
    """Every unknown a_k of the group with eps and the parameters symbolic, by sparse reconstruction over prime
    fields (the batch black box of recipe (B); the names weighted homogeneity normalizes set to 1, then restored):
    a candidate. The coordinates are independent reconstructions, each with its own seed: with an executor
    (ctx.mapper) they run side by side, one per job, with the same results as in a plain loop. The coordinates of a
    member that is the image of another under the group's symmetry are the images of that member's."""
    inputs = list(ctx.free) + list(ctx.kmap.variables)
    carried = {dst for _, dst in group.images}
    weights = iter(unknown_weights(ctx, group))
    jobs, shares = [], []
    for idx, m in enumerate(group.members):
        basis = group.order(m)
        seed = rng.randrange(2 ** 63)          # one per basis: its coordinates probe shared points (KernelBlackBox)
        for k in range(len(basis) - 1):
            weight = next(weights)
            if idx not in carried:
                jobs.append(_Coordinate(KernelBlackBox(ctx.kmap, basis, k, len(basis) - 1, inputs,
                                                       {n: 1 for n in ctx.weights.normalized}),
                                        seed, ctx.budget))
                shares.append(weight)
    if ctx.mapper is None:
        results: list[Rebuilt | BudgetExhausted] = []
        for job in jobs:
            results.append(job())
            if isinstance(results[-1], BudgetExhausted):
                break
    else:
        ctx.stages.say(f"step 5d: {len(jobs)} coordinates rebuilt side by side on the executor")
        results = list(ctx.mapper(_rebuild, jobs))
    done = [r for r in results if isinstance(r, Rebuilt)]
    stopped = next((r for r in results if isinstance(r, BudgetExhausted)), None)
    if stopped is not None:
        labels = "; ".join(f"({', '.join(group.labels(m))})" for m in group.members)
        raise BudgetExhausted(f"{stopped}; step 5d had reconstructed {len(done)} of the {len(jobs)} coordinates of "
                              f"the bases {labels}", limit=stopped.limit, raise_with=stopped.raise_with)
    rebuilt = iter(-restored(ctx, rec, inputs, weight)                        # a_k = -c_k / c_l
                   for rec, weight in zip(done, shares, strict=True))
    blocks: list[list[Frac]] = [[] if idx in carried else [next(rebuilt) for _ in range(len(group.order(m)) - 1)]
                                for idx, m in enumerate(group.members)]
    for src, dst in group.images:
        assert group.symmetry is not None
        blocks[dst] = [group.symmetry.apply(a) for a in blocks[src]]
    return [a for block in blocks for a in block]
