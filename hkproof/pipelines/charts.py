"""The affine chart `discover` searches in: the field in its normal form (hk.normal_form), the integrals pulled back.

Kahan's scheme is affinely equivariant (hk.affine_chart): if G(T x + c) = T F(x), an integral J of the Kahan map of
G pulls back to the integral J(T x + c) of the Kahan map of F. The search runs where the field is sparsest, and each
certificate gets the step that licenses the pull-back (the identity checked exactly again); the certificate file
carries it as an `affine-change` step that the checker verifies on its own.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.affine_chart import AffineChange, field_mismatches
from hkproof.hk.normal_form import field_size, normal_form
from hkproof.pipelines.carried import carry_integrals
from hkproof.pipelines.stages import Stages
from hkproof.proof.certificate import Certificate

if TYPE_CHECKING:
    from hkproof.pipelines.discover.report import DiscoveryReport

__all__ = ["Chart", "pull_back_integrals"]


@dataclass(frozen=True)
class Chart:
    """`searched` is `field` in the coordinates y = T x + c of `change` (same names)."""

    field: QuadraticField
    change: AffineChange
    searched: QuadraticField

    @classmethod
    def of(cls, field: QuadraticField) -> "Chart | None":
        """The normal form of the field, when it is sparser than the field as given (None: search as given)."""
        found = normal_form(field)
        return None if found is None else cls(field, *found)

    def pull_back(self, h: Frac) -> Frac:
        """J(T x + c) in the ring of the user's field."""
        return self.change.pull_back(self.field, h)

    def record(self, cert: Certificate, ring: Ring) -> None:
        """The step that licenses a pull-back in `cert`: G(T x + c) = T F(x), checked exactly again, det T != 0."""
        with cert.step("pulled back through an affine change", "Kahan's scheme is affinely equivariant: G(T x + c) "
                       "= T F(x) exactly (T, c constant, det T != 0), so g(T x + c) = T f(x) + c and each integral "
                       "J of g gives the integral J(T x + c) of f", ring) as s:
            self.change.inverse_images(self.field)           # det T != 0, or HKProofError
            bad = field_mismatches(self.field, self.searched, self.change)
            s.require(not bad, f"the field in the chart differs from T F at {', '.join(bad)}")
            s.note(self.describe())

    def describe(self) -> str:
        return (f"searched in the chart y = T x + c where the field is sparsest ({self.change.describe(self.field)}; "
                f"{field_size(self.field)} -> {field_size(self.searched)} characters of right-hand sides): each "
                "integral is pulled back and proven for the field as given")


def pull_back_integrals(report: "DiscoveryReport", chart: Chart, target: KahanMap, stages: Stages) -> None:
    """Replace each integral found in the chart by its pull-back J(T x + c); each certificate records the step that
    makes the pull-back an integral of the field as given (the identity G(T x + c) = T F(x) checked again)."""
    stages.start("pull back", "pulling the integrals back from the chart of the normal form")
    carry_integrals(report, lambda h: chart.pull_back(h).to_ring(target.ring),
                    lambda cert: chart.record(cert, target.ring), "in_chart",
                    "; found in the chart of the normal form, pulled back")
