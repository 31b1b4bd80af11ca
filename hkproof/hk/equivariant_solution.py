"""A reduced system's unique solution built, not guessed (Prop. "prop: even", check 4 without substitution): one
component per orbit by Cramer's rule, the others its images under a symmetry sigma of the system.

sigma is a signed permutation of the phase variables and parameters fixing eps (`hk.symmetries`) with
sigma o f = f o sigma, sigma(phi_k) = phi_pi(k) for the basis, sigma(phi_l) = phi_l for the target, and each
relation carried to itself with its coefficients permuted by pi. Applying the field automorphism sigma to
sum_k A_ik a_k = b_i (A_ik = phi_k o f^i) gives sum_k A_i,pi(k) sigma(a_k) = b_i, so (sigma(a_k) at pi(k)) solves
the system too; when the solution is unique, a_pi(k) = sigma(a_k). Every piece of this is checked exactly on the
system, and costs compositions of the small basis functions, not of the big solution with the iterates.
"""
from __future__ import annotations

from typing import Sequence

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import cramer
from hkproof.algebra.ring import Rational
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.reduced import Relation, hk_row, linear_combination_equals, verify_by_evenness
from hkproof.hk.symmetries import SignedPermutation
from hkproof.proof.certificate import Certificate

__all__ = ["prove_by_symmetry", "system_permutation"]


def system_permutation(kmap: KahanMap, basis: Sequence[Frac], target: Frac, relations: Sequence[Relation],
                       sigma: SignedPermutation) -> tuple[int, ...] | None:
    """pi with sigma(phi_k) = phi_pi(k), if sigma is a symmetry of the reduced system (sigma o f = f o sigma, the
    target and every relation carried to themselves, coefficients permuted by pi); None otherwise (exact)."""
    if not sigma.commutes(kmap) or sigma.apply(target) != target:
        return None
    images = [sigma.apply(phi) for phi in basis]
    perm = tuple(next((j for j, psi in enumerate(basis) if psi == image), -1) for image in images)
    if -1 in perm or len(set(perm)) != len(perm):
        return None
    for rel in relations:
        if sigma.apply(rel.rhs) != rel.rhs or any(sigma.apply(c) != rel.coefficients[perm[k]]
                                                  for k, c in enumerate(rel.coefficients)):
            return None
    return perm


def prove_by_symmetry(cert: Certificate, kmap: KahanMap, basis: Sequence[Frac], target: Frac, names: Sequence[str],
                      sigma: SignedPermutation, point: dict[str, Rational], iterates: Sequence[int] = (0, 1),
                      relations: Sequence[Relation] = ()) -> list[Frac]:
    """Prop. "prop: even" for the solution of rows `iterates` plus `relations`: Cramer's rule for the first unknown
    of each orbit of sigma's permutation, sigma's images for the rest; then uniqueness, hypotheses and evenness as in
    `hk.reduced.verify_by_evenness`, with check 4 (the solution satisfies the system) by this construction (row i = 0
    and the relations also by substitution, which is cheap)."""
    ring = kmap.ring
    with cert.step("the system's symmetry", f"{sigma}: sigma o f = f o sigma (exact, on the map's numerators), "
                   "basis permuted, target and relations carried to themselves", ring) as s:
        perm = system_permutation(kmap, basis, target, relations, sigma)
        s.require(perm is not None, f"{sigma} is not a symmetry of the system (of the map, the basis, the target or "
                  "a relation)")
        assert perm is not None
        s.note("basis: " + ", ".join(f"{names[k]} -> {names[j]}" for k, j in enumerate(perm)))
    leaders = _orbit_leaders(perm)
    with cert.step("the solution built: Cramer's rule on each orbit's first unknown, sigma's images for the others",
                   f"Cramer's rule (fraction-free) for {', '.join(names[k] for k in leaders)}; a_pi(k) = "
                   "sigma(a_k) by the symmetry", ring) as s:
        rows, rhs = zip(*(hk_row(kmap, basis, target, i) for i in iterates), strict=True)
        built, _ = cramer([*rows, *(rel.coefficients for rel in relations)], [*rhs, *(rel.rhs for rel in relations)],
                          columns=leaders)
        solution: list[Frac | None] = [None] * len(basis)
        for k, value in zip(leaders, built, strict=True):
            while solution[k] is None:
                solution[k] = value
                k, value = perm[k], sigma.apply(value)
        s.note("a component of the unique solution is its Cramer quotient (the determinant is not identically 0, "
               "next step); the images follow from the symmetry, so the big rows with iterates are never expanded")
    complete = [a for a in solution if a is not None]
    verify_by_evenness(cert, kmap, basis, target, names, complete, point, iterates, relations,
                       check=_BuiltSolution(complete), check_method="by construction: Cramer's rule and the system's "
                       "symmetry (steps above); row i = 0 and the relations also by substitution")
    return complete


def _orbit_leaders(perm: Sequence[int]) -> list[int]:
    """The smallest index of each cycle of a permutation."""
    seen: set[int] = set()
    leaders = []
    for k in range(len(perm)):
        if k not in seen:
            leaders.append(k)
            while k not in seen:
                seen.add(k)
                k = perm[k]
    return leaders


class _BuiltSolution:
    """Check 4 for a solution this module built: holds for that solution only, with row i = 0 and the relations
    substituted back as a cross-check (rows with iterates hold by the construction)."""

    def __init__(self, solution: Sequence[Frac]):
        self.solution = solution

    def __call__(self, kmap: KahanMap, basis: Sequence[Frac], target: Frac, iterates: Sequence[int],
                 relations: Sequence[Relation], solution: Sequence[Frac]) -> bool:
        if list(solution) != list(self.solution):
            raise HKProofError("a built solution's check was handed another solution")
        cheap = [linear_combination_equals(basis, solution, target)] if 0 in iterates else []
        return all(cheap) and all(linear_combination_equals(rel.coefficients, solution, rel.rhs)
                                  for rel in relations)
