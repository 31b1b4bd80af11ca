"""Random rational points and parameter values for algorithm (N), and points near the singular set Delta = 0."""
from __future__ import annotations

import random
from fractions import Fraction
from typing import Mapping

import numpy as np

from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ParseError
from hkproof.experiments.approximate import Float64
from hkproof.experiments.scene import Scene


def random_rational(rng: random.Random, size: int = 9) -> Fraction:
    """A non-zero rational a/b with |a| <= size and 1 <= b <= size."""
    return Fraction(rng.choice([a for a in range(-size, size + 1) if a]), rng.randint(1, size))


def random_values(kmap: KahanMap, rng: random.Random, fixed: Mapping[str, Rational] | None = None,
                  size: int = 9) -> dict[str, Fraction]:
    """eps and the parameters: the given ones, the others random (distinct, non-zero, eps in (0, 1])."""
    names = (EPS,) + kmap.field.parameters
    unknown = sorted(set(fixed or {}) - set(names))
    if unknown:
        raise ParseError(f"{unknown} are not eps or parameters of {kmap.field.name} ({list(names)})")
    out: dict[str, Fraction] = {}
    for name in names:
        if fixed and name in fixed:
            out[name] = Fraction(str(to_fmpq(fixed[name])))
            continue
        while True:
            v = abs(random_rational(rng, size)) if name == EPS else random_rational(rng, size)
            if name == EPS:
                v = min(v, 1 / v)
            if v not in out.values():
                break
        out[name] = v
    return out


def random_point(kmap: KahanMap, rng: random.Random, size: int = 9) -> list[Fraction]:
    """A phase point with small random rational coordinates (the paper's 'randomly chosen initial points')."""
    return [random_rational(rng, size) for _ in kmap.variables]


def near_singular_point(scene: Scene, rng: random.Random, offset: Fraction = Fraction(1, 10**9),
                        size: int = 9) -> list[Fraction]:
    """A rational point at distance ~offset from Delta = 0 along a random line (Delta(x) = det M(x) up to a factor)."""
    arithmetic = Float64()
    prep = arithmetic.prepare(scene, [])
    n = len(scene.variables)
    while True:
        x0 = random_point(scene.kmap, rng, size)
        v = random_point(scene.kmap, rng, size)
        ts = np.linspace(-2.0, 2.0, n + 1)
        dets = []
        for t in ts:
            x = [float(a) + t * float(b) for a, b in zip(x0, v)]
            dets.append(np.linalg.det(np.array([[arithmetic.affine(e, x) for e in row] for row in prep.matrix])))
        roots = [r.real for r in np.roots(np.polyfit(ts, dets, n)) if abs(r.imag) < 1e-9 and abs(r.real) < 10]
        if roots:
            t = Fraction(min(roots, key=abs)).limit_denominator(10**12) + offset
            return [a + t * b for a, b in zip(x0, v)]
