"""Reduced HK systems (recipes B, D, E) and the Proposition "prop: even" argument that makes them proofs."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac, Parity
from hkproof.algebra.linalg import cramer, lcm, nullspace_q
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, ShapeError
from hkproof.hk.independence import sample_point
from hkproof.proof.certificate import Certificate
from hkproof.proof.export import prop_even_step, relation_data

__all__ = ["block_rows_at", "check_solution", "det_at_point", "even_components", "hk_row", "kernel_coordinates",
           "linear_combination_equals", "orbit_points", "OverCommonDenominator", "prop_even_hypotheses",
           "prove_by_evenness", "Relation", "SolutionCheck", "solve_reduced_system", "system_at", "verify_by_evenness"]

SolutionCheck = Callable[..., bool]
SUBSTITUTION = "substitution back into every equation"


@dataclass
class Relation:
    """A linear relation sum coefficients[k] * a_k = rhs among the unknowns (recipe E).

    `source` names what makes rhs an integral: 'constant', or the id of the claim that proved it; `formula` is rhs
    as text over the integrals named in `uses` (for a certificate file), when rhs depends on the phase variables.
    """

    coefficients: Sequence[Frac]
    rhs: Frac
    source: str = "constant"
    formula: str = ""
    uses: Sequence[str] = ()


def hk_row(kmap: KahanMap, basis: Sequence[Frac], target: Frac, i: int) -> tuple[list[Frac], Frac]:
    """Row i of eq. "smaller system": (phi_1, ..., phi_k) o f^i and the right-hand side phi_l o f^i."""
    return [kmap.pullback(phi, i) for phi in basis], kmap.pullback(target, i)


def solve_reduced_system(kmap: KahanMap, basis: Sequence[Frac], target: Frac, iterates: Sequence[int],
                         relations: Sequence[Relation] = ()) -> list[Frac]:
    """The unique solution a of (sum a_k phi_k) o f^i = phi_l o f^i (i in iterates) plus the relations."""
    rows, rhs = [], []
    for i in iterates:
        r, b = hk_row(kmap, basis, target, i)
        rows.append(r)
        rhs.append(b)
    for rel in relations:
        rows.append(list(rel.coefficients))
        rhs.append(rel.rhs)
    if len(rows) != len(basis):
        raise HKProofError(f"{len(rows)} equations for {len(basis)} unknowns: the reduced system must be square")
    solution, _ = cramer(rows, rhs)
    return solution


def check_solution(kmap: KahanMap, basis: Sequence[Frac], target: Frac, iterates: Sequence[int],
                   relations: Sequence[Relation], solution: Sequence[Frac]) -> bool:
    """Substitute the solution back into every equation of the system (exactly)."""
    common = OverCommonDenominator.of(solution)        # the solution over one denominator for every equation
    for i in iterates:
        r, b = hk_row(kmap, basis, target, i)
        if not linear_combination_equals(r, solution, b, common):
            return False
    return all(linear_combination_equals(rel.coefficients, solution, rel.rhs, common) for rel in relations)


@dataclass(frozen=True)
class OverCommonDenominator:
    """Values written once over a common multiple of their denominators (`multiple`, and each value's numerator
    times multiple / its denominator), for a caller that checks many combinations of the same values: the lcm and
    the scaled numerators of a candidate's 18 components cost seconds when each relation recomputes them. Build it
    with `of` (the fields must be consistent: nothing checks them again)."""

    multiple: flint.fmpz_mpoly
    numerators: tuple[flint.fmpz_mpoly, ...]

    @classmethod
    def of(cls, values: Sequence[Frac]) -> OverCommonDenominator:
        multiple = lcm([v.den for v in values])
        return cls(multiple, tuple(v.num * (multiple / v.den) for v in values))


def linear_combination_equals(coefficients: Sequence[Frac], values: Sequence[Frac], rhs: Frac,
                              common: OverCommonDenominator | None = None) -> bool:
    """sum c_k v_k == rhs exactly: one common denominator lcm(c dens) lcm(v dens), no gcd of big numerators.
    `common`: the values already over one denominator (`OverCommonDenominator.of(values)`)."""
    lc = lcm([c.den for c in coefficients])
    over = common if common is not None else OverCommonDenominator.of(values)
    if len(over.numerators) != len(values):
        raise ShapeError(f"{len(values)} values but {len(over.numerators)} numerators over their common denominator")
    both = lc * over.multiple
    g = rhs.den.gcd(both)
    extra = rhs.den / g
    total = -rhs.num * (both / g)
    for c, v, scaled_v in zip(coefficients, values, over.numerators, strict=True):
        if c.is_zero() or v.is_zero():
            continue
        scaled_c = c.num * (lc / c.den)                    # each over its common denominator, then one big product
        if len(scaled_c) <= len(scaled_v):
            total += (scaled_c * extra) * scaled_v
        else:
            total += scaled_c * (scaled_v * extra)
    return total.is_zero()


def prop_even_hypotheses(cert: Certificate, kmap: KahanMap, iterates: Sequence[int],
                         relations: Sequence[Relation]) -> None:
    """Check (2) of Prop. "prop: even": rows from a non-symmetric range of iterates containing 0; relation
    coefficients and right-hand sides even in eps, and integrals (constants, or proven by the cited source)."""
    with cert.step("hypotheses of Prop. \"prop: even\"", "structure of the system", kmap.ring) as s:
        s.require(_non_symmetric_range(iterates),
                  f"iterates {list(iterates)} are not a non-symmetric consecutive range containing 0")
        for k, rel in enumerate(relations):
            for c in rel.coefficients:
                s.require(c.is_even_in(EPS), f"relation {k + 1} has a coefficient {c} that is not even in eps")
            s.require(rel.rhs.is_even_in(EPS), f"relation {k + 1} has a right-hand side that is not even in eps")
            if rel.source == "constant":
                for part in (*rel.coefficients, rel.rhs):
                    s.require(not (part.variables() & set(kmap.variables)),
                              f"relation {k + 1}: {part} depends on phase variables "
                              "but no proof that it is an integral is cited")
            else:
                s.note(f"relation {k + 1}: coefficients and right-hand side are integrals by {rel.source}")
        s.note(f"rows from iterates {list(iterates)}: non-symmetric, contain 0")


def even_components(cert: Certificate, names: Sequence[str], solution: Sequence[Frac]) -> None:
    """Check (3) of Prop. "prop: even": every component even in eps (exact parity in lowest terms)."""
    ring = solution[0].ring
    with cert.step("solution is even in eps", "exact parity of each component in lowest terms", ring) as s:
        for n, a in zip(names, solution, strict=True):
            par = a.parity(EPS)
            s.require(par is Parity.EVEN, lambda: f"{n} is {par.value} in eps, not even: {a}")
        s.note(f"{', '.join(names)} even in eps")


def _prop_even_checks(cert: Certificate, kmap: KahanMap, basis: Sequence[Frac], target: Frac, names: Sequence[str],
                      iterates: Sequence[int], relations: Sequence[Relation], solution: Sequence[Frac],
                      check: SolutionCheck | None = None, check_method: str = SUBSTITUTION) -> None:
    """Checks (2)-(4) of Prop. "prop: even": hypotheses on the rows, evenness, substitution back (or `check`)."""
    prop_even_hypotheses(cert, kmap, iterates, relations)
    even_components(cert, names, solution)
    with cert.step("solution satisfies the system", check_method, kmap.ring) as s:
        s.require((check or check_solution)(kmap, basis, target, iterates, relations, solution),
                  "the computed solution does not satisfy the system")


def verify_by_evenness(cert: Certificate, kmap: KahanMap, basis: Sequence[Frac], target: Frac,
                       names: Sequence[str], candidate: Sequence[Frac], point: Mapping[str, Rational],
                       iterates: Sequence[int] = (0, 1), relations: Sequence[Relation] = (),
                       check: SolutionCheck | None = None, check_method: str = SUBSTITUTION) -> list[Frac]:
    """Prop. "prop: even" for a candidate solution found by any means (e.g. one Cramer component and symmetry).

    Uniqueness is proven by a non-zero value of the system's determinant at one rational point (so the
    determinant is not identically 0); then the same checks as `prove_by_evenness`, including substitution,
    make the candidate the unique solution and its components integrals (`check_method` says how `check` decides).
    """
    ring = kmap.ring
    with cert.step("reduced system: unique solution (det not identically 0)",
                   f"exact det of the system at a rational point; rows i in {list(iterates)} + "
                   f"{len(relations)} relation(s)", ring) as s:
        value = det_at_point(kmap, basis, iterates, relations, point)
        s.require(value != 0, f"the determinant vanishes at {dict(point)}: choose another point")
        s.note(f"det = {value} != 0 at the point, so the system has at most one solution")
        for n, a in zip(names, candidate, strict=True):
            cert.formula(n, a)
    _prop_even_checks(cert, kmap, basis, target, names, iterates, relations, candidate, check, check_method)
    _record(cert, kmap, basis, target, names, candidate, iterates, relations, point)
    return list(candidate)


def _record(cert: Certificate, kmap: KahanMap, basis: Sequence[Frac], target: Frac, names: Sequence[str],
            solution: Sequence[Frac], iterates: Sequence[int], relations: Sequence[Relation],
            point: Mapping[str, Rational] | None = None) -> None:
    """The data of a checked Prop. "prop: even" argument, for a certificate file (proof.export); without a point,
    the first sample point where the determinant is not 0."""
    if point is None:
        point = next((q for q in (sample_point(kmap.ring.names, seed) for seed in range(1, 9))
                      if _det_or_zero(kmap, basis, iterates, relations, q) != 0), None)
        if point is None:
            return
    rows = [relation_data(r.coefficients, r.formula or r.rhs, r.uses) for r in relations]
    step = prop_even_step(kmap.field, basis, target, names, solution, iterates, rows, point)
    phase = set(kmap.variables)
    cited = [r.source for r in relations
             if not r.formula and any(q.variables() & phase for q in (*r.coefficients, r.rhs))]
    if cited:
        step["cites"] = cited       # integrals proven by other claims, not written in the file's integrals
    cert.checks.append(step)


def _det_or_zero(kmap: KahanMap, basis: Sequence[Frac], iterates: Sequence[int], relations: Sequence[Relation],
                 point: Mapping[str, Rational]) -> flint.fmpq:
    """det_at_point, 0 where the point is a pole (of the map or of a basis function)."""
    try:
        return det_at_point(kmap, basis, iterates, relations, point)
    except (HKProofError, ZeroDivisionError):
        return flint.fmpq(0)


def det_at_point(kmap: KahanMap, basis: Sequence[Frac], iterates: Sequence[int], relations: Sequence[Relation],
                 point: Mapping[str, Rational]) -> flint.fmpq:
    """The determinant of a square reduced system (rows i in iterates, then the relations) at an exact point."""
    orbit = orbit_points(kmap, point, iterates)
    rows = [[phi.evaluate(orbit[i]) for phi in basis] for i in iterates]
    rows += [[c.evaluate(point) for c in rel.coefficients] for rel in relations]
    if len(rows) != len(basis):
        raise HKProofError(f"{len(rows)} equations for {len(basis)} unknowns: the reduced system must be square")
    return flint.fmpq_mat(rows).det()


def kernel_coordinates(kmap: KahanMap, bases: Sequence[Sequence[Frac]], point: Mapping[str, Rational],
                       last: int = 6) -> list[flint.fmpq] | None:
    """Recipe (B) at one exact point: ker X_[0,last] of each basis with its last coordinate -1, the others
    concatenated (sec. 6.7's alpha, beta, gamma); None if a kernel is not 1-dimensional or ends in 0."""
    orbit = kmap.orbit_exact(point, last)
    out: list[flint.fmpq] = []
    for basis in bases:
        kernel = nullspace_q([[phi.evaluate({**point, **y}) for phi in basis] for y in orbit])
        if len(kernel) != 1 or kernel[0][-1] == 0:
            return None
        out += [c / -kernel[0][-1] for c in kernel[0][:-1]]
    return out


def block_rows_at(bases: Sequence[Sequence[Frac]], points: Sequence[Mapping[str, Rational]]
                  ) -> tuple[list[list[flint.fmpq]], list[flint.fmpq]]:
    """The rows sum_k a_k phi_k(y) = phi_last(y) of several bases at exact points y, each basis with its own block
    of unknowns (sec. 6.7, eqs. "Psi1 iterates" ... "Psi3 iterates"): (rows, right-hand sides), basis by basis."""
    width = sum(len(basis) - 1 for basis in bases)
    rows, rhs = [], []
    start = 0
    for basis in bases:
        for y in points:
            row = [flint.fmpq(0)] * width
            for k, phi in enumerate(basis[:-1]):
                row[start + k] = phi.evaluate(y)
            rows.append(row)
            rhs.append(basis[-1].evaluate(y))
        start += len(basis) - 1
    return rows, rhs


def orbit_points(kmap: KahanMap, point: Mapping[str, Rational], iterates: Sequence[int]) -> dict[int, dict]:
    """The exact points f^i(x), i in iterates, with the parameters of `point` (f^-1(x, eps) = f(x, -eps))."""
    fixed = {k: v for k, v in point.items() if k not in kmap.variables}
    forward = kmap.orbit_exact(point, max(max(iterates), 0))
    backward = kmap.orbit_exact({**point, EPS: -to_fmpq(point[EPS])}, max(-min(iterates), 0))
    return {i: {**fixed, **(forward[i] if i >= 0 else backward[-i])} for i in iterates}


def system_at(kmap: KahanMap, bases: Sequence[Sequence[Frac]], iterates: Sequence[int],
              relations: Sequence[Relation], point: Mapping[str, Rational]
              ) -> tuple[list[list[flint.fmpq]], list[flint.fmpq]]:
    """A reduced system at one exact point: the rows i in `iterates` of every basis (`block_rows_at`) and the
    relations' rows (rows, right-hand sides). A rank here is a lower bound for the generic rank."""
    orbit = orbit_points(kmap, point, iterates)
    rows, rhs = block_rows_at(bases, [orbit[i] for i in iterates])
    rows += [[c.evaluate(point) for c in rel.coefficients] for rel in relations]
    rhs += [rel.rhs.evaluate(point) for rel in relations]
    return rows, rhs


def _non_symmetric_range(iterates: Sequence[int]) -> bool:
    it = sorted(iterates)
    consecutive = it == list(range(it[0], it[-1] + 1))
    return consecutive and it[0] <= 0 <= it[-1] and it[0] != -it[-1]


def prove_by_evenness(cert: Certificate, kmap: KahanMap, basis: Sequence[Frac], target: Frac,
                      names: Sequence[str], iterates: Sequence[int] = (0, 1),
                      relations: Sequence[Relation] = (), check: SolutionCheck | None = None) -> list[Frac]:
    """Prop. "prop: even" / recipe (D): solve, and check everything that makes the solution integrals.

    Steps recorded: (1) unique solution (det not identically 0); (2) the rows come from a non-symmetric
    range of iterates containing 0, relation coefficients are even in eps and their right-hand sides are
    even integrals proven earlier; (3) every component is even in eps; (4) the solution satisfies the system.
    Returns the solution (named `names` in the certificate's formulas). `check` replaces `check_solution` for
    step (4) (e.g. `hk.row_check.check_solution_by_rows`, the same substitution organized for big solutions).
    """
    ring = kmap.ring
    with cert.step("reduced system: unique solution by Cramer's rule",
                   f"recipe (B)/(E): rows i in {list(iterates)} + {len(relations)} relation(s); fraction-free det",
                   ring) as s:
        solution = solve_reduced_system(kmap, basis, target, iterates, relations)
        s.note("det of the system is not identically zero")
        for n, a in zip(names, solution, strict=True):
            cert.formula(n, a)
    _prop_even_checks(cert, kmap, basis, target, names, iterates, relations, solution, check)
    _record(cert, kmap, basis, target, names, solution, iterates, relations)
    return solution
