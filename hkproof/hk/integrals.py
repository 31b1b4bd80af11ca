"""Is a rational function an integral of a Kahan map? Exact check by substitution: h o f - h = 0 in Q(x, eps, params)."""
from __future__ import annotations

from dataclasses import dataclass

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.proof.status import Status


@dataclass
class IntegralVerdict:
    """Exact verdict: VERIFIED when h o f = h identically, REFUTED when the difference is non-zero."""

    status: Status
    ring: str
    method: str
    difference_terms: int

    def to_dict(self) -> dict:
        return {"verdict": self.status.label, "ring": self.ring, "method": self.method,
                "difference_terms": self.difference_terms}


def integral_difference(kmap: KahanMap, h: Frac) -> Frac:
    """h o f - h, exactly (h o f by one homogenized compose of numerator and denominator)."""
    return kmap.pullback(h) - h


def check_integral(kmap: KahanMap, h: Frac) -> IntegralVerdict:
    """Verified iff h(f(x)) = h(x) as rational functions; refuted otherwise (an exact statement either way)."""
    diff = integral_difference(kmap, h)
    ring = f"Q({', '.join(kmap.ring.names)})"
    if diff.is_zero():
        return IntegralVerdict(Status.VERIFIED, ring, "substitution h(N/Delta) - h", 0)
    return IntegralVerdict(Status.REFUTED, ring, "substitution h(N/Delta) - h", len(diff.num))


def lie_derivative(field: QuadraticField, h: Frac) -> Frac:
    """dh/dt along the continuous flow x' = F(x): sum_i dh/dx_i F_i."""
    ring = field.ring
    total = Frac(ring, 0)
    for v, f in zip(field.variables, field.rhs, strict=True):
        total = total + h.derivative(v) * f
    return total
