"""Bases made of monomials and integrals of the continuous flow, solved together: the last stage of `discover`.

The paper builds bases from integrals of the continuous flow (Th. "dC Theta": I1, I2, I3 and H4) and proves
several bases at once with relations across them (Th. "dC bases 345"). Both ideas, driven by the search:

1. The polynomial integrals of the continuous flow of degree <= D, exactly (the kernel of the Lie derivative over
   Q(parameters)), and their circuits: the integrals of minimal support, which do not depend on a choice of basis.
2. Bases (some monomials of the kernel's support, one integral circuit I) with a one-dimensional kernel on orbits
   mod p, other than the identity I = its expansion, minimal; `new` when their coordinates raise the rank of the
   gradients of the integrals proven so far (the orbit's tangent maps).
3. Groups of such bases, each with a normalization, added greedily while the rows i = 0, 1 of every basis and the
   constant relations among all their coordinates (recipe (E) across bases, found mod p) come closer to a square
   system; a group is taken when they reach rank = unknowns.
4. The relations with eps and the parameters symbolic (hkproof.algebra.reconstruction, method "dense"), the coordinates by
   sparse reconstruction over prime fields, and the proof: Prop. "prop: even" for the whole block system
   (hk.block_system.verify_candidate: rank at a rational point, even relations and coordinates, every row and
   relation substituted exactly). Nothing is called an integral before that proof.
"""
from __future__ import annotations

import itertools
import random
import time
from dataclasses import dataclass, field
from typing import Sequence

import flint

from hkproof import budget
from hkproof.budget import Budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import cramer, lcm
from hkproof.algebra.modular import kernel_mod_p, random_prime, rank_mod_p
from hkproof.algebra.monomials import Exponents, exponents_upto, text
from hkproof.algebra.sampling import random_point
from hkproof.algebra.reconstruction import Rebuilt, reconstruct
from hkproof.errors import BudgetExhausted, HKProofError, SingularPointError, UnluckyPrimeError
from hkproof.hk.block_system import BlockSymmetry, BlockSystem, verify_candidate
from hkproof.hk.discover import independent_subset, jacobian_points
from hkproof.hk.independence import sample_point
from hkproof.hk.integrals import lie_derivative
from hkproof.hk.reduced import Relation
from hkproof.hk.symmetries import SignedPermutation, field_symmetries
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.report import FoundIntegral
from hkproof.pipelines.discover.blackbox import KernelBlackBox
from hkproof.pipelines.discover.candidates import recipe_b_gradients
from hkproof.pipelines.discover.symbolic import BATCH, PRIME_BITS, restored
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.export import prop_even_blocks_step, relation_data
from hkproof.proof.status import Status

__all__ = ["Group", "IntegralBasis", "carried_by_symmetry", "continuous_integral_circuits", "find_group",
           "group_coordinates",
           "integral_bases", "lift_group_relations", "prove_group", "prove_with_integral_bases"]

MAX_BASIS = 6        # functions in a basis (monomials and one integral circuit)
MAX_GROUP = 4        # bases solved together
MAX_CIRCUITS = 16    # integral circuits tried (smallest support first)
STARTS = 6           # bases (with each normalization) a group may start from
SAMPLES_SPARE = 12   # sample points beyond the number of unknowns when relations are sought mod p
SAMPLE_TRIES = 4     # random orbits tried per sample point wanted (a basis may be singular at some points)
Weight = list[flint.fmpq]


@dataclass
class IntegralBasis:
    """A basis: monomials, then one integral circuit (`names` says I<k> for the k-th circuit); `new` when its
    coordinates carry an integral independent of those proven (gradients mod p)."""

    functions: list[Frac]
    names: list[str]
    new: bool


class _Modular:
    """The map mod p at fixed eps and parameters, and functions of the ring evaluated there."""

    def __init__(self, ctx: SearchContext, p: int, controls: dict[str, int]):
        self.ctx, self.p, self.controls = ctx, p, controls
        self.map = ctx.kmap.mod(p, controls)
        self.names = ctx.kmap.ring.names
        self.phase = [self.names.index(v) for v in ctx.kmap.variables]

    def ring_point(self, x: Sequence[int]) -> list[int]:
        values = dict(zip(self.ctx.kmap.variables, x, strict=True)) | self.controls
        return [values[n] % self.p for n in self.names]

    def random_orbit(self, rng: random.Random, steps: int) -> list[list[int]]:
        for _ in range(20):
            try:
                return self.map.orbit([rng.randrange(1, self.p) for _ in self.phase], steps)
            except (UnluckyPrimeError, ZeroDivisionError):
                continue
        raise HKProofError(f"twenty random orbits mod {self.p} met det M = 0: the map looks singular")

    def table(self, functions: Sequence[Frac], orbit: Sequence[Sequence[int]]) -> list[list[int]]:
        """phi_k(f^i x) mod p, row i, column k (HKProofError where a function has a pole)."""
        mods = [h.mod_p(self.p) for h in functions]
        out = []
        for y in orbit:
            at = self.ring_point(y)
            row = [m(at) for m in mods]
            if any(v is None for v in row):
                raise HKProofError("a basis function has a pole on the orbit mod p")
            out.append([int(v) for v in row])      # type: ignore[arg-type]
        return out


def _normalized(vector: Sequence[int], j: int, p: int) -> list[int] | None:
    """a_k = -c_k / c_j (k != j) for a kernel vector c: the unknowns of a basis normalized by its j-th function."""
    if vector[j] % p == 0:
        return None
    inv = pow(-vector[j], -1, p)
    return [c * inv % p for k, c in enumerate(vector) if k != j]


def continuous_integral_circuits(ctx: SearchContext, degree: int, rng: random.Random) -> list[Frac]:
    """The polynomial integrals of x' = F(x) of degree <= `degree` with minimal support (circuits of the kernel of
    the Lie derivative), exact over Q(parameters), each checked exactly (L_F I = 0)."""
    kmap = ctx.kmap
    ring, field = kmap.ring, kmap.field
    n = len(kmap.variables)
    monos = [e for e in exponents_upto(n, degree) if any(e)]
    scale = Frac(ring, lcm([f.to_ring(ring).den for f in field.rhs]))   # a constant time scale clears denominators
    derivs = [lie_derivative(field, Frac.parse(field.ring, text(kmap.variables, e))).to_ring(ring) * scale
              for e in monos]
    phase = [ring.index(v) for v in kmap.variables]
    rows: dict[tuple[int, ...], dict[int, dict]] = {}
    for col, d in enumerate(derivs):
        if not d.den.is_one():
            raise HKProofError("the Lie derivative of a monomial has a denominator in the phase variables: the "
                               "field is not polynomial")
        for m, c in d.num.to_dict().items():
            key = tuple(m[i] for i in phase)
            rest = tuple(0 if i in phase else e for i, e in enumerate(m))
            rows.setdefault(key, {}).setdefault(col, {})[rest] = c
    matrix = [[Frac(ring, ring.ctx.from_dict(row[c])) if c in row else Frac(ring, 0) for c in range(len(monos))]
              for row in rows.values()]
    p = random_prime(rng, 62)
    controls = [rng.randrange(1, p) if i not in phase else 0 for i in range(len(ring.names))]
    mod = [[int(e.residue_at(controls, p) or 0) for e in r] for r in matrix]
    kernel = kernel_mod_p(mod, p)
    if not kernel:
        return []
    support = [c for c in range(len(monos)) if any(v[c] for v in kernel)]
    supports: set[tuple[int, ...]] = set()
    for zeros in itertools.combinations(support, len(kernel) - 1):
        extra = [[1 if c == z else 0 for c in range(len(monos))] for z in zeros]
        restricted = kernel_mod_p(mod + extra, p)
        if len(restricted) == 1:
            supports.add(tuple(c for c in range(len(monos)) if restricted[0][c]))
    minimal = sorted((s for s in supports if not any(set(t) < set(s) for t in supports)), key=len)
    out = []
    for s in minimal[:MAX_CIRCUITS]:
        sub = [[r[c] for c in s] for r in mod]
        chosen: list[int] = []
        for i, r in enumerate(sub):
            if rank_mod_p([sub[k] for k in chosen] + [r], p) > len(chosen):
                chosen.append(i)
        if len(chosen) != len(s) - 1:
            continue
        square = [[matrix[i][c] for c in s[1:]] for i in chosen]
        rhs = [-matrix[i][s[0]] for i in chosen]
        try:
            coeffs = [Frac(ring, 1)] + cramer(square, rhs)[0]
        except (HKProofError, ZeroDivisionError):
            continue
        total = sum((a * Frac.parse(ring, text(kmap.variables, monos[c])) for a, c in zip(coeffs, s, strict=True)),
                    Frac(ring, 0))
        integral = Frac(ring, total.num)
        if not integral.is_zero() and lie_derivative(field, integral.to_ring(field.ring)).is_zero():
            out.append(integral)
    return out


def integral_bases(ctx: SearchContext, monomials: Sequence[Exponents], circuits: Sequence[Frac],
                   known: Sequence[Frac], rng: random.Random) -> list[IntegralBasis]:
    """Minimal bases (monomials, one circuit) with a one-dimensional kernel on orbits mod p that is not the circuit's
    own expansion; `new` when their coordinates raise the gradient rank of `known` (at one orbit, mod p)."""
    kmap = ctx.kmap
    p = random_prime(rng, 62)
    controls = {n: rng.randrange(1, p) for n in kmap.field.control_names}
    mod = _Modular(ctx, p, controls)
    mono_fracs = [Frac.parse(kmap.ring, text(kmap.variables, e)) for e in monomials]
    functions = mono_fracs + list(circuits)
    steps = MAX_BASIS + 3
    orbit, tangents = mod.map.tangent_orbit([rng.randrange(1, p) for _ in kmap.variables], steps)
    values = mod.table(functions, orbit)
    at = mod.ring_point(orbit[0])
    known_grads = [g for g in (h.mod_p(p).gradient(at, mod.phase) for h in known) if g is not None]
    base_rank = rank_mod_p(known_grads, p) if known_grads else 0
    m = len(monomials)
    out: list[IntegralBasis] = []
    for ci, circuit in enumerate(circuits):
        own = {k for k, h in enumerate(mono_fracs) if _occurs(h, circuit, mod.phase)}
        hits: list[set[int]] = []
        for size in range(1, MAX_BASIS):
            ctx.budget.check("searching bases with integrals of the flow")
            for subset in itertools.combinations(range(m), size):
                chosen = set(subset)
                if own <= chosen or any(h <= chosen for h in hits):
                    continue
                cols = list(subset) + [m + ci]
                rows = [[r[c] for c in cols] for r in values]
                if len(kernel_mod_p([r[:-1] for r in rows], p)) or len(kernel_mod_p(rows, p)) != 1:
                    continue
                hits.append(chosen)
                basis = [functions[c] for c in cols]
                grads = _coordinate_gradients(mod, basis, orbit, tangents)
                new = grads is not None and rank_mod_p(known_grads + grads, p) > base_rank
                out.append(IntegralBasis(basis, [text(kmap.variables, monomials[c]) for c in subset] +
                                         [f"I{ci + 1}"], new))
    return out


def _occurs(monomial: Frac, circuit: Frac, phase: Sequence[int]) -> bool:
    """Whether the monomial x^e occurs in the circuit (its coefficient a polynomial in the parameters)."""
    (e,) = monomial.num.monoms()
    return any(all(m[i] == e[i] for i in phase) for m in circuit.num.monoms())


def _coordinate_gradients(mod: _Modular, basis: Sequence[Frac], orbit: Sequence[Sequence[int]],
                          tangents: Sequence[flint.nmod_mat]) -> list[list[int]] | None:
    """Gradients mod p of the coordinates of recipe (B) for basis functions given as fractions (candidates'
    `recipe_b_gradients`: grad phi at f^i(x), through the tangent map D(f^i)(x))."""
    p, l, nphase = mod.p, len(basis), len(mod.phase)
    mods = [h.mod_p(p) for h in basis]
    values = [[int(mods[k](mod.ring_point(orbit[i])) or 0) for k in range(l)] for i in range(l - 1)]

    def gradient(k: int, i: int) -> list[int]:
        g = mods[k].gradient(mod.ring_point(orbit[i]), mod.phase) or [0] * nphase
        row = flint.nmod_mat([g], p) * tangents[i]
        return [int(row[0, c]) for c in range(nphase)]
    return recipe_b_gradients(values, gradient, p)


Member = tuple[int, int]      # (basis index, the index of its normalized function)


@dataclass
class Group:
    """Bases solved together, each with its normalized function, and the relations among their coordinates mod p;
    `images` (source, target) are members whose basis is the image of an earlier member's under `symmetry`, a
    symmetry of the map (their coordinates are images too, and so are their rows)."""

    members: list[Member]
    bases: list[IntegralBasis]
    symmetry: SignedPermutation | None = None
    images: list[tuple[int, int]] = field(default_factory=list)

    def order(self, m: Member) -> list[Frac]:
        """The functions of a member's basis, the normalized one last (hk.block_system's convention)."""
        b, j = m
        fs = self.bases[b].functions
        return [f for k, f in enumerate(fs) if k != j] + [fs[j]]

    def labels(self, m: Member) -> list[str]:
        b, j = m
        names = self.bases[b].names
        return [n for k, n in enumerate(names) if k != j] + [names[j]]

    @property
    def width(self) -> int:
        return sum(len(self.bases[b].functions) - 1 for b, _ in self.members)

    def unknown_names(self) -> list[str]:
        """a<block>_<k> for every unknown, block after block (the names of the certificates)."""
        return [f"a{b + 1}_{k + 1}" for b, m in enumerate(self.members) for k in range(len(self.order(m)) - 1)]


def _kernel_vector(mod: _Modular, basis: Sequence[Frac], orbit: Sequence[Sequence[int]]) -> list[int] | None:
    """The kernel vector of recipe (B)'s rows i = 0..l-2 on an orbit mod p (None where it is not one-dimensional)."""
    try:
        rows = mod.table(basis, orbit[:len(basis) - 1])
    except HKProofError:
        return None
    kernel = kernel_mod_p(rows, mod.p)
    return kernel[0] if len(kernel) == 1 else None


class _Sampler:
    """Normalized coordinates of every candidate basis at shared random points, and the rows i = 0, 1 at a test
    point, mod p at one value of eps and the parameters: what deficits and relations are computed from."""

    def __init__(self, mod: _Modular, bases: Sequence[IntegralBasis], count: int, rng: random.Random):
        self.mod, self.bases = mod, list(bases)
        self.vectors: list[list[list[int]]] = []
        steps = max(len(b.functions) for b in self.bases) - 2
        for _ in range(SAMPLE_TRIES * count):
            budget.check("sampling the coordinates of bases with integrals of the flow")
            orbit = mod.random_orbit(rng, steps)         # one orbit per point serves every basis
            vs = [_kernel_vector(mod, b.functions, orbit) for b in self.bases]
            if all(v is not None for v in vs):
                self.vectors.append(vs)            # type: ignore[arg-type]
                if len(self.vectors) == count:
                    break
        else:
            raise HKProofError(f"fewer than {count} of {SAMPLE_TRIES * count} random orbits mod {mod.p} give every "
                               "basis a one-dimensional kernel")
        orbit = mod.random_orbit(rng, 1)
        self.rows = [mod.table(b.functions, orbit) for b in self.bases]

    def relations(self, members: Sequence[Member]) -> list[list[int]] | None:
        """The constant relations sum v_k a_k + v_U = 0 among the members' coordinates (kernel of the samples)."""
        matrix = []
        for vs in self.vectors:
            row: list[int] = []
            for b, j in members:
                a = _normalized(vs[b], j, self.mod.p)
                if a is None:
                    return None
                row += a
            matrix.append(row + [1])
        return kernel_mod_p(matrix, self.mod.p)

    def deficit(self, members: Sequence[Member]) -> int:
        """Unknowns minus the rank of the rows i = 0, 1 of every member and the relations among them."""
        relations = self.relations(members)
        width = Group(list(members), list(self.bases)).width
        if relations is None:
            return width
        system, start = [], 0
        for b, j in members:
            size = len(self.bases[b].functions) - 1
            for values in self.rows[b]:
                row = [0] * width
                row[start:start + size] = [v for k, v in enumerate(values) if k != j]
                system.append(row)
            start += size
        system += [r[:width] for r in relations]
        return width - rank_mod_p(system, self.mod.p)


def find_group(ctx: SearchContext, bases: Sequence[IntegralBasis], rng: random.Random) -> Group | None:
    """Bases with normalizations whose rows i = 0, 1 and constant relations form a square system (mod p), grown
    greedily from each new basis (smallest first) by the member that leaves the smallest deficit."""
    p = random_prime(rng, 62)
    mod = _Modular(ctx, p, {n: rng.randrange(1, p) for n in ctx.kmap.field.control_names})
    sampler = _Sampler(mod, bases, MAX_GROUP * (MAX_BASIS - 1) + SAMPLES_SPARE, rng)
    starts = [b for b in sorted(range(len(bases)), key=lambda b: len(bases[b].functions)) if bases[b].new][:STARTS]
    for b0 in starts:
        for j0 in range(len(bases[b0].functions)):
            ctx.budget.check("grouping bases with integrals of the flow")
            members = [(b0, j0)]
            deficit = sampler.deficit(members)
            while deficit > 0 and len(members) < MAX_GROUP:
                used = {b for b, _ in members}
                options = [(sampler.deficit(members + [(b, j)]), (b, j)) for b in range(len(bases)) if b not in used
                           for j in range(len(bases[b].functions))]
                if not options:
                    break
                deficit, best = min(options)
                members.append(best)
            if deficit == 0:
                return Group([(k, j) for k, (_, j) in enumerate(members)], [bases[b] for b, _ in members])
    return None


def _proportional(a: Frac, b: Frac, phase: set[str]) -> bool:
    """a = c b with c free of the phase variables (a function of eps and the parameters only)."""
    return not a.is_zero() and not b.is_zero() and not ((a / b).variables() & phase)


def _carries(sigma: SignedPermutation, group: Group, src: int, dst: int, phase: set[str]) -> bool:
    """Whether sigma carries the basis of member src to that of member dst, function by function up to factors free
    of x, the normalized function to the normalized one."""
    source, target = group.order(group.members[src]), group.order(group.members[dst])
    if len(source) != len(target):
        return False
    images = [sigma.apply(h) for h in source]
    if not _proportional(images[-1], target[-1], phase):
        return False
    free = list(range(len(target) - 1))
    for h in images[:-1]:
        k = next((k for k in free if _proportional(h, target[k], phase)), None)
        if k is None:
            return False
        free.remove(k)
    return True


def carried_by_symmetry(ctx: SearchContext, group: Group) -> Group:
    """The group with as many members as possible replaced by images of earlier ones under one symmetry of the
    field (hk.symmetries: signed permutations of the variables with the parameters permuted): a member whose basis a
    symmetry carries to another's, up to factors free of x, is replaced by the exact image, so that its coordinates
    and its rows are images too (the system keeps its rank: only functions are rescaled)."""
    if len(group.members) < 2 or not ctx.symmetries:
        return group
    phase = set(ctx.kmap.variables)
    best: tuple[SignedPermutation | None, list[tuple[int, int]]] = (None, [])
    for sigma in field_symmetries(ctx.kmap.field):
        ctx.budget.check("looking for symmetries that carry one basis of the group to another")
        images: list[tuple[int, int]] = []
        for dst in range(1, len(group.members)):
            src = next((s for s in range(dst) if _carries(sigma, group, s, dst, phase)), None)
            if src is not None:
                images.append((src, dst))
        if len(images) > len(best[1]):
            best = (sigma, images)
    chosen, images = best
    if chosen is None:
        return group
    out = Group(list(group.members), list(group.bases), chosen, images)
    for src, dst in images:                 # in order: a source carried earlier is already its exact image
        functions = [chosen.apply(h) for h in out.order(out.members[src])]
        names = [f"s({n})" if n.startswith(("I", "s(")) else str(h)
                 for n, h in zip(out.labels(out.members[src]), functions, strict=True)]
        out.bases.append(IntegralBasis(functions, names, out.bases[out.members[dst][0]].new))
        out.members[dst] = (len(out.bases) - 1, len(functions) - 1)
    return out


def _weight(ctx: SearchContext, h: Frac) -> Weight:
    return ctx.weights.of_frac(h) if not h.is_constant() else [flint.fmpq(0)] * len(ctx.weights.basis)


def _coordinate_weights(ctx: SearchContext, group: Group) -> list[Weight]:
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
            mod = _Modular(ctx, p, controls)
            sampler = _Sampler(mod, group.bases, count, random.Random(rng.random()))
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
    weights = _coordinate_weights(ctx, group) + [[flint.fmpq(0)] * len(ctx.weights.basis)]
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
    coordinates of a group can run side by side on the executor of --jobs (each one's probes then run in its job)."""
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
    weights = iter(_coordinate_weights(ctx, group))
    jobs, shares = [], []
    for idx, m in enumerate(group.members):
        basis = group.order(m)
        for k in range(len(basis) - 1):
            weight = next(weights)
            if idx not in carried:
                jobs.append(_Coordinate(KernelBlackBox(ctx.kmap, basis, k, len(basis) - 1, inputs,
                                                       {n: 1 for n in ctx.weights.normalized}),
                                        rng.randrange(2 ** 63), ctx.budget))
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


def prove_group(ctx: SearchContext, group: Group, rng: random.Random) -> tuple[list[Frac], Certificate]:
    """Relations and coordinates made exact, then Prop. "prop: even" for the whole block system."""
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
    names = group.unknown_names()
    point = sample_point(ctx.kmap.ring.names, 3)
    symmetry = None
    if group.symmetry is not None:
        sigma = group.symmetry
        symmetry = BlockSymmetry(sigma.apply, sigma.commutes,
                                 tuple((src, dst, tuple(range(len(group.order(group.members[src])))))
                                       for src, dst in group.images))
        carried = ", ".join(f"block {src + 1} to block {dst + 1}" for src, dst in group.images)
        cert.notes.append(f"s = ({sigma}) is a symmetry of the field; it carries {carried}: those blocks' "
                          "coordinates are images, their rows follow")
    try:
        verify_candidate(cert, system, names, candidate, point, symmetry)
        blocks = [(basis[:-1], basis[-1]) for basis in system.bases]
        rows = [relation_data(r.coefficients, r.rhs) for r in relations]
        cert.checks.append(prop_even_blocks_step(ctx.kmap.field, blocks, names, candidate, (0, 1), rows, point))
    except ProofStopped as exc:
        cert.error = str(exc)
    except HKProofError as exc:
        cert.error = f"{type(exc).__name__}: {exc}"
    return candidate, cert


EVIDENCE_POINTS = 2
"""Random exact points at which a candidate whose proof the budget stopped is checked (a(f(x)) = a(x))."""


def stopped_by_budget(cert: Certificate) -> bool:
    """Whether the proof stopped because the time budget ran out (in a step, e.g. a row check by Horner)."""
    return bool(cert.steps) and cert.steps[-1].status is Status.UNKNOWN and \
        cert.steps[-1].detail.startswith(BudgetExhausted.__name__)


def evidence_at_points(ctx: SearchContext, names: Sequence[str], candidate: Sequence[Frac],
                       rng: random.Random) -> Certificate:
    """Evidence(exact) for candidates whose proof was stopped: a(f(x)) = a(x) exactly at EVIDENCE_POINTS random
    rational points (x, eps and the parameters random); refuted if one differs. Not a proof."""
    kmap = ctx.kmap
    cert = Certificate("bases (evidence)", "the kernel coordinates of the bases are constant along the map at random "
                       "exact points", 'sec. 3 (an integral: h o f = h), at points', "Evidence, not proof: each "
                       "coordinate takes the same exact value at x and at f(x) for random rational x, eps and "
                       "parameters.", fixed={k: str(v) for k, v in ctx.fixed.items()})
    controls = [n for n in kmap.ring.names if n not in kmap.variables]
    try:
        with cert.step("a(f(x)) = a(x) at random exact points", "exact arithmetic over Q (the map by one linear "
                       "solve)", f"Q at {EVIDENCE_POINTS} points") as s:
            checked = 0
            for _ in range(4 * EVIDENCE_POINTS):
                point = random_point(rng, [*kmap.variables, *controls], 5, denominator=7)
                try:
                    image = {**point, **kmap.step_exact(point)}
                    values = [(a.evaluate(point), a.evaluate(image)) for a in candidate]
                except SingularPointError:
                    continue
                for n, (here, there) in zip(names, values, strict=True):
                    s.require(here == there, f"{n} takes {here} at x and {there} at f(x): not an integral")
                checked += 1
                if checked == EVIDENCE_POINTS:
                    break
            s.require(checked > 0, "the map or a candidate is singular at every random point tried")
            s.evidence(Status.EVIDENCE_EXACT, points=checked)
    except ProofStopped as exc:
        cert.error = str(exc)
    return cert


def prove_with_integral_bases(ctx: SearchContext, monomials: Sequence[Exponents], known: dict[str, Frac],
                              degree: int, start_name: int) -> list[FoundIntegral]:
    """The stage: circuits, bases, a group, its proof; the coordinates that raise the exact Jacobian rank of the
    integrals proven so far, as found integrals (named I<start_name>, ...)."""
    rng = ctx.rng
    start = time.perf_counter()
    ctx.stages.start("integral bases", "bases with integrals of the continuous flow, solved together")
    circuits = continuous_integral_circuits(ctx, degree, rng)
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
    candidate, cert = prove_group(ctx, group, rng)
    stopped = ""
    if cert.status < Status.VERIFIED_SPECIALIZED and stopped_by_budget(cert):
        stopped = f"the proof by Prop. \"prop: even\" was stopped: {cert.error}"
        ctx.stages.say(f"{stopped}; the candidates are checked at random exact points instead (evidence)")
        cert = evidence_at_points(ctx, group.unknown_names(), candidate, random.Random(rng.random()))
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
