"""Is a rational function an integral of a Kahan map? Exact check by substitution: h o f - h = 0 in Q(x, eps, params)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational
from hkproof.budget import current
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ParseError
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

__all__ = ["check_integral", "integral_difference", "IntegralVerdict", "lie_derivative", "point_text",
           "shared_integrals"]

INLINE_WORK = 20_000     # terms of h times terms of f below which the check runs in this process (a fork costs ~10 ms)


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
    """Verified iff h(f(x)) = h(x) as rational functions; refuted otherwise (an exact statement either way).

    h o f = P/Q by one homogenized compose of numerator and denominator (not reduced), and P/Q = h iff
    P h.den = Q h.num: no gcd of the big P and Q (it was most of the time on a five-dimensional cubic field, and a
    gcd is one FLINT call that nothing interrupts). A large composition runs in a child of `Budget.call`, stopped at
    the deadline of the active budget (BudgetExhausted) and by SIGTERM at once.

    >>> from hkproof.dynamics.field import QuadraticField
    >>> rotation = KahanMap(QuadraticField("rotation", ("x", "y"), (), ("-y", "x")))
    >>> [check_integral(rotation, Frac.parse(rotation.ring, h)).status.label for h in ("x**2 + y**2", "x*y")]
    ['verified', 'refuted']
    """
    if h.ring != kmap.ring:
        raise ParseError(f"{h} is not in the ring {kmap.ring} of {kmap}")
    nums, delta = kmap.explicit
    work = (len(h.num) + len(h.den)) * (sum(len(n) for n in nums) + len(delta))
    if work <= INLINE_WORK:
        holds, terms = _difference_terms(kmap, h)
    else:
        holds, terms = current().call("checking h o f = h by substitution", _difference_terms, kmap, h)
    ring = f"Q({', '.join(kmap.ring.names)})"
    if holds:
        return IntegralVerdict(Status.VERIFIED, ring, "substitution h(N/Delta) - h", 0)
    return IntegralVerdict(Status.REFUTED, ring, "substitution h(N/Delta) - h", terms)


def _difference_terms(kmap: KahanMap, h: Frac) -> tuple[bool, int]:
    """(h o f == h, the number of terms of the numerator of h o f - h in lowest terms: 0 when equal)."""
    nums, delta = kmap.explicit
    p, q = h.pullback_terms(nums, delta, kmap.variables)
    if q.is_zero():
        raise ZeroDivisionError("denominator is the zero polynomial")     # h's denominator vanishes along f
    left, right = p * h.den, q * h.num
    if left == right:
        return True, 0
    return False, len(Frac(kmap.ring, left - right, q * h.den).num)


def lie_derivative(field: QuadraticField, h: Frac) -> Frac:
    """dh/dt along the continuous flow x' = F(x): sum_i dh/dx_i F_i."""
    ring = field.ring
    total = Frac(ring, 0)
    for v, f in zip(field.variables, field.rhs, strict=True):
        total = total + h.derivative(v) * f
    return total


def point_text(point: Mapping[str, Rational]) -> str:
    """'x1 = 1, x2 = 2/3, ...' for step methods and notes."""
    return ", ".join(f"{k} = {v}" for k, v in point.items())


def shared_integrals(cert: Certificate, integrals: Mapping[str, Frac], other: KahanMap, label: str,
                     witness: Mapping[str, Rational], witness_ring: str, symbolic_limit: int = 2000) -> list[str]:
    """The names of those `integrals` that are also integrals of `other` (sec. 7, Conclusions): refuted by one
    exact point where h(f(x)) != h(x), else proven by substitution; above `symbolic_limit` terms a function equal at
    the point is kept as exact evidence only."""
    moved = {**witness, **other.step_exact(witness)}
    shared = []
    with cert.step(f"{label}: values at x and at the other map's image of x",
                   f"exact evaluation over Q at {point_text(witness)}", witness_ring) as s:
        kept = [n for n, h in integrals.items() if h.evaluate(witness) == h.evaluate(moved)]
        refuted = [n for n in integrals if n not in kept]
        s.note(f"not integrals of the Kahan map of {other.field.name} (I(f(x)) != I(x) at the witness): "
               f"{', '.join(refuted) or 'none'}")
    for n in kept:
        h = integrals[n]
        with cert.step(f"{n} o f = {n} for the Kahan map of {other.field.name}", "substitution h(N/Delta) - h",
                       other.ring) as s:
            if len(h.num) + len(h.den) > symbolic_limit:
                s.evidence(Status.EVIDENCE_EXACT, 1)
                s.note(f"{n} has {len(h.num) + len(h.den)} terms: equal at the witness only")
                shared.append(n)
                continue
            if check_integral(other, h).status is Status.VERIFIED:
                shared.append(n)
            else:
                s.note(f"{n} o f != {n}")
    return shared
