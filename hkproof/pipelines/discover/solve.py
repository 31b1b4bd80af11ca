"""A minimal HK-basis proven whole: every kernel coordinate an integral, by Prop. "prop: even", with relations whose
right-hand sides are integrals proven before; the proof never expands h o f.

1. A plan mod p (hkproof.pipelines.discover.relation_plan): combinations l.c that are functions R of the proven
   integrals K (constant relations, recipe (E), among them), enough of them to make the rows i = 0, 1 square.
2. The plan with eps and the parameters symbolic (hkproof.pipelines.discover.symbolic): l, R, and R composed with K.
3. The coordinates by sparse reconstruction over prime fields (the same module).
4. The proof (hkproof.hk.reduced.verify_by_evenness): the system has a unique solution (its determinant at a rational
   point), the relations' coefficients and right-hand sides are even and integrals (rational functions of K), the
   candidate is even in eps and satisfies the rows i = 0, 1 (by Horner in the numerators of f) and every relation.
The certificate records each step; a basis whose plan falls short waits for more proven integrals.
"""
from __future__ import annotations

import random
import time
from dataclasses import dataclass, field
from typing import Mapping, Sequence

from hkproof import budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import lcm
from hkproof.algebra.modular import random_prime
from hkproof.algebra.monomials import Exponents, text
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import BudgetExhausted, HKProofError, ResourceLimitError
from hkproof.hk.independence import sample_point
from hkproof.hk.reduced import Relation, verify_by_evenness
from hkproof.hk.row_check import check_solution_by_rows
from hkproof.algebra.dense_reconstruction import ansatz_size
from hkproof.pipelines.discover.candidates import line_degrees
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.relation_plan import ModularPlan, plan_mod_p
from hkproof.pipelines.discover.sample_pool import SamplePool
from hkproof.pipelines.discover.symbolic import PRIME_BITS, SymbolicRelation, coordinates, lift_relations
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

__all__ = ["FIRST_ATTEMPT", "BasisProof", "Postponed", "prove_basis", "verify_candidate"]

FIRST_ATTEMPT = 20.0     # seconds of sparse reconstruction a normalization of a basis gets first (then 4x, 16x, ...)


@dataclass
class BasisProof:
    """The coordinates c_1..c_(l-1) (c_l = -1) of a basis, in the order `exponents` (the normalized function last),
    proven integrals when `certificate` says so."""

    basis: list[str]
    exponents: list[Exponents]
    coordinates: list[Frac]
    certificate: Certificate
    relations: list[SymbolicRelation] = field(default_factory=list)
    seconds: float = 0.0

    @property
    def status(self) -> Status:
        return self.certificate.status

    def coordinate(self, e: Exponents) -> Frac:
        """The coordinate of the basis function x^e (-1 for the normalized one)."""
        k = self.exponents.index(e)
        return self.coordinates[k] if k < len(self.coordinates) else Frac(self.coordinates[0].ring, -1)


@dataclass
class Postponed:
    """Why a basis cannot be proven with the integrals proven so far (it may be, once there are more)."""

    reason: str


def _names(basis: Sequence[str]) -> list[str]:
    return [f"c{k + 1}" for k in range(len(basis) - 1)]


def prove_basis(ctx: SearchContext, basis: Sequence[Exponents], known: Mapping[str, Frac],
                rng: random.Random) -> BasisProof | Postponed:
    """Prove every kernel coordinate of `basis` an integral (Prop. "prop: even" with relations l.c = R(K)), or say
    what is missing."""
    start = time.perf_counter()
    kmap = ctx.kmap
    even = {n: h for n, h in known.items() if h.is_even_in(EPS)}
    p = random_prime(rng, PRIME_BITS)
    controls = {n: rng.randrange(1, p) for n in kmap.field.control_names} | {n: 1 for n in ctx.weights.normalized}
    complete, best_rank = [], 0
    pool = SamplePool(kmap, even, p, controls, rng, len(basis) - 2)
    for last in range(len(basis)):           # the normalization: which function's coefficient is -1
        order = [e for k, e in enumerate(basis) if k != last] + [basis[last]]
        plan = plan_mod_p(kmap, order, even, p, controls, rng, pool=pool)
        best_rank = max(best_rank, plan.rank)
        if plan.complete:
            complete.append((last, order, plan))
    if not complete:
        return Postponed(f"the rows i = 0, 1 and the relations with the {len(even)} proven integrals have rank "
                         f"at most {best_rank} of {len(basis) - 1} (mod p, every normalization tried)")
    degrees = line_degrees(kmap, list(basis), ctx.weights, ctx.free, rng)
    nvars = len(ctx.free) + len(kmap.variables)

    def cost(last: int) -> int:                  # the size of the dense ansatzes of the coordinates (an estimate)
        sizes = [degrees[(k, last)] for k in range(len(basis)) if k != last]
        return sum(10**12 if d is None else ansatz_size(nvars, d) for d in sizes)
    ordered = [(order, plan) for last, order, plan in sorted(complete, key=lambda t: cost(t[0]))]
    try:
        order, _, coords = _race(ctx, ordered, rng)
    except BudgetExhausted:
        raise
    except ResourceLimitError as exc:
        return Postponed(f"the sparse reconstruction of every normalization exceeded a size limit ({exc})")
    basis, plan, candidate = _smallest(order, coords, ordered)
    texts = [text(kmap.variables, e) for e in basis]
    ctx.stages.say(f"({', '.join(texts)}): {len(plan.relations)} relations with proven integrals; lifting them")
    relations = lift_relations(ctx, basis, even, plan, rng)
    cert = Certificate(f"basis ({', '.join(texts)})", f"the kernel coordinates of ({', '.join(texts)}) are integrals",
                       'Prop. "prop: even"', f"The kernel of the HK-basis ({', '.join(texts)}) is one-dimensional "
                       "and its coordinates, normalized by the last one (-1), are integrals of the Kahan map.",
                       fixed={k: str(v) for k, v in ctx.fixed.items()})
    _cite(cert, kmap.ring, relations, even)
    try:
        verify_candidate(cert, kmap, texts, relations, candidate)
    except ProofStopped as exc:
        cert.error = str(exc)
    except HKProofError as exc:
        cert.error = f"{type(exc).__name__}: {exc}"
    return BasisProof(texts, list(basis), candidate, cert, relations, time.perf_counter() - start)


def verify_candidate(cert: Certificate, kmap: KahanMap, basis: Sequence[str], relations: Sequence[SymbolicRelation],
                     candidate: Sequence[Frac]) -> None:
    """Step 4: Prop. "prop: even" for candidate coordinates of `basis` (the last one normalized to -1) with the rows
    i = 0, 1 and `relations`, recorded in `cert` (ProofStopped when a step fails)."""
    fracs = [Frac.parse(kmap.ring, t) for t in basis]
    rows = [Relation(r.combination, r.rhs, source="a rational function of proven integrals (step 1)",
                     formula=r.formula, uses=r.knowns) for r in relations]
    verify_by_evenness(cert, kmap, fracs[:-1], fracs[-1], _names(basis), candidate, sample_point(kmap.ring.names, 2),
                       (0, 1), rows, check=check_solution_by_rows)


def _race(ctx: SearchContext, complete: list[tuple[list[Exponents], ModularPlan]], rng: random.Random
          ) -> tuple[list[Exponents], ModularPlan, list[Frac]]:
    """The coordinates in the first normalization whose sparse reconstruction finishes: the sizes of the coordinates
    differ by orders of magnitude from one normalization to another, and degrees along a line do not show it. Each
    normalization gets a share of time, which grows (times four) until one finishes or the budget runs out."""
    seconds, left = FIRST_ATTEMPT, list(complete)
    while True:
        for order, plan in list(left):
            attempt = ctx.budget.child(seconds)
            texts = ", ".join(text(ctx.kmap.variables, e) for e in order)
            ctx.stages.say(f"({texts}): sparse reconstruction of {len(order) - 1} coordinates (at most {seconds:g} s)")
            try:
                return order, plan, coordinates(ctx, order, rng, budget=attempt)
            except BudgetExhausted:
                budget.check("reconstructing the coordinates of a basis")     # the whole budget, or the next try
            except ResourceLimitError:          # a size limit (memory), not time: this normalization is out
                left.remove((order, plan))
                if not left:
                    raise
        seconds *= 4


def _smallest(order: list[Exponents], coords: list[Frac], complete: list[tuple[list[Exponents], ModularPlan]]
              ) -> tuple[list[Exponents], ModularPlan, list[Frac]]:
    """The complete normalization whose coordinates have the fewest terms over their common denominator (the proof
    substitutes them into the rows over it): the coordinates of one normalization give every other exactly,
    c'_k = -c_k / c_j."""
    value = dict(zip(order, [*coords, Frac(coords[0].ring, -1)], strict=True))
    best = None
    for basis, plan in complete:
        last = value[basis[-1]]
        if last.is_zero():
            continue
        moved = [-value[e] / last for e in basis[:-1]]
        common = lcm([c.den for c in moved])                # the rows are checked over it (hk.row_check)
        size = len(common) + sum(len(c.num * (common / c.den)) for c in moved)
        if best is None or size < best[0]:
            best = (size, basis, plan, moved)
    assert best is not None
    return best[1], best[2], best[3]


def _cite(cert: Certificate, ring, relations: Sequence[SymbolicRelation], known: Mapping[str, Frac]) -> None:
    """Step 1: the right-hand sides are rational functions R of integrals proven before (and of the relations before
    them), written out; each composition is exact."""
    with cert.step("right-hand sides are integrals", "rational functions of integrals proven earlier, composed "
                   "exactly (one homogenized compose each)", ring) as s:
        for k, rel in enumerate(relations, 1):
            s.note(f"relation {k}: rhs = {rel.formula} in {', '.join(rel.knowns) or 'constants'}")
        s.note(f"proven integrals used: {', '.join(sorted(known)) or 'none'}; _l<k> is the right-hand side of "
               "relation k + 1")
