"""Exact orbits of a Kahan map over Q (KahanMap.orbit_exact) and the detection of periodic orbits."""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Mapping

import flint

from hkproof.algebra.printing import markdown_table, sympy_rational
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.heights import HeightGuard
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import SingularPointError

if TYPE_CHECKING:
    import sympy

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

    def outcome(self) -> str:
        """Periodic, eventually periodic, stopped (too many digits) or no repetition within the steps."""
        if self.closes:
            return f"periodic: f^{self.period}(x_0) = x_0 exactly (period {self.period})"
        if self.period and self.preperiod is not None:
            return f"eventually periodic: x_{self.preperiod + self.period} = x_{self.preperiod} (period {self.period})"
        if self.stopped:
            return f"no repetition; {self.stopped}"
        return f"no repetition within {len(self.points) - 1} steps (largest size {max(map(digits, self.points))} digits)"

    def to_sympy(self) -> list[tuple[sympy.Rational, ...]]:
        """The points x_0, x_1, ... as tuples of exact sympy Rationals."""
        return [tuple(sympy_rational(x[v]) for v in self.variables) for x in self.points]

    def _repr_markdown_(self) -> str:
        """The points (long coordinates cut, with their digit counts) and the outcome: how Jupyter shows the orbit."""
        at = ", ".join(f"{k} = {v}" for k, v in self.values.items())
        rows = [[f"x_{i}", *(_cut(str(x[v])) for v in self.variables)] for i, x in enumerate(self.points[:SHOWN])]
        more = [f"... {len(self.points) - SHOWN} more points"] if len(self.points) > SHOWN else []
        return "\n".join([f"**exact orbit over Q** at {at}", "", markdown_table(["", *self.variables], rows), *more,
                          "", self.outcome()])


SHOWN = 12          # points of an orbit shown in a notebook


def _cut(text: str, width: int = 40) -> str:
    return text if len(text) <= width else f"{text[:width - 12]}... ({len(text)} chars)"


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
