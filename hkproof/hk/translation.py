"""A translation symmetry of the parameters (w -> w + c(1, ..., 1), other parameters moving along linearly): prove
a reduced HK system on the slice w_pivot = 0 and lift the result, so that every parameter stays symbolic with one
variable fewer in the work."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import flint

from hkproof.algebra.formula import tokens
from hkproof.algebra.fraction import Frac, normalize_sign
from hkproof.algebra.ring import Rational, Ring
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.reduced import Relation, check_solution, prove_by_evenness, verify_by_evenness
from hkproof.proof.certificate import Certificate, StepRecorder

__all__ = ["check_solution_on_slice", "ParameterTranslation", "prove_on_slice", "slice_decides", "verify_on_slice"]


@dataclass(frozen=True)
class ParameterTranslation:
    """The shift of the parameters `names` by one common c; `pivot` (one of them) is 0 on the slice.

    `velocity` lets other parameters move along, linearly in c: {"y": "-z"} shifts y by -z c (z must not move).
    The shift is the flow of the derivation D = sum_n d/dn + sum_v velocity_v d/dv. A rational function h is
    invariant iff D h = 0 (over Q the infinitesimal invariance integrates), and an invariant h is determined by
    its restriction h0 to the slice: h = h0(n - w_pivot for n in names, v - velocity_v w_pivot).
    """

    names: tuple[str, ...]
    pivot: str
    velocity: tuple[tuple[str, str], ...] = ()

    def __post_init__(self) -> None:
        if self.pivot not in self.names:
            raise HKProofError(f"the pivot {self.pivot!r} is not one of the shifted parameters {self.names}")
        moving = set(self.names) | {v for v, _ in self.velocity}
        for v, text in self.velocity:
            if {t.text for t in tokens(text) if t.kind == "name"} & moving:
                raise HKProofError(f"the velocity {text!r} of {v} involves a moving parameter: the shift would "
                                   "not be linear in c")

    def __str__(self) -> str:
        moves = "".join(f", {v} -> {v} + ({text}) c" for v, text in self.velocity)
        return f"({', '.join(self.names)}) -> (..) + c{moves}"

    def _velocities(self, ring: Ring) -> list[tuple[str, flint.fmpz_mpoly]]:
        """(name, velocity polynomial) for the moving names of `ring`."""
        out = [(n, ring.constant(1)) for n in self.names if n in ring.names]
        for v, text in self.velocity:
            if v in ring.names:
                value = Frac.parse(ring, text)
                if not value.den.is_one():
                    raise HKProofError(f"the velocity {text!r} of {v} must be a polynomial with integer coefficients")
                out.append((v, value.num))
        return out

    def is_invariant(self, h: Frac) -> bool:
        """D h == 0 exactly: D(num) den == num D(den), no gcd."""
        moving = self._velocities(h.ring)

        def d(p):
            return sum((v * p.derivative(n) for n, v in moving), p - p)

        return d(h.num) * h.den == h.num * d(h.den)

    def slice_ring(self, ring: Ring) -> Ring:
        return ring.drop([self.pivot])

    def restrict(self, h: Frac) -> Frac:
        """h on the slice w_pivot = 0."""
        return h.specialize({self.pivot: 0}, self.slice_ring(h.ring))

    def lift(self, h0: Frac, ring: Ring) -> Frac:
        """The invariant function of `ring` whose restriction is h0: n -> n - velocity_n w_pivot (an automorphism,
        so lowest terms are kept; the sign is normalized again, the last term having changed)."""
        pivot = ring.gen(self.pivot)
        moves = {n: ring.gen(n) - v * pivot for n, v in self._velocities(ring) if n in h0.ring.names}
        num, den = (h0.ring.substitute(p, moves, ring) for p in (h0.num, h0.den))
        return Frac(ring, *normalize_sign(num, den), reduced=True)

    def restrict_relation(self, rel: Relation) -> Relation:
        return Relation([self.restrict(c) for c in rel.coefficients], self.restrict(rel.rhs), rel.source)

    def slice_map(self, kmap: KahanMap) -> KahanMap:
        """The Kahan map of the field with w_pivot = 0."""
        return kahan_map(kmap.field.specialize({self.pivot: 0}))


def verify_on_slice(cert: Certificate, kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac],
                    target: Frac, names: Sequence[str], candidate: Sequence[Frac], point: Mapping[str, Rational],
                    iterates: Sequence[int] = (0, 1), relations: Sequence[Relation] = ()) -> list[Frac]:
    """Prop. "prop: even" for a candidate, checked on the slice w_pivot = 0 of a translation-invariant system.

    If f, the basis, the target, the relations and the candidate are invariant, the residual of every equation
    is invariant, and so is the system's determinant: both vanish identically iff they vanish on the slice.
    Parity in eps is untouched by the shift. So `verify_by_evenness` on the slice proves the full statement;
    if something is not invariant, the checks run in the full ring.
    """
    if not _system_invariant(cert, kmap, shift, basis, target, relations, dict(zip(names, candidate, strict=True))):
        return verify_by_evenness(cert, kmap, basis, target, names, candidate, point, iterates, relations)
    small, sbasis, starget, srelations = _restricted(kmap, shift, basis, target, relations)
    verify_by_evenness(cert, small, sbasis, starget, names, [shift.restrict(a) for a in candidate],
                       {k: v for k, v in point.items() if k != shift.pivot}, iterates, srelations)
    for n, a in zip(names, candidate, strict=True):
        cert.formula(n, a)
    return list(candidate)


def prove_on_slice(cert: Certificate, kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac],
                   target: Frac, names: Sequence[str], iterates: Sequence[int] = (0, 1),
                   relations: Sequence[Relation] = ()) -> list[Frac]:
    """Prop. "prop: even" / recipe (D) on the slice w_pivot = 0 of a translation-invariant system, lifted.

    The system being invariant, so is its unique solution: it is the lift of the slice's solution, and every
    check of `prove_by_evenness` made on the slice holds for all parameters (else it runs in the full ring).
    """
    if not _system_invariant(cert, kmap, shift, basis, target, relations, {}):
        return prove_by_evenness(cert, kmap, basis, target, names, iterates, relations)
    small, sbasis, starget, srelations = _restricted(kmap, shift, basis, target, relations)
    solution = prove_by_evenness(cert, small, sbasis, starget, names, iterates, srelations)
    lifted = [shift.lift(a, kmap.ring) for a in solution]
    for n, a in zip(names, lifted, strict=True):
        cert.formula(n, a)
    return lifted


def check_solution_on_slice(kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac], target: Frac,
                            iterates: Sequence[int], relations: Sequence[Relation], solution: Sequence[Frac]) -> bool:
    """`check_solution` (substitution into the rows `iterates` and the relations), on the slice when f, the basis,
    the target, the relations and the solution are invariant, else in the full ring."""
    parts = _parts(kmap, basis, target, relations, dict(enumerate(solution)))
    if not all(shift.is_invariant(h) for h in parts.values()):
        return check_solution(kmap, basis, target, iterates, relations, solution)
    small, sbasis, starget, srelations = _restricted(kmap, shift, basis, target, relations)
    return check_solution(small, sbasis, starget, iterates, srelations, [shift.restrict(a) for a in solution])


def _restricted(kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac], target: Frac,
                relations: Sequence[Relation]) -> tuple[KahanMap, list[Frac], Frac, list[Relation]]:
    return (shift.slice_map(kmap), [shift.restrict(b) for b in basis], shift.restrict(target),
            [shift.restrict_relation(rel) for rel in relations])


def _system_invariant(cert: Certificate, kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac],
                      target: Frac, relations: Sequence[Relation], candidate: Mapping[str, Frac]) -> bool:
    """The step that licenses working on the slice: is everything the system is made of invariant?"""
    parts = _parts(kmap, basis, target, relations, candidate)
    with cert.step(f"invariance of the system under {shift}",
                   "the derivative along the shift is 0, exactly", kmap.ring) as s:
        return slice_decides(s, shift, parts)


def _parts(kmap: KahanMap, basis: Sequence[Frac], target: Frac, relations: Sequence[Relation],
           candidate: Mapping[str, Frac] | Mapping[int, Frac]) -> dict[str, Frac]:
    """Everything a reduced system (and a candidate solution) is made of, by name."""
    parts: dict[str, Frac] = {f"component {i + 1} of f": c for i, c in enumerate(kmap.components())}
    parts.update({f"basis function {k + 1}": b for k, b in enumerate(basis)})
    parts["the target"] = target
    for k, rel in enumerate(relations):
        parts.update({f"relation {k + 1}, coefficient {j + 1}": c for j, c in enumerate(rel.coefficients)})
        parts[f"relation {k + 1}, right-hand side"] = rel.rhs
    parts.update({f"candidate {n}": a for n, a in candidate.items()})
    return parts


def slice_decides(s: StepRecorder, shift: ParameterTranslation, parts: Mapping[str, Frac]) -> bool:
    """True if every part is invariant (then an identity among them holds iff it holds on the slice); otherwise
    say which part is not, so that the caller checks in the full ring."""
    for what, h in parts.items():
        if not shift.is_invariant(h):
            s.note(f"{what} is not invariant under the shift: the checks below run in the full ring")
            return False
    s.note(f"every residual and determinant built from them is invariant: checking it at {shift.pivot} = 0 "
           f"proves it for all {', '.join(shift.names)}")
    return True
