"""A Kahan map at fixed eps and parameters, compiled for evaluation at points (eq. "Kahan gen" in matrix form)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ParseError

__all__ = ["AffineEntry", "compile_poly", "CompiledPoly", "make_scene", "point_values", "Scene"]

# a polynomial in the phase variables at fixed eps and parameters: ((coefficient, exponents), ...)
CompiledPoly = tuple[tuple[flint.fmpq, tuple[int, ...]], ...]
# an affine entry c0 + sum_k c_k x_k: (c0, ((k, c_k), ...))
AffineEntry = tuple[flint.fmpq, tuple[tuple[int, flint.fmpq], ...]]


@dataclass(frozen=True)
class Scene:
    """The map f(., eps) with eps and every parameter fixed: M(x) = M0 + sum x_k M_k and b(x) likewise, exactly."""

    kmap: KahanMap
    values: tuple[tuple[str, flint.fmpq], ...]
    matrix: tuple[tuple[AffineEntry, ...], ...]
    rhs: tuple[AffineEntry, ...]

    @property
    def fixed(self) -> dict[str, flint.fmpq]:
        return dict(self.values)

    @property
    def variables(self) -> tuple[str, ...]:
        return self.kmap.variables

    def compile(self, h: Frac) -> tuple[CompiledPoly, CompiledPoly]:
        """(numerator, denominator) of h as polynomials in the phase variables with eps and parameters fixed."""
        return compile_poly(self, h.num), compile_poly(self, h.den)


def make_scene(kmap: KahanMap, values: Mapping[str, Rational]) -> Scene:
    """Fix eps and all parameters of `kmap` to rationals; the affine pieces of M and b are evaluated once."""
    names = (EPS,) + kmap.field.parameters
    missing = [n for n in names if n not in values]
    if missing:
        raise ParseError(f"a scene of {kmap.field.name} needs values for {missing}")
    fixed = tuple((n, to_fmpq(values[n])) for n in names)
    m_parts, b_parts = kmap.affine_matrix
    matrix = tuple(tuple(_evaluate_affine(kmap, e, fixed) for e in row) for row in m_parts)
    rhs = tuple(_evaluate_affine(kmap, e, fixed) for e in b_parts)
    return Scene(kmap, fixed, matrix, rhs)


def _evaluate_affine(kmap: KahanMap, parts: dict, fixed: tuple) -> AffineEntry:
    ring = kmap.ring
    values = dict(fixed)
    args = [values.get(n, flint.fmpq(0)) for n in ring.names]
    const = ring.to_q(parts[None])(*args) if None in parts else flint.fmpq(0)
    lin = sorted((k, ring.to_q(p)(*args)) for k, p in parts.items() if k is not None)
    return const, tuple((k, c) for k, c in lin if c != 0)


def compile_poly(scene: Scene, p: flint.fmpz_mpoly) -> CompiledPoly:
    """p with eps and parameters fixed, as (coefficient, exponents in the phase variables) terms."""
    ring = scene.kmap.ring
    fixed = scene.fixed
    idx = [ring.index(v) for v in scene.variables]
    other = [(i, fixed[n]) for i, n in enumerate(ring.names) if n in fixed]
    terms: dict[tuple[int, ...], flint.fmpq] = {}
    for mono, c in p.to_dict().items():
        coef = flint.fmpq(c)
        for i, v in other:
            if mono[i]:
                coef *= v ** mono[i]
        key = tuple(int(mono[i]) for i in idx)
        terms[key] = terms.get(key, flint.fmpq(0)) + coef
    return tuple((c, k) for k, c in terms.items() if c != 0)


def point_values(scene: Scene, point: Sequence[Rational]) -> list[flint.fmpq]:
    """A phase point as exact rationals, checked against the number of variables."""
    if len(point) != len(scene.variables):
        raise ParseError(f"a point of {scene.kmap.field.name} has {len(scene.variables)} coordinates, got {len(point)}")
    return [to_fmpq(v) for v in point]
