"""`discover`, the exact half: certify reconstructed integrals, sort out trivial ones, prove independence.

The search (algorithm (N) on monomial bases, kernels, reconstruction) lives in hkproof.pipelines.discover;
everything it finds passes through here before it is called an integral: h o f = h by substitution
(`check_integral`, every remaining parameter symbolic) and functional independence by an exact Jacobian rank at
a rational point (a full rank at one point proves independence).
"""
from __future__ import annotations

from typing import Mapping, Sequence

import flint

from hkproof.algebra.sampling import random_point
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import SingularPointError, SingularSystemError
from hkproof.hk.independence import jacobian_rank_at
from hkproof.hk.integrals import check_integral
from hkproof.hk.linear_relations import relation_rank
from hkproof.hk.reduced import Relation, solve_reduced_system
from hkproof.hk.row_check import check_solution_by_rows
from hkproof.proof.status import Status

__all__ = ["certify", "independent_subset", "is_phase_constant", "jacobian_points", "solve_by_evenness"]


def certify(kmap: KahanMap, h: Frac, fixed: Mapping[str, Rational] | None = None) -> tuple[Status, str]:
    """Exact substitution h(N/Delta) - h = 0 in Q(x, eps, parameters): verified (or verified(specialized) when
    some parameters were fixed by the user), refuted otherwise."""
    verdict = check_integral(kmap, h.to_ring(kmap.ring))
    where = f"in {verdict.ring}" + (f" at {', '.join(f'{k}={v}' for k, v in fixed.items())}" if fixed else "")
    if verdict.status is not Status.VERIFIED:
        return Status.REFUTED, f"{verdict.method} is not zero {where} ({verdict.difference_terms} terms)"
    return (Status.VERIFIED_SPECIALIZED if fixed else Status.VERIFIED), f"{verdict.method} = 0 {where}"


def solve_by_evenness(kmap: KahanMap, basis: Sequence[Frac], relations: Sequence[Relation],
                      fixed: Mapping[str, Rational] | None = None) -> tuple[list[Frac] | None, Status, str]:
    """Recipe (E) with Prop. "prop: even" for a basis with a one-dimensional kernel (last coordinate -1): the rows
    i = 0, 1 and independent relations with eps-even constant coefficients, solved by Cramer's rule; a unique
    solution that is even in eps and satisfies every equation consists of integrals. (None, status, why) when the
    relations are too few or the hypotheses fail."""
    unknowns = len(basis) - 1
    chosen: list[Relation] = []
    for rel in relations:
        if len(chosen) == unknowns - 2:
            break
        if relation_rank(chosen + [rel]) > len(chosen):
            chosen.append(rel)
    if len(chosen) < unknowns - 2:
        return None, Status.UNKNOWN, (f"{len(chosen)} independent relations for {unknowns} unknowns: the rows "
                                      "i = 0, 1 cannot fix the rest")
    if not all(c.is_even_in(EPS) for rel in chosen for c in (*rel.coefficients, rel.rhs)):
        return None, Status.UNKNOWN, "a relation's coefficient is not even in eps: Prop. \"prop: even\" does not apply"
    try:
        solution = solve_reduced_system(kmap, basis[:-1], basis[-1], (0, 1), chosen)
    except SingularSystemError:
        return None, Status.UNKNOWN, "the rows i = 0, 1 and the relations are singular"
    if not all(c.is_even_in(EPS) for c in solution):
        return None, Status.UNKNOWN, "the solution is not even in eps: Prop. \"prop: even\" does not apply"
    if not check_solution_by_rows(kmap, basis[:-1], basis[-1], (0, 1), chosen, solution):
        return None, Status.REFUTED, "the solution fails a row or a relation"
    where = f" at {', '.join(f'{k}={v}' for k, v in fixed.items())}" if fixed else ""
    return solution, (Status.VERIFIED_SPECIALIZED if fixed else Status.VERIFIED), (
        f"recipe (E): rows i = 0, 1 and {len(chosen)} relation(s) found exactly, unique solution (Cramer), even in "
        f"eps, substituted back: integrals by Prop. \"prop: even\"{where}")


def is_phase_constant(h: Frac, variables: Sequence[str]) -> bool:
    """True when h involves no phase variable (a constant integral: trivial)."""
    return not (h.variables() & set(variables))


def independent_subset(functions: Sequence[Frac], variables: Sequence[str],
                       points: Sequence[Mapping[str, Rational]]) -> list[int]:
    """Indices of a maximal subset whose Jacobian has full rank at one of `points` (exact; proves independence)."""
    chosen: list[int] = []
    for i in range(len(functions)):
        trial = [functions[j] for j in chosen + [i]]
        for point in points:
            try:
                if jacobian_rank_at(trial, variables, point) == len(trial):
                    chosen.append(i)
                    break
            except SingularPointError:
                continue
    return chosen


def jacobian_points(names: Sequence[str], count: int = 3, seed: int = 11) -> list[dict[str, flint.fmpq]]:
    """A few reproducible rational points fixing every name (for exact Jacobian ranks)."""
    import random
    rng = random.Random(seed)
    return [random_point(rng, names, 97, denominator=89)
            for _ in range(count)]
