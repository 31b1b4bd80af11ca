"""Heights of exact orbits: an orbit over Q whose heights grow exponentially is stopped before its costly steps."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterable

import flint

from hkproof import budget
from hkproof.errors import ResourceLimitError

__all__ = ["MAX_ORBIT_BITS", "HeightGuard"]

MAX_ORBIT_BITS = 4_000_000      # an exact orbit is not computed past coordinates of about 1.2 million digits


@dataclass
class HeightGuard:
    """Watches the heights (bits of numerators and denominators) of an exact orbit of `steps` steps. The height of
    f^n(x) grows like deg(f^n): quadratically in n for an integrable Kahan map, like lambda^n otherwise. When the
    last three ratios of heights show exponential growth and the last point's height times that ratio to the
    remaining steps passes `max_bits`, the orbit is stopped before the costly steps (ResourceLimitError, with the
    growth seen); ratios that fall from step to step (polynomial growth) never stop it. The budget active in this
    thread is checked at every step.

    >>> g = HeightGuard(60, max_bits=10**4)
    >>> HeightGuard(60, max_bits=10**4).observe_bits(0, 4) is None   # one point says nothing
    True
    >>> for i, bits in enumerate([8, 20, 50, 120, 290]):
    ...     g.observe_bits(i, bits)
    Traceback (most recent call last):
    hkproof.errors.ResourceLimitError: the heights of the exact orbit grow exponentially (8, 20, 50, 120 bits: a factor of about 2.4 per step): step 60 would need about 5.6e+23 bits, more than 10000; no exact orbit of this length at these values
    """

    steps: int
    max_bits: int = MAX_ORBIT_BITS
    heights: list[int] = field(default_factory=list)

    def observe(self, i: int, point: Iterable[flint.fmpq]) -> None:
        """Record step i's point; stop if the orbit cannot finish within the bound."""
        self.observe_bits(i, max(max(q.p.bit_length(), q.q.bit_length()) for q in point))

    def observe_bits(self, i: int, bits: int) -> None:
        budget.check(f"step {i} of an exact orbit ({bits} bits)")
        self.heights.append(max(bits, 1))
        h = self.heights
        if len(h) < 4 or h[-1] < 64:
            return
        ratios = [h[-k] / h[-k - 1] for k in (3, 2, 1)]     # oldest first
        if min(ratios) < 1.8 or any(b < 0.9 * a for a, b in zip(ratios, ratios[1:])):
            return          # polynomial growth shows falling ratios (n^2: 4, 2.25, 1.78, ...)
        growth = min(ratios)
        predicted = h[-1] * growth ** (self.steps - i)
        if predicted > self.max_bits:
            seen = ", ".join(map(str, h[-5:]))
            raise ResourceLimitError(
                f"the heights of the exact orbit grow exponentially ({seen} bits: a factor of about {growth:.2g} per "
                f"step): step {self.steps} would need about {predicted:.2g} bits, more than {self.max_bits}; no exact "
                "orbit of this length at these values")
