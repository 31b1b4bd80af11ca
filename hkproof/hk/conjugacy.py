"""Kahan maps in other linear coordinates: Kahan's scheme commutes with linear changes of the phase variables.

If y = T x (T invertible, constant) carries the field F to G = T F(T^-1 y), the Kahan maps satisfy g(T x) = T f(x),
because eq. "Kahan gen" is linear in the polarized field. `LinearChart` states such a chart as data (each new
variable and new parameter as a formula in the old names), `conjugacy_mismatches` checks g o T = T o f exactly, and
`pull_back` carries an integral h of g to h o T, an integral of f: h(g(T x)) = h(T f(x)) and h(g(y)) = h(y).
A search that fails in one chart can succeed in another (the so(4) Euler top, docs/atlas.md): integrals proven for
g are proven for f once the chart is checked.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.independence import sample_point
from hkproof.hk.transport import Substitution

__all__ = ["LinearChart", "conjugacy_mismatches", "pull_back"]


@dataclass(frozen=True)
class LinearChart:
    """y = T x from `source` (variables x, parameters a) to `target` (variables y, parameters b): `images` gives each
    y_j as a linear form in x and each b_k as a formula in a; eps is the same step in both."""

    source: KahanMap
    target: KahanMap
    images: Mapping[str, str]

    def substitution(self) -> Substitution:
        """sigma: Q(y, eps, b) -> Q(x, eps, a), y -> T x, b -> b(a)."""
        missing = [n for n in (*self.target.variables, *self.target.field.parameters) if n not in self.images]
        if missing:
            raise HKProofError(f"the chart gives no image for {missing}")
        images = {n: Frac.parse(self.source.ring, t) for n, t in self.images.items()}
        for y in self.target.variables:
            if images[y].den != 1 or images[y].num.total_degree() > 1 or \
                    images[y].variables() - set(self.source.variables):
                raise HKProofError(f"{y} = {images[y]} is not a linear form in {', '.join(self.source.variables)}")
        sigma = Substitution(self.target.ring, self.source.ring, images)
        moved = [*self.source.variables, *self.source.field.parameters]
        if not sigma.is_injective_at(moved, sample_point(moved + [EPS], 3)):
            raise HKProofError("the chart is not invertible: its images have a degenerate Jacobian")
        return sigma


def conjugacy_mismatches(chart: LinearChart) -> list[str]:
    """The components where g(T x) != T f(x) as rational functions of x, eps and a ([] when the maps are
    conjugate)."""
    sigma = chart.substitution()
    f = chart.source
    out = []
    for y, g_y in zip(chart.target.variables, chart.target.components(), strict=True):
        linear = Frac.parse(f.ring, chart.images[y])
        if sigma.apply(g_y) != f.pullback(linear):
            out.append(f"{y}~")
    return out


def pull_back(chart: LinearChart, integrals: Sequence[Frac]) -> list[Frac]:
    """h o T for integrals h of the target map: integrals of the source map once `conjugacy_mismatches` is empty."""
    sigma = chart.substitution()
    return [sigma.apply(h.to_ring(chart.target.ring)) for h in integrals]
