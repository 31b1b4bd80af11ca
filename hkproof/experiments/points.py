"""Random rational points and parameter values for algorithm (N), and points near the singular set Delta = 0."""
from __future__ import annotations

import random
from fractions import Fraction
from typing import Mapping

import numpy as np

from hkproof.algebra.ring import Rational
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
    """eps and the parameters: the given ones (checked by QuadraticField.check_values), the others random (distinct,
    non-zero, eps in (0, 1], off the poles of the field's coefficients)."""
    field = kmap.field
    given = {k: Fraction(str(v)) for k, v in field.check_values(fixed or {}).items()}
    for _ in range(1000):
        out: dict[str, Fraction] = {}
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
                     f"coefficients of {field.name} with {given}: fix them with --param")


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
            x = [float(a) + t * float(b) for a, b in zip(x0, v, strict=True)]
            dets.append(np.linalg.det(np.array([[arithmetic.affine(e, x) for e in row] for row in prep.matrix])))
        roots = [r.real for r in np.roots(np.polyfit(ts, dets, n)) if abs(r.imag) < 1e-9 and abs(r.real) < 10]
        if roots:
            t = Fraction(min(roots, key=abs)).limit_denominator(10**12) + offset
            return [a + t * b for a, b in zip(x0, v, strict=True)]
