"""Affine changes of the phase variables, y = T x + c, under which Kahan's scheme is equivariant.

Eq. "Kahan gen" is affine in the polarized field, so if G(T x + c) = T F(x) as polynomials in x (T constant and
invertible, c constant: both may involve the parameters, never eps or x), the Kahan maps satisfy g(T x + c) = T f(x)
+ c, and an integral J of g pulls back to the integral J(T x + c) of f (hk.conjugacy states the linear case for
maps). `transformed` builds G from F, `field_mismatches` checks the identity exactly, `pull_back` carries a function
back; a search can run in whichever chart is cheapest (hkproof.pipelines.charts) and prove in the user's.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import solve_by_inverse
from hkproof.algebra.ring import Ring
from hkproof.dynamics.field import EPS, QuadraticField
from hkproof.errors import HKProofError, SingularSystemError
from hkproof.hk.transport import Substitution

__all__ = ["AffineChange", "CHANGE_KINDS", "field_mismatches", "random_change", "transformed"]

CHANGE_KINDS = ("dense", "signed-permutation", "translation", "affine")


@dataclass(frozen=True)
class AffineChange:
    """y = T x + c for a field's phase variables x (y named as x): `matrix` T and `shift` c as formulas in the
    field's parameters (rows of T in the order of the variables)."""

    matrix: tuple[tuple[str, ...], ...]
    shift: tuple[str, ...]

    @classmethod
    def translation(cls, shift: Sequence[str]) -> "AffineChange":
        """y = x + c."""
        n = len(shift)
        return cls(tuple(tuple("1" if i == j else "0" for j in range(n)) for i in range(n)), tuple(shift))

    def is_translation(self) -> bool:
        n = len(self.shift)
        return all(self.matrix[i][j] == ("1" if i == j else "0") for i in range(n) for j in range(n))

    def entries(self, field: QuadraticField) -> tuple[list[list[Frac]], list[Frac]]:
        """T and c read exactly in the field's ring, checked: the right sizes, free of x and eps, det T != 0."""
        n = len(field.variables)
        if len(self.matrix) != n or any(len(row) != n for row in self.matrix) or len(self.shift) != n:
            raise HKProofError(f"an affine change of {field.name} needs an {n} x {n} matrix and {n} shifts")
        t = [[field.parse(e) for e in row] for row in self.matrix]
        c = [field.parse(e) for e in self.shift]
        moving = set(field.variables) | {EPS}
        for value in [*(e for row in t for e in row), *c]:
            if value.variables() & moving:
                raise HKProofError(f"an entry {value} of an affine change involves {sorted(value.variables() & moving)}"
                                   ": T and c must be constant along the flow and free of the step")
        return t, c

    def images(self, field: QuadraticField) -> dict[str, Frac]:
        """y_j -> (T x + c)_j in the field's ring."""
        t, c = self.entries(field)
        x = [Frac(field.ring, field.ring.gen(v)) for v in field.variables]
        return {y: _row_times(row, x, c[j]) for j, (y, row) in enumerate(zip(field.variables, t, strict=True))}

    def inverse_images(self, field: QuadraticField) -> dict[str, Frac]:
        """x_k -> (T^-1 (y - c))_k in the field's ring (y named as x); HKProofError when T is singular."""
        t, c = self.entries(field)
        y = [Frac(field.ring, field.ring.gen(v)) - ck for v, ck in zip(field.variables, c, strict=True)]
        try:
            x = solve_by_inverse(t, y)
        except SingularSystemError:
            raise HKProofError(f"the matrix T of the affine change is singular: y = T x + c is not a change of "
                               f"coordinates of {field.name}") from None
        return dict(zip(field.variables, x, strict=True))

    def pull_back(self, field: QuadraticField, h: Frac) -> Frac:
        """J(T x + c) for a function J of the transformed chart (same names): an integral of f when J is one of g."""
        return _substitution(field.ring, self.images(field)).apply(h.to_ring(field.ring))

    def describe(self, field: QuadraticField) -> str:
        """The change as equations y_j = ... in the user's names."""
        return ", ".join(f"{y} -> {img}" for y, img in self.images(field).items())


def transformed(field: QuadraticField, change: AffineChange, name: str | None = None) -> QuadraticField:
    """G(y) = T F(T^-1 (y - c)): the field in the new chart (the same names; quadratic again, exactly)."""
    t, _ = change.entries(field)
    back = _substitution(field.ring, change.inverse_images(field))
    moved = [back.apply(f) for f in field.rhs]
    rhs = [str(_row_times(row, moved, Frac(field.ring, 0))) for row in t]
    return QuadraticField(name or f"{field.name}[affine chart]", field.variables, field.parameters, tuple(rhs),
                          f"{field.name} in the chart y = T x + c", field.step)


def field_mismatches(field: QuadraticField, target: QuadraticField, change: AffineChange) -> list[str]:
    """The components j where G_j(T x + c) != (T F(x))_j exactly ([] when `target` is `field` in the new chart)."""
    if target.variables != field.variables or target.parameters != field.parameters:
        raise HKProofError(f"{target.name} must have the variables and parameters of {field.name}")
    t, _ = change.entries(field)
    forward = _substitution(field.ring, change.images(field))
    out = []
    for y, g, row in zip(field.variables, target.rhs, t, strict=True):
        if forward.apply(g.to_ring(field.ring)) != _row_times(row, field.rhs, Frac(field.ring, 0)):
            out.append(f"{y}'")
    return out


def random_change(n: int, rng: random.Random, kind: str) -> AffineChange:
    """A random change of coordinates for metamorphic tests and benchmarks: "dense" (entries of T in [-2, 2],
    det T != 0), "signed-permutation" (with scalings by 1, 2 or 3), "translation" (c in [-3, 3]), or "affine" (a
    dense T and a translation)."""
    if kind not in CHANGE_KINDS:
        raise HKProofError(f"the kind of a random change is one of {CHANGE_KINDS}, got {kind!r}")
    t = [[int(i == j) for j in range(n)] for i in range(n)]
    if kind in ("dense", "affine"):
        t = [[rng.randint(-2, 2) for _ in range(n)] for _ in range(n)]
        while flint.fmpz_mat(t).det() == 0:
            t = [[rng.randint(-2, 2) for _ in range(n)] for _ in range(n)]
    elif kind == "signed-permutation":
        order = rng.sample(range(n), n)
        t = [[rng.choice((-1, 1)) * rng.randint(1, 3) if j == order[i] else 0 for j in range(n)] for i in range(n)]
    shift = [rng.randint(-3, 3) if kind in ("translation", "affine") else 0 for _ in range(n)]
    return AffineChange(tuple(tuple(str(e) for e in row) for row in t), tuple(str(e) for e in shift))


def _row_times(row: Sequence[Frac], values: Sequence[Frac], start: Frac) -> Frac:
    """start + sum_k row_k values_k: one component of T v (+ c)."""
    return sum((a * v for a, v in zip(row, values, strict=True)), start)


def _substitution(ring: Ring, images: dict[str, Frac]) -> Substitution:
    """Simultaneous substitution of the phase variables in `ring` (into the same ring)."""
    return Substitution(ring, ring, images)
