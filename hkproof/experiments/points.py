"""Random rational points and parameter values for algorithm (N), and points near the singular set Delta = 0."""
from __future__ import annotations

import random
from fractions import Fraction
from typing import Mapping

import flint
import numpy as np

from hkproof.algebra.ring import Rational
from hkproof.algebra.sampling import random_rational, random_rationals
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ParseError
from hkproof.experiments.approximate import Float64
from hkproof.experiments.scene import Scene

__all__ = ["near_singular_point", "random_values"]


def random_values(kmap: KahanMap, rng: random.Random, fixed: Mapping[str, Rational] | None = None,
                  size: int = 9) -> dict[str, flint.fmpq]:
    """eps and the parameters: the given ones (checked by QuadraticField.check_values), the others random (distinct,
    non-zero, eps in (0, 1], off the poles of the field's coefficients)."""
    field = kmap.field
    given = field.check_values(fixed or {})
    for _ in range(1000):
        out: dict[str, flint.fmpq] = {}
        for name in (EPS,) + field.parameters:
            if name in given:
                out[name] = given[name]
                continue
            while True:
                v = abs(random_rational(rng, size)) if name == EPS else random_rational(rng, size)
                if name == EPS:
                    v = min(v, 1 / v)
                if v not in out.values() and v not in given.values():
                    break
            out[name] = v
        try:
            field.check_values(out)
        except ParseError:
            continue
        return out
    raise ParseError(f"no random values of {sorted(set(field.parameters) - set(given))} avoid the poles of the "
                     f"coefficients of {field.name} with {given}: fix their values")


def near_singular_point(scene: Scene, rng: random.Random, offset: Fraction = Fraction(1, 10**9),
                        size: int = 9) -> list[Fraction]:
    """A rational point at distance ~offset from Delta = 0 along a random line (Delta(x) = det M(x) up to a factor)."""
    arithmetic = Float64()
    prep = arithmetic.prepare(scene, [])
    n = len(scene.variables)
    while True:
        x0 = [Fraction(int(q.p), int(q.q)) for q in random_rationals(rng, len(scene.variables), size)]
        v = [Fraction(int(q.p), int(q.q)) for q in random_rationals(rng, len(scene.variables), size)]
        ts = np.linspace(-2.0, 2.0, n + 1)
        dets = []
        for t in ts:
            x = [float(a) + t * float(b) for a, b in zip(x0, v, strict=True)]
            dets.append(np.linalg.det(np.array([[arithmetic.affine(e, x) for e in row] for row in prep.matrix])))
        roots = [r.real for r in np.roots(np.polyfit(ts, dets, n)) if abs(r.imag) < 1e-9 and abs(r.real) < 10]
        if roots:
            t = Fraction(min(roots, key=abs)).limit_denominator(10**12) + offset
            return [a + t * b for a, b in zip(x0, v, strict=True)]
