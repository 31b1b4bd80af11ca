"""Exact orbits of a Kahan map over Q (KahanMap.orbit_exact) and the detection of periodic orbits."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import flint

from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.heights import HeightGuard
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import SingularPointError

__all__ = ["digits", "exact_orbit", "ExactOrbit"]

@dataclass
class ExactOrbit:
    """x_0, ..., x_steps over Q; `period` k > 0 when x_(s + k) = x_s for the first repeated point x_s."""

    variables: tuple[str, ...]
    values: dict[str, flint.fmpq]
    points: list[dict[str, flint.fmpq]]
    period: int | None = None
    preperiod: int | None = None
    stopped: str = ""

    @property
    def closes(self) -> bool:
        """The orbit returns exactly to its initial point (f^period(x_0) = x_0)."""
        return self.period is not None and self.preperiod == 0

    def height(self, index: int) -> int:
        """About the largest number of decimal digits of a numerator or denominator of x_index."""
        return digits(self.points[index])


def digits(point: Mapping[str, flint.fmpq]) -> int:
    """About the largest number of decimal digits of a numerator or denominator (from the bit length)."""
    bits = max(max(int(q.p).bit_length(), int(q.q).bit_length()) for q in point.values())
    return 1 + int(bits * 0.30103)


def exact_orbit(kmap: KahanMap, point: Mapping[str, flint.fmpq], values: Mapping[str, Rational],
                steps: int, max_digits: int = 100_000) -> ExactOrbit:
    """The orbit of `point` for `steps` steps at exact eps and parameters, stopped at the first repetition (a periodic
    orbit: every later point is known) or when a coordinate exceeds `max_digits` digits (heights of exact orbits grow
    like exp(c n^2) for integrable maps and faster otherwise); SingularPointError names the step where det M = 0."""
    exact = {k: to_fmpq(v) for k, v in values.items()}
    guard = HeightGuard(steps, max_bits=10 * max_digits)
    seen: dict[tuple, int] = {}
    orbit: list[dict[str, flint.fmpq]] = []
    current = dict(point)
    for i in range(steps + 1):
        key = tuple(current[v] for v in kmap.variables)
        if key in seen:
            return ExactOrbit(kmap.variables, exact, orbit, i - seen[key], seen[key])
        seen[key] = i
        orbit.append(current)
        guard.observe(i, current.values())
        if i < steps and digits(current) > max_digits:
            return ExactOrbit(kmap.variables, exact, orbit,
                              stopped=f"x_{i} has more than {max_digits} digits: stopped after {i} steps")
        if i < steps:
            try:
                current = kmap.step_exact({**exact, **current})
            except SingularPointError as exc:
                raise SingularPointError(f"x_{i} of the orbit is a singular point of the map ({exc})") from None
    return ExactOrbit(kmap.variables, exact, orbit)
