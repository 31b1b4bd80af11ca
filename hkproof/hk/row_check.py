"""Substituting a solution back into a row with an iterate, (sum a_k phi_k) o f^i = phi_l o f^i, by a Horner
scheme in the numerators of f^i: the big solution is multiplied only by the small numerators N_j, one at a time,
never by the big rows phi_k o f^i (Prop. "prop: even", check 4, for polynomial basis functions); or, where a cost
model says it is cheaper, the same identity with eps and one parameter set to 1 by the weighted homogeneity and
the other parameters on a unisolvent lattice (`algebra.lattice_identity`): never expanded in the parameters; or
expanded modulo word-size primes whose product exceeds twice a proven bound on its coefficients
(`algebra.modular_identity`). All three routes are exact; the route is named in the result (and the certificate)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.lattice_identity import horner, horner_work, plan_lattice, vanishes_on_lattice
from hkproof.algebra.modular_identity import plan_modular, vanishes_modulo
from hkproof.algebra.linalg import lcm
from hkproof.algebra.monomials import Exponents
from hkproof.algebra.ring import cores, flint_threads
from hkproof.budget import current, parallel_parts, spread_slots
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.reduced import OverCommonDenominator, Relation, hk_row, linear_combination_equals

__all__ = ["check_solution_by_rows", "decide_identity", "phase_coefficients", "row_holds", "RouteCosts", "RowCheck",
           "Route"]

Route = Literal["auto", "horner", "lattice", "modular"]
# measured by benchmarks/routes.py on so(4) and Clebsch rows (docs/performance-frontier.md), against one expansion
# over Z with one-word coefficients on every core
ONE_PRIME_WEIGHT = 1.05  # one expansion modulo a lone prime, in this process on every core
MODULAR_WEIGHT = 2.0     # one round of expansions modulo primes, one prime per one-thread child
WORD_WEIGHT = 0.25       # the expansion over Z: each further 64 bits of the coefficient bound adds this much
LIMB_BITS = 62           # FLINT keeps an integer below 2^62 in one word


@dataclass(frozen=True)
class RowCheck:
    """Whether a row holds, and how that was decided (for the certificate); true in a boolean context iff it holds.
    `by` names the route: "substitution", "horner" (expanded over Z), "lattice" or "modular"."""

    holds: bool
    route: str
    by: str = "substitution"

    def __bool__(self) -> bool:
        return self.holds


def row_holds(kmap: KahanMap, basis: Sequence[Frac], target: Frac, i: int, solution: Sequence[Frac],
              route: Route = "auto") -> RowCheck:
    """sum a_k(x) phi_k(f^i(x)) == phi_l(f^i(x)) exactly, for basis functions and target polynomial in x.

    With f^i = N / Delta and D the largest degree, the row times Delta^D is sum_mu C_mu(x) N^mu Delta^(D - |mu|),
    C_mu(x) = sum_k a_k(x) [x^mu] phi_k - [x^mu] phi_l (the a_k stay at x, only phi moves); it is evaluated by
    Horner's scheme in (N, Delta) over the common denominator of the C_mu, and compared with 0 by one of three exact
    routes: expanded in every variable ("horner"), at the points of a unisolvent lattice in the parameters
    ("lattice"), or expanded modulo primes beyond twice a proven coefficient bound ("modular"); "auto" takes the
    cheapest by `RouteCosts`. Row i = 0, and a row of basis functions that are not polynomial in x, is the plain
    substitution.
    """
    if i == 0:
        return RowCheck(linear_combination_equals(basis, solution, target), "row i = 0 by substitution")
    if any(phi.den_variables_in(kmap.variables) for phi in (*basis, target)):
        row, rhs = hk_row(kmap, basis, target, i)
        return RowCheck(linear_combination_equals(row, solution, rhs), f"row i = {i} by substitution")
    ring = kmap.ring
    coefficients: dict[Exponents, Frac] = {}
    for a, phi in [*zip(solution, basis, strict=True), (Frac(ring, -1), target)]:
        for mu, c in _x_coefficients(kmap, phi).items():
            coefficients[mu] = coefficients.get(mu, Frac(ring, 0)) + a * c
    coefficients = {mu: c for mu, c in coefficients.items() if not c.is_zero()}
    if not coefficients:
        return RowCheck(True, f"row i = {i}: every coefficient cancels")
    nums, delta = kmap.iterate(i) if abs(i) > 1 else (kmap.explicit if i > 0 else kmap.inverse_explicit)
    top = max(sum(mu) for mu in coefficients)
    common = lcm([c.den for c in coefficients.values()])
    terms = {(*mu, top - sum(mu)): c.num * (common / c.den) for mu, c in coefficients.items()}
    return decide_identity(terms, [*nums, delta], ring.names, (EPS, *kmap.field.parameters), route,
                           f"row i = {i}", f"the numerators of f^{i}")


def decide_identity(terms: dict[Exponents, flint.fmpz_mpoly], factors: Sequence[flint.fmpz_mpoly],
                    names: Sequence[str], free: Sequence[str], route: Route, what: str, where: str) -> RowCheck:
    """sum_mu terms[mu] prod_j factors[j]^mu_j == 0 in Z[names] by `route` ("auto": the cheapest by `RouteCosts`);
    `free` are the names the gradings may set to 1, and the lattice is on those after the first (the parameters)."""
    costs = RouteCosts(terms, factors, names, free) if route == "auto" else None
    chosen = costs.cheapest if costs else route
    if chosen == "lattice":
        plan = costs.lattice if costs and costs.lattice else plan_lattice(terms, factors, names, free, tuple(free[1:]))
        with flint_threads():
            holds, bad = vanishes_on_lattice(terms, factors, plan, jobs=parallel_parts(cores()))
        return RowCheck(holds, f"{what}: {plan.describe()}" + (f"; not zero at {bad}" if bad else ""), "lattice")
    if chosen == "modular":
        modular = costs.modular if costs else plan_modular(terms, factors, 0, spread_slots() or cores())
        holds, prime = vanishes_modulo(terms, factors, modular.primes, jobs=parallel_parts(cores()))
        return RowCheck(holds, f"{what} by Horner's scheme in {where}, modulo primes: {modular.describe()}" +
                        (f"; not zero modulo {prime}" if prime else ""), "modular")
    holds = current().call(f"checking {what} by Horner's scheme", _vanishes, terms, factors)
    return RowCheck(holds, f"{what} by Horner's scheme in {where}, expanded", "horner")


class RouteCosts:
    """The cost model of the three routes: term products of Horner's scheme (`lattice_identity.horner_work`), over Z
    times 1 + WORD_WEIGHT per further word of the coefficient bound, at the lattice points likewise (parameters only,
    the names of `free` after the first), and modulo primes times ONE_PRIME_WEIGHT for a lone prime, else the
    primes each of `jobs` children takes times MODULAR_WEIGHT (so on two cores the expansion over Z stays cheaper;
    with many cores and large coefficients the primes win). `jobs` defaults to the slots of the active spread
    (`budget.spread_on`) or the cores; the expansion runs on this machine's cores only, so a spread with more slots
    than cores divides the lattice's estimate by slots / cores (its points are independent tasks)."""

    def __init__(self, terms: dict[Exponents, flint.fmpz_mpoly], factors: Sequence[flint.fmpz_mpoly],
                 names: Sequence[str], free: Sequence[str], jobs: int | None = None):
        plain = horner_work(terms, factors)
        local = cores()
        jobs = jobs or spread_slots() or local
        self.modular = plan_modular(terms, factors, plain, jobs)
        words = 1 + WORD_WEIGHT * max(0, self.modular.bound.bit_length() - LIMB_BITS) / 64
        self.lattice = plan_lattice(terms, factors, names, free, tuple(free[1:])) if free[1:] else None
        weight = ONE_PRIME_WEIGHT if len(self.modular.primes) <= 1 else MODULAR_WEIGHT
        self.costs: dict[Route, float] = {"horner": plain * words, "modular": self.modular.work * weight}
        if self.lattice is not None:
            self.costs["lattice"] = self.lattice.work * words * local / max(local, jobs)

    @property
    def cheapest(self) -> Route:
        return min(self.costs, key=lambda r: self.costs[r])


def check_solution_by_rows(kmap: KahanMap, basis: Sequence[Frac], target: Frac, iterates: Sequence[int],
                           relations: Sequence[Relation], solution: Sequence[Frac]) -> bool:
    """`hk.reduced.check_solution` with the rows checked by `row_holds` (the relations by substitution)."""
    if not all(row_holds(kmap, basis, target, i, solution) for i in iterates):
        return False
    common = OverCommonDenominator.of(solution)
    return all(linear_combination_equals(rel.coefficients, solution, rel.rhs, common) for rel in relations)


def _x_coefficients(kmap: KahanMap, phi: Frac) -> dict[Exponents, Frac]:
    """phi = sum_mu c_mu x^mu with c_mu free of x (phi must be polynomial in x)."""
    if phi.den_variables_in(kmap.variables):
        raise ValueError(f"{phi} is not polynomial in {kmap.variables}: no row check by monomials")
    return {mu: Frac(kmap.ring, c, phi.den) for mu, c in phase_coefficients(kmap, phi.num).items()}


def phase_coefficients(kmap: KahanMap, p: flint.fmpz_mpoly) -> dict[Exponents, flint.fmpz_mpoly]:
    """p = sum_mu c_mu x^mu with c_mu in Z[eps, params] (x the phase variables)."""
    ring, idx = kmap.ring, [kmap.ring.index(v) for v in kmap.variables]
    parts: dict[Exponents, dict] = {}
    for m, c in p.to_dict().items():
        mu = tuple(int(m[k]) for k in idx)
        rest = list(m)
        for k in idx:
            rest[k] = 0
        parts.setdefault(mu, {})[tuple(rest)] = c
    return {mu: ring.ctx.from_dict(d) for mu, d in parts.items()}


def _vanishes(terms: dict[Exponents, flint.fmpz_mpoly], factors: Sequence[flint.fmpz_mpoly]) -> bool:
    """Whether sum_mu terms[mu] prod_j factors[j]^mu_j is zero (FLINT's threads on the big products)."""
    with flint_threads():
        return horner(terms, factors).is_zero()
