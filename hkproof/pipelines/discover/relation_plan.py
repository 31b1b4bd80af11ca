"""Relations between the kernel coordinates of a basis and integrals already proven, found modulo a prime.

Prop. "prop: even" needs, besides the rows i = 0, 1, as many relations as the basis has coordinates minus two. Where
constant relations (recipe (E)) are too few, relations whose right-hand sides are proven integrals serve as well:
l.c = R(K), l constant, K proven integrals (and combinations l'.c expressed before, which are integrals too).

At fixed eps and parameters, modulo p:
- a combination l.c is a function of K exactly when its gradient lies in the span of theirs at every point,
  l^T Dc(x) v = 0 for every v with DK(x) v = 0; collected at a few points these conditions give the space L of such
  combinations (gradients of c by the orbit's tangent maps, eq. "Kahan gen" differentiated);
- the reduced echelon rows of L that raise the rank of the rows i = 0, 1 at a random point are chosen, single
  coordinates first;
- for each chosen row, R = N/D is found by the smallest degree-bounded ansatz (l.c) D(K') = N(K') that the sampled
  values admit, K' being K and the combinations chosen before.
The plan is evidence mod p; hkproof.pipelines.discover.symbolic lifts it to eps and the parameters, and the proof
checks every identity exactly.
"""
from __future__ import annotations

import random
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import flint

from hkproof import budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.modular import kernel_mod_p, polynomial_mod_p, rank_mod_p, rational_fit_mod_p
from hkproof.algebra.monomials import Exponents, exponents_upto, value_mod_p
from hkproof.dynamics.kahan import KahanMap
from hkproof.pipelines.discover.sample_pool import SamplePool, Samples

__all__ = ["DEGREES", "ModularPlan", "ModularRelation", "evaluate_plan", "plan_mod_p"]

DEGREES = ((0, 0), (1, 0), (0, 1), (1, 1), (2, 0), (2, 1), (1, 2), (2, 2))   # (deg N, deg D) tried, in this order


@dataclass
class ModularRelation:
    """l.c = N(K') / D(K') mod p: l a reduced echelon row (1 at `pivot`), N and D over the names `knowns`."""

    combination: list[int]
    pivot: int
    knowns: list[str]
    degrees: tuple[int, int]
    numerator: dict[Exponents, int]
    denominator: dict[Exponents, int]

    @property
    def lead(self) -> Exponents:
        """The monomial of D whose coefficient is 1 (the normalization of `_fit`: the first of D's monomials in the
        order of `exponents_upto`)."""
        return min(self.denominator, key=_order)

    @property
    def shape(self) -> tuple:
        """What must be the same at every eps and parameter value for the plan to be lifted symbolically."""
        return (self.pivot, tuple(k for k, c in enumerate(self.combination) if c), tuple(self.knowns),
                self.degrees, tuple(sorted(self.numerator)), tuple(sorted(self.denominator)))


@dataclass
class ModularPlan:
    """The relations chosen for one basis at one prime and one value of eps and the parameters, the rank they reach
    with the rows i = 0, 1 (`width` = the number of unknowns: enough when rank == width)."""

    p: int
    controls: dict[str, int]
    width: int
    rank: int = 0
    relations: list[ModularRelation] = field(default_factory=list)
    dimension: int = 0            # dim L: the combinations that are functions of the proven integrals

    @property
    def complete(self) -> bool:
        return self.rank == self.width

    @property
    def shape(self) -> tuple:
        return (self.rank, tuple(r.shape for r in self.relations))


def _dependent_space(samples: Samples, points: int) -> list[list[int]]:
    """A basis of L mod p in reduced echelon form (one row per pivot): the constant combinations l whose l.c is a
    function of the proven integrals (gradient conditions at `points` random points)."""
    p, n = samples.p, len(samples.kmap.variables)
    equations: list[list[int]] = []
    for _ in range(points):
        budget.check("collecting gradient conditions for the relations with proven integrals")
        x, orbit = samples.point()
        grads = samples.gradients(x, orbit)
        dk = samples.known_gradients(x) if samples.known else []
        if grads is None or dk is None:
            continue
        directions = kernel_mod_p(dk, p) if dk else [[int(i == j) for j in range(n)] for i in range(n)]
        for v in directions:
            equations.append([sum(g[j] * v[j] for j in range(n)) % p for g in grads])
    basis = kernel_mod_p(equations, p)
    if not basis:
        return []
    r, rank = flint.nmod_mat(basis, p).rref()
    return [[int(r[i, j]) for j in range(r.ncols())] for i in range(rank)]


def _rows_01(samples: Samples) -> list[list[int]]:
    """The rows i = 0, 1 of the reduced system at a random point: (phi_1..phi_(l-1))(f^i x)."""
    _, orbit = samples.point()
    return [[value_mod_p(e, orbit.points[i], samples.p) for e in samples.basis[:-1]] for i in (0, 1)]


def _pivot(row: Sequence[int]) -> int:
    return next(k for k, c in enumerate(row) if c)


def _order(e: Exponents) -> tuple:
    """The position of a monomial in the order of `exponents_upto` (higher total degree first, then the first
    exponent descending)."""
    return (-sum(e), tuple(-k for k in e))


def _choose(rows01: list[list[int]], space: list[list[int]], p: int, width: int) -> list[list[int]]:
    """Rows of L that raise the rank of the rows i = 0, 1, single coordinates first, then by pivot."""
    chosen: list[list[int]] = []
    rank = rank_mod_p(rows01, p)
    for row in sorted(space, key=lambda r: (sum(1 for c in r if c), _pivot(r))):
        if rank == width:
            break
        budget.check("choosing the relations with proven integrals")
        if rank_mod_p(rows01 + chosen + [row], p) > rank:
            chosen.append(row)
            rank += 1
    return chosen


@dataclass
class _Point:
    """One sample: the coordinates c and the proven integrals k (mod p); the gradients dc, dk only at the first
    sample (where the independent subsets of the knowns are read off)."""

    c: list[int]
    k: list[int]
    dc: list[list[int]] = field(default_factory=list)
    dk: list[list[int]] = field(default_factory=list)


def _data(samples: Samples, count: int) -> list[_Point]:
    out: list[_Point] = []
    while len(out) < count:
        budget.check("sampling kernel coordinates and proven integrals mod p")
        x, orbit = samples.point()
        c, k = samples.coordinates(x, orbit), samples.known_values(x)
        if c is None or k is None:
            continue
        if out:
            out.append(_Point(c, list(k.values())))
            continue
        dc, dk = samples.gradients(x, orbit), samples.known_gradients(x)
        if dc is not None and dk is not None:
            out.append(_Point(c, list(k.values()), dc, dk))
    return out


def _combine(row: Sequence[int], vectors: Sequence[Sequence[int]], p: int) -> list[int]:
    """row . vectors (a combination of the coordinates' values or gradients)."""
    return [sum(a * v[j] for a, v in zip(row, vectors, strict=True)) % p for j in range(len(vectors[0]))]


def _independent_subsets(gradients: list[list[int]], p: int) -> list[tuple[int, ...]]:
    """Subsets of the knowns with independent gradients (a rank mod p at one point), smallest first."""
    import itertools
    out = []
    for size in range(1, len(gradients) + 1):
        for subset in itertools.combinations(range(len(gradients)), size):
            budget.check("finding independent subsets of the proven integrals")
            if rank_mod_p([gradients[i] for i in subset], p) == size:
                out.append(subset)
    return out


def _subsets_for(gradients: list[list[int]], target: list[int], p: int) -> list[tuple[int, ...]]:
    """The subsets of the knowns a function R with d(l.c) = dR(K') may depend on. When the knowns' gradients are
    independent at the point, d(l.c) has one expression through them and R depends on exactly the knowns that enter
    it (and a reduced N/D over more knowns has no lower degrees): one subset, or none when d(l.c) is outside their
    span. Otherwise every independent subset, smallest first."""
    if rank_mod_p(gradients, p) < len(gradients):
        return _independent_subsets(gradients, p)
    columns = [list(col) for col in zip(*gradients, target, strict=True)]
    kernel = [v for v in kernel_mod_p(columns, p) if v[-1] % p]
    if not kernel:
        return []
    return [tuple(j for j, c in enumerate(kernel[0][:-1]) if c % p)]


def _express(samples: Samples, rows: list[list[int]], names: list[str], max_degree: int,
             extra: int = 6) -> list[ModularRelation] | None:
    """R for each chosen row in turn, over functionally independent knowns (the proven integrals and the
    combinations expressed before: K'), the smallest degrees first; None if a row has no R within the bound."""
    p = samples.p
    width = len(names) + len(rows)
    needed = 2 * max(len(exponents_upto(width, d)) for d in range(max_degree + 1)) + extra
    data = _data(samples, needed)
    out: list[ModularRelation] = []
    for i, row in enumerate(rows):
        budget.check("expressing a combination of kernel coordinates through proven integrals")
        knowns = list(names) + [f"_l{j}" for j in range(i)]
        values = [pt.k + [_combine(prev, [[v] for v in pt.c], p)[0] for prev in rows[:i]] for pt in data]
        first = data[0]
        grads = first.dk + [_combine(prev, first.dc, p) for prev in rows[:i]]
        ys = [_combine(row, [[v] for v in pt.c], p)[0] for pt in data]
        found = None
        subsets = _subsets_for(grads, _combine(row, first.dc, p), p) if knowns else [()]
        trials = sorted(((len(exponents_upto(len(sub), dn)) + len(exponents_upto(len(sub), dd)), sub, (dn, dd))
                         for sub in subsets for dn, dd in DEGREES if max(dn, dd) <= max_degree),
                        key=lambda t: t[0])
        for _, subset, degrees in trials:
            budget.check("fitting a right-hand side through proven integrals")
            ks = [[v[j] for j in subset] for v in values]
            fit = rational_fit_mod_p(ys[:-extra], ks[:-extra], degrees, p)
            if fit is not None and _holds(fit, ys[-extra:], ks[-extra:], p):
                found = ModularRelation(row, _pivot(row), [knowns[j] for j in subset], degrees, *fit)
                break
        if found is None:
            return None
        out.append(found)
    return out


def _holds(fit: tuple[dict[Exponents, int], dict[Exponents, int]], ys: Sequence[int], ks: Sequence[Sequence[int]],
           p: int) -> bool:
    num, den = fit
    return all((y * polynomial_mod_p(den, k, p) - polynomial_mod_p(num, k, p)) % p == 0
               for y, k in zip(ys, ks, strict=True))


def plan_mod_p(kmap: KahanMap, basis: Sequence[Exponents], known: Mapping[str, Frac], p: int,
               controls: Mapping[str, int], rng: random.Random, *, max_degree: int = 2,
               gradient_points: int | None = None, pool: SamplePool | None = None) -> ModularPlan:
    """The relations l.c = R(K') that make the reduced system of `basis` square, found mod p at the given residues
    of eps and the parameters (the plan says how far it got: rank < width when the proven integrals do not
    suffice). The normalizations of one basis share a `pool` of points (the same p, residues and integrals)."""
    samples = Samples(basis, pool or SamplePool(kmap, known, p, controls, rng, len(basis) - 2))
    width = len(basis) - 1
    space = _dependent_space(samples, gradient_points or width + 4)
    rows01 = _rows_01(samples)
    chosen = _choose(rows01, space, p, width)
    plan = ModularPlan(p, dict(controls), width, rank_mod_p(rows01 + chosen, p), dimension=len(space))
    if not plan.complete:
        return plan
    relations = _express(samples, chosen, list(known), max_degree)
    if relations is None:
        plan.rank = rank_mod_p(rows01, p)
        return plan
    plan.relations = relations
    return plan


def evaluate_plan(kmap: KahanMap, basis: Sequence[Exponents], known: Mapping[str, Frac], plan: ModularPlan, p: int,
                  controls: Mapping[str, int], rng: random.Random) -> list[ModularRelation] | None:
    """The relations of `plan` (its supports, knowns and degrees) at other residues of eps and the parameters and
    another prime: the combinations (only those of several coordinates need the gradients) and the functions R.
    None when the shape differs there (a special value or an unlucky prime)."""
    samples = Samples(basis, SamplePool(kmap, known, p, controls, rng, len(basis) - 2))
    space: list[list[int]] | None = None
    rows = []
    for rel in plan.relations:
        budget.check("evaluating the relations of a plan mod p")
        support = [k for k, c in enumerate(rel.combination) if c]
        if len(support) == 1:
            rows.append(rel.combination)
            continue
        if space is None:
            space = _dependent_space(samples, plan.width + 4)
        row = next((r for r in space if _pivot(r) == rel.pivot), None)
        if row is None or [k for k, c in enumerate(row) if c] != support:
            return None
        rows.append(row)
    names = list(known)
    unknowns = max(len(exponents_upto(len(r.knowns), d)) for r in plan.relations for d in r.degrees) * 2
    extra = 4
    data: list[tuple[list[int], dict[str, int]]] = []
    while len(data) < unknowns + extra:
        budget.check("sampling kernel coordinates and proven integrals mod p")
        x, orbit = samples.point()
        c, k = samples.coordinates(x, orbit), samples.known_values(x)
        if c is not None and k is not None:
            data.append((c, k))
    out: list[ModularRelation] = []
    for i, (rel, row) in enumerate(zip(plan.relations, rows, strict=True)):
        budget.check("fitting the relations of a plan mod p")
        columns = {n: [k[n] for _, k in data] for n in names}
        for j, prev in enumerate(rows[:i]):
            columns[f"_l{j}"] = [sum(a * b for a, b in zip(prev, c, strict=True)) % p for c, _ in data]
        ks = [[columns[n][t] for n in rel.knowns] for t in range(len(data))]
        ys = [sum(a * b for a, b in zip(row, c, strict=True)) % p for c, _ in data]
        fit = rational_fit_mod_p(ys[:-extra], ks[:-extra], rel.degrees, p)
        if fit is None or not _holds(fit, ys[-extra:], ks[-extra:], p):
            return None
        found = ModularRelation(row, rel.pivot, rel.knowns, rel.degrees, *fit)
        if found.shape != rel.shape:
            return None
        out.append(found)
    return out
