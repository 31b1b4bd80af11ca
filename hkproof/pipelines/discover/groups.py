"""Bases made of monomials and one integral of the continuous flow, and groups of them solved together, found modulo
a prime (steps 2 and 3 of `discover`'s last stage, hkproof.pipelines.discover.integral_bases):

- bases (some monomials of the kernel's support, one integral circuit I) with a one-dimensional kernel on orbits
  mod p, other than the identity I = its expansion, minimal; `new` when their coordinates raise the rank of the
  gradients of the integrals proven so far (the orbit's tangent maps);
- groups of such bases, each with a normalization, added greedily while the rows i = 0, 1 of every basis and the
  constant relations among all their coordinates (recipe (E) across bases, found mod p) come closer to a square
  system; a group is taken when they reach rank = unknowns; members carried to one another by a symmetry of the
  field are replaced by exact images.
Everything here is mod p: a search, not a proof.
"""
from __future__ import annotations

import itertools
import random
from dataclasses import dataclass, field
from typing import Sequence

import flint

from hkproof import budget
from hkproof.algebra.fraction import Frac, ModularFrac
from hkproof.algebra.modular import kernel_mod_p, random_prime, rank_mod_p
from hkproof.algebra.monomials import Exponents, text
from hkproof.errors import HKProofError, UnluckyPrimeError
from hkproof.hk.symmetries import SignedPermutation, field_symmetries
from hkproof.pipelines.discover.candidates import recipe_b_gradients
from hkproof.pipelines.discover.context import SearchContext

__all__ = ["SAMPLES_SPARE", "Group", "IntegralBasis", "Member", "ModularScene", "Sampler", "carried_by_symmetry", "find_group",
           "integral_bases", "kernel_vector", "normalized"]

MAX_BASIS = 6        # functions in a basis (monomials and one integral circuit)
MAX_GROUP = 4        # bases solved together
STARTS = 6           # bases (with each normalization) a group may start from
SAMPLES_SPARE = 12   # sample points beyond the number of unknowns when relations are sought mod p
SAMPLE_TRIES = 4     # random orbits tried per sample point wanted (a basis may be singular at some points)


@dataclass
class IntegralBasis:
    """A basis: monomials, then one integral circuit (`names` says I<k> for the k-th circuit); `new` when its
    coordinates carry an integral independent of those proven (gradients mod p)."""

    functions: list[Frac]
    names: list[str]
    new: bool


class ModularScene:
    """The map mod p at fixed eps and parameters, and functions of the ring evaluated there."""

    def __init__(self, ctx: SearchContext, p: int, controls: dict[str, int]):
        self.ctx, self.p, self.controls = ctx, p, controls
        self.map = ctx.kmap.mod(p, controls)
        self.names = ctx.kmap.ring.names
        self.phase = [self.names.index(v) for v in ctx.kmap.variables]
        self._reduced: dict[int, tuple[Frac, ModularFrac]] = {}     # by id: each function object reduced once

    def reduced(self, h: Frac) -> ModularFrac:
        """h mod p, reduced once per scene and function object (the tables of one scene evaluate the same basis
        functions many times; the object is kept with it, so that its id is not reused)."""
        if id(h) not in self._reduced:
            self._reduced[id(h)] = (h, h.mod_p(self.p))
        return self._reduced[id(h)][1]

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
        mods = [self.reduced(h) for h in functions]
        out = []
        for y in orbit:
            at = self.ring_point(y)
            row = [m(at) for m in mods]
            if any(v is None for v in row):
                raise HKProofError("a basis function has a pole on the orbit mod p")
            out.append([int(v) for v in row])      # type: ignore[arg-type]
        return out


def normalized(vector: Sequence[int], j: int, p: int) -> list[int] | None:
    """a_k = -c_k / c_j (k != j) for a kernel vector c: the unknowns of a basis normalized by its j-th function."""
    if vector[j] % p == 0:
        return None
    inv = pow(-vector[j], -1, p)
    return [c * inv % p for k, c in enumerate(vector) if k != j]


def integral_bases(ctx: SearchContext, monomials: Sequence[Exponents], circuits: Sequence[Frac],
                   known: Sequence[Frac], rng: random.Random) -> list[IntegralBasis]:
    """Minimal bases (monomials, one circuit) with a one-dimensional kernel on orbits mod p that is not the circuit's
    own expansion; `new` when their coordinates raise the gradient rank of `known` (at one orbit, mod p)."""
    kmap = ctx.kmap
    p = random_prime(rng, 62)
    controls = {n: rng.randrange(1, p) for n in kmap.field.control_names}
    mod = ModularScene(ctx, p, controls)
    mono_fracs = [Frac.parse(kmap.ring, text(kmap.variables, e)) for e in monomials]
    functions = mono_fracs + list(circuits)
    steps = MAX_BASIS + 3
    orbit, tangents = mod.map.tangent_orbit([rng.randrange(1, p) for _ in kmap.variables], steps)
    values = mod.table(functions, orbit)
    at = mod.ring_point(orbit[0])
    known_grads = [g for g in (mod.reduced(h).gradient(at, mod.phase) for h in known) if g is not None]
    base_rank = rank_mod_p(known_grads, p) if known_grads else 0
    m = len(monomials)
    out: list[IntegralBasis] = []
    for ci, circuit in enumerate(circuits):
        own = {k for k, h in enumerate(mono_fracs) if _occurs(h, circuit, mod.phase)}
        hits: list[set[int]] = []
        for size in range(1, MAX_BASIS):
            budget.check("searching bases with integrals of the flow")
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


def _coordinate_gradients(mod: ModularScene, basis: Sequence[Frac], orbit: Sequence[Sequence[int]],
                          tangents: Sequence[flint.nmod_mat]) -> list[list[int]] | None:
    """Gradients mod p of the coordinates of recipe (B) for basis functions given as fractions (candidates'
    `recipe_b_gradients`: grad phi at f^i(x), through the tangent map D(f^i)(x))."""
    p, l, nphase = mod.p, len(basis), len(mod.phase)
    mods = [mod.reduced(h) for h in basis]     # the objects `table` reduced: their derivatives are kept with them
    values = [[int(mods[k](mod.ring_point(orbit[i])) or 0) for k in range(l)] for i in range(l - 1)]

    def point_gradient(k: int, i: int) -> list[int]:
        return mods[k].gradient(mod.ring_point(orbit[i]), mod.phase) or [0] * nphase
    return recipe_b_gradients(values, point_gradient, tangents, p)


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


def kernel_vector(mod: ModularScene, basis: Sequence[Frac], orbit: Sequence[Sequence[int]]) -> list[int] | None:
    """The kernel vector of recipe (B)'s rows i = 0..l-2 on an orbit mod p (None where it is not one-dimensional)."""
    try:
        rows = mod.table(basis, orbit[:len(basis) - 1])
    except HKProofError:
        return None
    kernel = kernel_mod_p(rows, mod.p)
    return kernel[0] if len(kernel) == 1 else None


class Sampler:
    """Normalized coordinates of every candidate basis at shared random points, and the rows i = 0, 1 at a test
    point, mod p at one value of eps and the parameters: what deficits and relations are computed from."""

    def __init__(self, mod: ModularScene, bases: Sequence[IntegralBasis], count: int, rng: random.Random):
        self.mod, self.bases = mod, list(bases)
        self.vectors: list[list[list[int]]] = []
        steps = max(len(b.functions) for b in self.bases) - 2
        for _ in range(SAMPLE_TRIES * count):
            budget.check("sampling the coordinates of bases with integrals of the flow")
            orbit = mod.random_orbit(rng, steps)         # one orbit per point serves every basis
            vs = [kernel_vector(mod, b.functions, orbit) for b in self.bases]
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
                a = normalized(vs[b], j, self.mod.p)
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
    mod = ModularScene(ctx, p, {n: rng.randrange(1, p) for n in ctx.kmap.field.control_names})
    sampler = Sampler(mod, bases, MAX_GROUP * (MAX_BASIS - 1) + SAMPLES_SPARE, rng)
    starts = [b for b in sorted(range(len(bases)), key=lambda b: len(bases[b].functions)) if bases[b].new][:STARTS]
    for b0 in starts:
        for j0 in range(len(bases[b0].functions)):
            budget.check("grouping bases with integrals of the flow")
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
        budget.check("looking for symmetries that carry one basis of the group to another")
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
