"""A translation symmetry of the parameters (w -> w + c(1, ..., 1)): prove a reduced HK system on the slice
w_pivot = 0 and lift the result, so that every parameter stays symbolic with one variable fewer in the work."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac, normalize_sign
from hkproof.algebra.ring import Rational, Ring
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.reduced import Relation, check_solution, prove_by_evenness, verify_by_evenness
from hkproof.proof.certificate import Certificate, StepRecorder


@dataclass(frozen=True)
class ParameterTranslation:
    """The shift of the parameters `names` by one common c; `pivot` (one of them) is 0 on the slice.

    A rational function h is invariant iff sum_n dh/dn = 0 (over Q the infinitesimal invariance integrates).
    An invariant h is determined by its restriction h0 to the slice: h(w) = h0(w - w_pivot (1, ..., 1)).
    """

    names: tuple[str, ...]
    pivot: str

    def __post_init__(self) -> None:
        if self.pivot not in self.names:
            raise HKProofError(f"the pivot {self.pivot!r} is not one of the shifted parameters {self.names}")

    def is_invariant(self, h: Frac) -> bool:
        """sum_n dh/dw_n == 0 over the shifted parameters, exactly: D(num) den == num D(den), no gcd."""
        shifted = [n for n in self.names if n in h.ring.names]

        def d(p):
            return sum((p.derivative(n) for n in shifted), p - p)

        return d(h.num) * h.den == h.num * d(h.den)

    def slice_ring(self, ring: Ring) -> Ring:
        return ring.drop([self.pivot])

    def restrict(self, h: Frac) -> Frac:
        """h on the slice w_pivot = 0."""
        return h.specialize({self.pivot: 0}, self.slice_ring(h.ring))

    def lift(self, h0: Frac, ring: Ring) -> Frac:
        """The invariant function of `ring` whose restriction is h0: w_n -> w_n - w_pivot (an automorphism, so
        lowest terms are kept; the sign is normalized again, the last term having changed)."""
        pivot = ring.gen(self.pivot)
        args = [ring.gen(n) - pivot if n in self.names else ring.gen(n) for n in h0.ring.names]
        return Frac(ring, *normalize_sign(h0.num.compose(*args), h0.den.compose(*args)), reduced=True)

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
    if not _system_invariant(cert, kmap, shift, basis, target, relations, dict(zip(names, candidate))):
        return verify_by_evenness(cert, kmap, basis, target, names, candidate, point, iterates, relations)
    small, sbasis, starget, srelations = _restricted(kmap, shift, basis, target, relations)
    verify_by_evenness(cert, small, sbasis, starget, names, [shift.restrict(a) for a in candidate],
                       {k: v for k, v in point.items() if k != shift.pivot}, iterates, srelations)
    for n, a in zip(names, candidate):
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
    for n, a in zip(names, lifted):
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
    with cert.step(f"invariance of the system under ({', '.join(shift.names)}) -> (..) + c",
                   "sum of the partial derivatives in the shifted parameters is 0, exactly", kmap.ring) as s:
        return slice_decides(s, shift, parts)


def _parts(kmap: KahanMap, basis: Sequence[Frac], target: Frac, relations: Sequence[Relation],
           candidate: Mapping[object, Frac]) -> dict[str, Frac]:
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
