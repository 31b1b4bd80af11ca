"""The slice of a parameter translation: `discover` and `measure` search where a_pivot = 0 and lift what they find.

If the field is invariant under a translation of its parameters (hkproof.hk.translation.field_translations, exact),
so is its Kahan map, and an integral h0 of the map on the slice a_pivot = 0 lifts to the invariant function h with
h = h0 on the slice: h o f - h is invariant and vanishes on the slice, so it vanishes (the same for P o f = K P with
P and K lifted). The kernel coordinates on the slice have one parameter fewer (so(4) in m_ij: coordinates in eps,
a2, a3 instead of eps, a2, a3, a4).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.translation import ParameterTranslation, field_translations, lift_through
from hkproof.pipelines.carried import carry_integrals
from hkproof.pipelines.stages import Stages
from hkproof.proof.certificate import Certificate

if TYPE_CHECKING:
    from hkproof.pipelines.discover.report import DiscoveryReport

__all__ = ["lift_integrals", "Slice"]


@dataclass(frozen=True)
class Slice:
    """`searched` is `field` with the pivots of `shifts` set to 0, one after the other."""

    field: QuadraticField
    searched: QuadraticField
    shifts: tuple[ParameterTranslation, ...]

    @classmethod
    def of(cls, field: QuadraticField) -> "Slice":
        """The field's translations (none: the slice is the field itself)."""
        shifts = field_translations(field)
        searched = field
        for shift in shifts:
            searched = searched.specialize({shift.pivot: 0})
        return cls(field, searched, tuple(shifts))

    def lift(self, h: Frac, ring: Ring) -> Frac:
        """The invariant function of `ring` (the whole map's) equal to h on the slice."""
        return lift_through(self.shifts, h, ring)

    def images(self, ring: Ring) -> dict[str, Frac]:
        """Each parameter of the slice as the polynomial in the whole field's parameters its lift substitutes."""
        small = self.searched.ring
        return {b: self.lift(Frac(small, small.gen(b)), ring) for b in self.searched.parameters}

    def lift_poly(self, p: flint.fmpz_mpoly, ring: Ring) -> flint.fmpz_mpoly:
        """A polynomial of the slice's ring lifted to `ring` (the substitution a_j -> a_j - c_j a_pivot)."""
        return self.lift(Frac(self.searched.ring, p), ring).num

    def record_lift(self, cert: Certificate, ring: Ring) -> None:
        """The step that licenses a lift in `cert`: the field's invariance under each translation, checked again."""
        with cert.step("lifted from the slice", "the field is invariant under each translation (its derivative along "
                       "the shift is 0, exact): so is the Kahan map, and an identity of invariant functions that holds "
                       "on the slice holds everywhere", ring) as s:
            field = self.field
            for shift in self.shifts:
                s.require(shift.field_is_invariant(field), f"{field.name} is not invariant under {shift}")
                field = field.specialize({shift.pivot: 0})
            s.note(self.describe())

    def pivots(self) -> str:
        return ", ".join(f"{s.pivot} = 0" for s in self.shifts)

    def describe(self) -> str:
        return (f"searched on the slice {self.pivots()}: the field is invariant under {'; '.join(map(str, self.shifts))} "
                "(exact), so what is found there is lifted to every parameter symbolic")


def lift_integrals(report: DiscoveryReport, where: Slice, target: KahanMap, stages: Stages) -> None:
    """Replace each integral found on the slice by its lift; each certificate records the invariance of the field
    that makes the lift an integral (checked exactly again)."""
    stages.start("lift", "lifting the integrals from the slice along the parameter translations")
    carry_integrals(report, lambda h: where.lift(h, target.ring), lambda cert: where.record_lift(cert, target.ring),
                    "searched",
                    f"; on the slice {where.pivots()}, lifted along the parameter translation")
