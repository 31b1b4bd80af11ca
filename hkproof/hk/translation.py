"""A translation symmetry of the parameters (w -> w + c(1, ..., 1), other parameters moving along linearly): prove
a reduced HK system on the slice w_pivot = 0 and lift the result, so that every parameter stays symbolic with one
variable fewer in the work."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import flint

from hkproof.algebra.formula import tokens
from hkproof.algebra.fraction import Frac, normalize_sign
from hkproof.algebra.linalg import nullspace_q, primitive_vector
from hkproof.algebra.ring import Rational, Ring
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.reduced import Relation, check_solution, prove_by_evenness, verify_by_evenness
from hkproof.proof.certificate import Certificate, StepRecorder

__all__ = ["check_solution_on_slice", "field_translations", "lift_through", "ParameterTranslation", "prove_on_slice",
           "slice_decides", "verify_on_slice"]


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

    def field_is_invariant(self, field: QuadraticField) -> bool:
        """Every right-hand side is invariant (exact); then so is the Kahan map, built from them by Cramer's rule."""
        return all(self.is_invariant(f) for f in field.rhs)


def field_translations(field: QuadraticField) -> list[ParameterTranslation]:
    """Constant translations of the parameters leaving the field invariant, one per slice: the kernel of
    c -> sum_j c_j dF/da_j over Q (exact), a direction with an entry +-1 taken as a shift with that pivot, then the
    same on the slice a_pivot = 0, until no direction is left. A direction with no entry +-1 (after making it a
    primitive integer vector) is not used: the lift n -> n - c_n a_pivot would not have integer coefficients."""
    out: list[ParameterTranslation] = []
    while field.parameters:
        shift = _first_translation(field)
        if shift is None:
            break
        out.append(shift)
        field = field.specialize({shift.pivot: 0})
    return out


def _first_translation(field: QuadraticField) -> ParameterTranslation | None:
    """One direction of the kernel of c -> D_c F, as a shift whose pivot is the last parameter with entry +-1."""
    params = field.parameters
    rows: dict[tuple[int, tuple[int, ...]], list[flint.fmpq]] = {}
    for i, f in enumerate(field.rhs):
        for j, a in enumerate(params):
            d = f.derivative(a)
            for m, coefficient in (d.num * (f.den ** 2 / d.den)).to_dict().items():
                rows.setdefault((i, m), [flint.fmpq(0)] * len(params))[j] += coefficient
    for direction in nullspace_q(list(rows.values())) if rows else [[flint.fmpq(1)] * len(params)]:
        ints = [int(n) for n in primitive_vector(direction)]
        units = [j for j, c in enumerate(ints) if abs(c) == 1]
        if units:
            pivot = units[-1]
            ints = [c * ints[pivot] for c in ints]
            names = tuple(a for a, c in zip(params, ints, strict=True) if c == 1)
            velocity = tuple((a, str(c)) for a, c in zip(params, ints, strict=True) if c not in (0, 1))
            shift = ParameterTranslation(names, params[pivot], velocity)
            if shift.field_is_invariant(field):
                return shift
    return None


def lift_through(shifts: Sequence[ParameterTranslation], h: Frac, ring: Ring) -> Frac:
    """The invariant function of `ring` whose restriction to the slices of `shifts` (applied in order) is h."""
    rings = [ring]
    for shift in shifts[:-1]:
        rings.append(shift.slice_ring(rings[-1]))
    for shift, target in zip(reversed(shifts), reversed(rings), strict=True):
        h = shift.lift(h, target)
    return h


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
