"""Reduced HK systems of several bases at once (sec. 6.7, eqs. "Psi1 iterates" ... "Psi3 iterates") and the steps of
the proof of Th. "dC bases 345", written once for any map and bases given as data.

The unknowns of all bases form one vector, block after block (each basis' last element is the normalized one, its
coefficient -1); linear relations may run across blocks (recipe (E)) and have integrals on the right. The steps:

- `determined_components` (Step 1): rank one short of the width at a point and an exact kernel direction: every
  solution has the components where the direction vanishes;
- `prove_block` (Steps 3-5): one block by Prop. "prop: even", the components of other blocks known (the relations
  that involve only that block and known components);
- `check_block`, `BlockSystem.block_det_at` (Step 2): another choice of rows (the symmetric i = -1, 0, 1) has the
  same unique solution;
- `verify_candidate` (where no block decouples, as for the second Clebsch flow): Prop. "prop: even" for the whole
  system and a candidate found by any means (`hk.completion`), the rows with iterates checked by Horner
  (`hk.row_check`) or carried from one block to another by a symmetry of the map (`BlockSymmetry`, checked).
"""
from __future__ import annotations

import random
from dataclasses import dataclass, field, replace
from typing import Callable, Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational
from hkproof.algebra.sampling import random_point
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, SingularPointError
from hkproof.hk.independence import sample_point
from hkproof.hk.reduced import (
    OverCommonDenominator,
    Relation,
    det_at_point,
    even_components,
    linear_combination_equals,
    prop_even_hypotheses,
    prove_by_evenness,
    system_at,
)
from hkproof.hk.row_check import row_holds
from hkproof.hk.translation import ParameterTranslation, check_solution_on_slice, prove_on_slice
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.export import prop_even_blocks_step, relation_data
from hkproof.proof.status import Status

__all__ = ["BlockSymmetry", "BlockSystem", "EVIDENCE_POINTS", "check_block", "determined_components", "evidence_at_points",
           "prove_block", "prove_blocks", "verify_candidate"]


@dataclass(frozen=True)
class BlockSystem:
    """The rows i in `iterates` of every basis and the `relations` (rows of length `width`, over all blocks)."""

    kmap: KahanMap
    bases: tuple[tuple[Frac, ...], ...]
    relations: tuple[Relation, ...] = ()
    iterates: tuple[int, ...] = (0, 1)

    def __post_init__(self) -> None:
        for k, rel in enumerate(self.relations):
            if len(rel.coefficients) != self.width:
                raise HKProofError(f"relation {k + 1} has {len(rel.coefficients)} coefficients, but the bases have "
                                   f"{self.width} unknowns")

    @property
    def width(self) -> int:
        return sum(len(b) - 1 for b in self.bases)

    def block(self, b: int) -> range:
        """The positions of block b's unknowns."""
        start = sum(len(x) - 1 for x in self.bases[:b])
        return range(start, start + len(self.bases[b]) - 1)

    def with_(self, *, relations: Sequence[Relation] | None = None,
              iterates: Sequence[int] | None = None) -> BlockSystem:
        """The same bases with other relations or other rows."""
        return replace(self, relations=self.relations if relations is None else tuple(relations),
                       iterates=self.iterates if iterates is None else tuple(iterates))

    def at(self, point: Mapping[str, Rational]) -> tuple[list[list[flint.fmpq]], list[flint.fmpq]]:
        """The system at one exact point (rows, right-hand sides)."""
        return system_at(self.kmap, self.bases, self.iterates, self.relations, point)

    def rank_at(self, point: Mapping[str, Rational]) -> int:
        """Exact rank at a point: a lower bound for the generic rank."""
        return flint.fmpq_mat(self.at(point)[0]).rank()

    def restricted(self, b: int, known: Mapping[int, Frac], source: str) -> list[Relation]:
        """The relations that involve block b and otherwise only `known` components, as relations among block b's
        unknowns, the known part moved to the right (an integral by `source` when it is not zero)."""
        inside, out = set(self.block(b)), []
        for rel in self.relations:
            support = {k for k, c in enumerate(rel.coefficients) if not c.is_zero()}
            if not support & inside or not support <= inside | set(known):
                continue
            moved = [rel.coefficients[k] * known[k] for k in sorted(support - inside)]
            rhs = rel.rhs - sum(moved, Frac(rel.rhs.ring, 0)) if moved else rel.rhs
            label = rel.source if not moved else source if rel.source == "constant" else f"{rel.source}; {source}"
            out.append(Relation([rel.coefficients[k] for k in self.block(b)], rhs, label))
        return out

    def block_det_at(self, b: int, point: Mapping[str, Rational]) -> flint.fmpq:
        """The determinant of block b's square system (its rows and the relations inside the block) at a point."""
        relations = self.restricted(b, {}, "")
        return det_at_point(self.kmap, self.bases[b][:-1], self.iterates, relations, point)


@dataclass(frozen=True)
class BlockSymmetry:
    """A substitution tau with tau o f = f o tau (`holds` checks it exactly); each of `images` (source, target,
    perm) says that tau carries the basis of block source to that of block target, tau(source basis[perm[k]]) =
    target basis[k]. Then tau carries every row identity of the source block to that of the target block, the
    solution's components permuted the same way (images apply in order, so chains source -> target -> ... work)."""

    apply: Callable[[Frac], Frac]
    holds: Callable[[KahanMap], bool]
    images: tuple[tuple[int, int, tuple[int, ...]], ...] = field(default=())

    def image(self, block: Sequence[Frac], perm: Sequence[int]) -> list[Frac]:
        """tau of a source block's components, in the target block's order (the last, normalized one dropped)."""
        return [self.apply(block[j]) for j in perm[:-1]]


def determined_components(cert: Certificate, system: BlockSystem, shapes: Sequence[Sequence[Frac]],
                          point: Mapping[str, Rational], scales: Sequence[Frac] | None = None) -> list[int]:
    """Step 1 of the proof of Th. "dC bases 345": the system has rank width - 1 at a point and the direction (block b:
    scales[b] * shapes[b], scales 1 by default) is an exact non-zero kernel vector, so every solution has the same
    components where the direction vanishes. A row sees one block, so it is checked on the shape (once for blocks
    that share their basis functions and shape)."""
    f, ring, width = system.kmap, system.kmap.ring, system.width
    zero, one = Frac(ring, 0), Frac(ring, 1)
    factors = list(scales) if scales is not None else [one] * len(system.bases)
    if len(shapes) != len(system.bases) or len(factors) != len(system.bases) or \
            any(len(shape) != len(system.block(b)) for b, shape in enumerate(shapes)):
        raise HKProofError("the direction needs one shape and one scale per basis, of the lengths of the blocks")
    direction = [c * h for c, shape in zip(factors, shapes, strict=True) for h in shape]
    with cert.step("the kernel direction of the system", "exact identities: every row and every relation "
                   "annihilates it (the rows on each block's shape)", ring) as s:
        s.require(any(not c.is_zero() for c in direction), "the direction is zero")
        moved: dict[tuple[int, int], Frac] = {}
        checked: set[tuple] = set()
        for b, (basis, shape) in enumerate(zip(system.bases, shapes, strict=True)):
            support = [k for k, h in enumerate(shape) if not h.is_zero()]
            for i in system.iterates:
                key = (i, *((id(basis[k]), id(shape[k])) for k in support))
                if key in checked:
                    continue
                values = [moved.setdefault((id(basis[k]), i), f.pullback(basis[k], i)) for k in support]
                s.require(linear_combination_equals(values, [shape[k] for k in support], zero),
                          f"the direction violates the row i = {i} of block {b + 1}")
                checked.add(key)
        for k, rel in enumerate(system.relations):
            s.require(linear_combination_equals(rel.coefficients, direction, zero),
                      f"the direction violates relation {k + 1}")
    rows = len(system.iterates) * len(system.bases) + len(system.relations)
    with cert.step(f"rank {width - 1}", f"exact rank of the {rows} x {width} system at a rational point", ring) as s:
        got = system.rank_at(point)
        s.require(got == width - 1, f"rank {got} at the sample point, not {width - 1}: choose another point")
        s.note(f"a non-zero minor of order {width - 1} at a point: the kernel is spanned by the direction, so the "
               "components where it vanishes are the same for every solution")
    return [k for k in range(width) if direction[k].is_zero()]


def prove_block(cert: Certificate, system: BlockSystem, b: int, known: Mapping[int, Frac], names: Sequence[str],
                source: str, shift: ParameterTranslation | None = None) -> list[Frac]:
    """Steps 3-5 of the proof of Th. "dC bases 345": block b by Prop. "prop: even" (its rows, the relations inside
    it, `known` components of other blocks moved right, integrals by `source`), on the slice of `shift` if given."""
    basis = system.bases[b]
    relations = system.restricted(b, known, source)
    if len(system.iterates) + len(relations) != len(basis) - 1:
        raise HKProofError(f"block {b + 1}: {len(system.iterates)} rows and {len(relations)} relations for "
                           f"{len(basis) - 1} unknowns: the system is not square")
    if shift is None:
        return prove_by_evenness(cert, system.kmap, basis[:-1], basis[-1], names, system.iterates, relations)
    return prove_on_slice(cert, system.kmap, shift, basis[:-1], basis[-1], names, system.iterates, relations)


def check_block(system: BlockSystem, b: int, known: Mapping[int, Frac], solution: Sequence[Frac],
                shift: ParameterTranslation) -> bool:
    """Block b's rows and inside relations hold for `solution` (Step 2, the row i = -1), on the slice if invariant."""
    basis = system.bases[b]
    return check_solution_on_slice(system.kmap, shift, basis[:-1], basis[-1], system.iterates,
                                   system.restricted(b, known, ""), solution)


def verify_candidate(cert: Certificate, system: BlockSystem, names: Sequence[str], candidate: Sequence[Frac],
                     point: Mapping[str, Rational], symmetry: BlockSymmetry | None = None) -> list[Frac]:
    """Prop. "prop: even" for the whole block system and a candidate found by any means: rank = width at a point
    (uniqueness), the hypotheses on rows and relations, every component even in eps, and the candidate substituted
    into every relation and row (rows with iterates by Horner; those of a symmetry's target blocks as images)."""
    f, ring = system.kmap, system.kmap.ring
    if len(candidate) != system.width or len(names) != system.width:
        raise HKProofError(f"{len(candidate)} components and {len(names)} names for {system.width} unknowns")
    with cert.step(f"unique solution: the rows and relations have rank {system.width}",
                   "exact rank at a rational point", ring) as s:
        got = system.rank_at(point)
        s.require(got == system.width, f"rank {got} at the point, not {system.width}")
    prop_even_hypotheses(cert, f, system.iterates, system.relations)
    even_components(cert, names, candidate)
    carried = {dst for _, dst, _ in symmetry.images} if symmetry else set()
    with cert.step("the candidate satisfies the system", "substitution: relations and rows i = 0 exactly, rows with "
                   "iterates by Horner's scheme in the numerators of f^i (hk.row_check: expanded, or at the points of "
                   "a unisolvent lattice in the parameters, or modulo primes beyond twice a proven coefficient "
                   "bound; the route of each row is noted)" +
                   ("; the rows of the carried blocks as images under a symmetry of f (checked)" if carried else ""),
                   ring) as s:
        common = OverCommonDenominator.of(candidate)   # the candidate over one denominator for every relation
        for k, rel in enumerate(system.relations):
            s.require(linear_combination_equals(rel.coefficients, candidate, rel.rhs, common),
                      f"relation {k + 1} fails")
        for b, basis in enumerate(system.bases):
            block = [candidate[k] for k in system.block(b)]
            for i in system.iterates:
                if i == 0 or b not in carried:
                    row = row_holds(f, basis[:-1], basis[-1], i, block)
                    s.require(row.holds, f"{row.route}: row i = {i} of block {b + 1} fails")
                    if i:
                        s.note(f"block {b + 1}, {row.route}")
        if symmetry:
            s.require(symmetry.holds(f), "the symmetry does not commute with the map")
            established = set(range(len(system.bases))) - carried
            for src, dst, perm in symmetry.images:
                s.require(src in established, f"block {src + 1} is carried before its rows are established")
                source, target = system.bases[src], system.bases[dst]
                s.require(len(perm) == len(source) == len(target) and perm[-1] == len(source) - 1 and
                          all(symmetry.apply(source[j]) == target[k] for k, j in enumerate(perm)),
                          f"the symmetry does not carry basis {src + 1} to basis {dst + 1}")
                moved = [candidate[k] for k in system.block(src)]
                s.require(symmetry.image(moved, perm) == [candidate[k] for k in system.block(dst)],
                          f"block {dst + 1} of the candidate is not the image of block {src + 1}")
                established.add(dst)
            s.note("tau o f = f o tau: tau carries the row identities of each source block to those of its target")
    for n, a in zip(names, candidate, strict=True):
        cert.formula(n, a)
    return list(candidate)


def prove_blocks(cert: Certificate, system: BlockSystem, names: Sequence[str], candidate: Sequence[Frac],
                 symmetry: BlockSymmetry | None, rng: random.Random) -> tuple[Certificate, str]:
    """Prop. "prop: even" for the whole block system and a candidate (`verify_candidate`, at a rational point), its
    re-checkable step recorded in `cert`; (cert, ""). A proof the budget stopped (Certificate.stopped_by_budget)
    leaves the candidate as evidence(exact) at EVIDENCE_POINTS random exact points instead: (that certificate, why
    the proof stopped). A proof that failed otherwise keeps its error."""
    point = sample_point(system.kmap.ring.names, 3)
    try:
        verify_candidate(cert, system, names, candidate, point, symmetry)
        blocks = [(basis[:-1], basis[-1]) for basis in system.bases]
        rows = [relation_data(r.coefficients, r.rhs) for r in system.relations]
        cert.checks.append(prop_even_blocks_step(system.kmap.field, blocks, names, candidate, system.iterates, rows,
                                                 point))
    except ProofStopped as exc:
        cert.error = str(exc)
    except HKProofError as exc:
        cert.error = f"{type(exc).__name__}: {exc}"
    if cert.status >= Status.VERIFIED_SPECIALIZED or not cert.stopped_by_budget:
        return cert, ""
    stopped = f"the proof by Prop. \"prop: even\" was stopped: {cert.error}"
    evidence = evidence_at_points(system.kmap, names, candidate, rng, cert.fixed)
    evidence.notes.append(stopped)
    return evidence, stopped


EVIDENCE_POINTS = 2
"""Random exact points at which a candidate whose proof the budget stopped is checked (a(f(x)) = a(x))."""


def evidence_at_points(kmap: KahanMap, names: Sequence[str], candidate: Sequence[Frac], rng: random.Random,
                       fixed: Mapping[str, str]) -> Certificate:
    """Evidence(exact) for candidates whose proof was stopped: a(f(x)) = a(x) exactly at EVIDENCE_POINTS random
    rational points (x, eps and the parameters random); refuted if one differs. Not a proof."""
    cert = Certificate("bases (evidence)", "the kernel coordinates of the bases are constant along the map at random "
                       "exact points", 'sec. 3 (an integral: h o f = h), at points', "Evidence, not proof: each "
                       "coordinate takes the same exact value at x and at f(x) for random rational x, eps and "
                       "parameters.", fixed=dict(fixed))
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
