"""Float data for pictures (Figs. "LV", "dET", plots 1-4): orbits of the Kahan and explicit Euler maps, and
kernel coordinates at many points.  Pictures need no exact arithmetic; accuracy claims are made elsewhere."""
from __future__ import annotations

from fractions import Fraction
from typing import Mapping, Sequence

import numpy as np

from hkproof.dynamics.kahan import KahanMap
from hkproof.experiments.approximate import Float64
from hkproof.experiments.profiles import HK_BASIS, ProfileProblem
from hkproof.experiments.scene import make_scene

__all__ = ["euler_orbit", "kahan_orbit", "kernel_cloud"]


def _exact(values: Mapping[str, float | str]) -> dict[str, Fraction]:
    """Decimal inputs such as 0.2 read as the rationals they denote (1/5)."""
    return {k: Fraction(str(v)) for k, v in values.items()}


def kahan_orbit(kmap: KahanMap, values: Mapping[str, float | str], x0: Sequence[float], steps: int) -> np.ndarray:
    """x, f(x), ..., f^steps(x) in float64 (rows), stopping early if the orbit meets Delta = 0."""
    arithmetic = Float64()
    prep = arithmetic.prepare(make_scene(kmap, _exact(values)), [])
    x = [float(v) for v in x0]
    out = [x]
    for _ in range(steps):
        m = np.array([[arithmetic.affine(e, x) for e in row] for row in prep.matrix])
        b = np.array([arithmetic.affine(e, x) for e in prep.rhs])
        x = list(np.linalg.solve(m, b))
        out.append(x)
    return np.array(out)


def euler_orbit(kmap: KahanMap, values: Mapping[str, float | str], x0: Sequence[float], h: float,
                steps: int) -> np.ndarray:
    """The explicit Euler method x + h F(x) for the same field (the spiralling orbits of Figs. "LV", "dET")."""
    arithmetic = Float64()
    scene = make_scene(kmap, _exact({"eps": 1, **values}))
    rhs = [tuple(arithmetic.prepare(scene, [scene.compile(f)]).basis[0]) for f in kmap.field.rhs]
    x = [float(v) for v in x0]
    out = [x]
    for _ in range(steps):
        x = [xi + h * arithmetic.evaluate(num, x) / arithmetic.evaluate(den, x) for xi, (num, den) in zip(x, rhs, strict=True)]
        out.append(x)
    return np.array(out)


def kernel_cloud(kmap: KahanMap, basis: Sequence, values: Mapping[str, float | str],
                 points: Sequence[Sequence[float | str]]) -> np.ndarray:
    """K_Phi(x) (last coordinate -1) in float64 at each point where algorithm (N) finds d = 1; NaN rows elsewhere."""
    problem = ProfileProblem(make_scene(kmap, _exact(values)), basis)
    rows = []
    for x in points:
        p = problem.profile([Fraction(str(v)) for v in x], Float64())
        ok = p.verdict == HK_BASIS and p.dimension == 1 and p.kernel is not None
        rows.append(p.kernel[0] if ok and p.kernel is not None else [np.nan] * len(basis))
    return np.array(rows, dtype=float)
