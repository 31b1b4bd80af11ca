"""Substituting a solution back into a row with an iterate, (sum a_k phi_k) o f^i = phi_l o f^i, by a Horner
scheme in the numerators of f^i: the big solution is multiplied only by the small numerators N_j, one at a time,
never by the big rows phi_k o f^i (Prop. "prop: even", check 4, for polynomial basis functions); or, where a cost
model says it is cheaper, the same identity with eps and one parameter set to 1 by the weighted homogeneity and
the other parameters on a unisolvent lattice (`algebra.lattice_identity`): never expanded in the parameters."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.lattice_identity import horner, plan_lattice, vanishes_on_lattice
from hkproof.algebra.linalg import lcm
from hkproof.algebra.monomials import Exponents
from hkproof.algebra.ring import cores, flint_threads
from hkproof.budget import current
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.reduced import Relation, hk_row, linear_combination_equals

__all__ = ["check_solution_by_rows", "row_holds", "RowCheck", "Route"]

Route = Literal["auto", "horner", "lattice"]


@dataclass(frozen=True)
class RowCheck:
    """Whether a row holds, and how that was decided (for the certificate); true in a boolean context iff it holds."""

    holds: bool
    route: str

    def __bool__(self) -> bool:
        return self.holds


def row_holds(kmap: KahanMap, basis: Sequence[Frac], target: Frac, i: int, solution: Sequence[Frac],
              route: Route = "auto") -> RowCheck:
    """sum a_k(x) phi_k(f^i(x)) == phi_l(f^i(x)) exactly, for basis functions and target polynomial in x.

    With f^i = N / Delta and D the largest degree, the row times Delta^D is sum_mu C_mu(x) N^mu Delta^(D - |mu|),
    C_mu(x) = sum_k a_k(x) [x^mu] phi_k - [x^mu] phi_l (the a_k stay at x, only phi moves); it is evaluated by
    Horner's scheme in (N, Delta) over the common denominator of the C_mu, and compared with 0 -- expanded in
    every variable, or (route "lattice", or "auto" when the cost model prefers it) at the points of a unisolvent
    lattice in the parameters. Row i = 0, and a row of basis functions that are not polynomial in x, is the plain
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
    factors = [*nums, delta]
    parameters = tuple(kmap.field.parameters)
    if route != "horner" and parameters:
        plan = plan_lattice(terms, factors, ring.names, (EPS, *parameters), parameters)
        if route == "lattice" or plan.cheaper:
            with flint_threads():
                holds, bad = vanishes_on_lattice(terms, factors, plan, jobs=cores())
            return RowCheck(holds, f"row i = {i}: {plan.describe()}" + (f"; not zero at {bad}" if bad else ""))
    holds = current().call(f"checking row i = {i} by Horner's scheme", _vanishes, terms, factors)
    return RowCheck(holds, f"row i = {i} by Horner's scheme in the numerators of f^{i}, expanded")


def check_solution_by_rows(kmap: KahanMap, basis: Sequence[Frac], target: Frac, iterates: Sequence[int],
                           relations: Sequence[Relation], solution: Sequence[Frac]) -> bool:
    """`hk.reduced.check_solution` with the rows checked by `row_holds` (the relations by substitution)."""
    if not all(row_holds(kmap, basis, target, i, solution) for i in iterates):
        return False
    return all(linear_combination_equals(rel.coefficients, solution, rel.rhs) for rel in relations)


def _x_coefficients(kmap: KahanMap, phi: Frac) -> dict[Exponents, Frac]:
    """phi = sum_mu c_mu x^mu with c_mu free of x (phi must be polynomial in x)."""
    ring, idx = kmap.ring, [kmap.ring.index(v) for v in kmap.variables]
    if phi.den_variables_in(kmap.variables):
        raise ValueError(f"{phi} is not polynomial in {kmap.variables}: no row check by monomials")
    parts: dict[Exponents, dict] = {}
    for m, c in phi.num.to_dict().items():
        mu = tuple(m[k] for k in idx)
        rest = list(m)
        for k in idx:
            rest[k] = 0
        parts.setdefault(mu, {})[tuple(rest)] = c
    return {mu: Frac(ring, ring.ctx.from_dict(d), phi.den) for mu, d in parts.items()}


def _vanishes(terms: dict[Exponents, flint.fmpz_mpoly], factors: Sequence[flint.fmpz_mpoly]) -> bool:
    """Whether sum_mu terms[mu] prod_j factors[j]^mu_j is zero (FLINT's threads on the big products)."""
    with flint_threads():
        return horner(terms, factors).is_zero()
