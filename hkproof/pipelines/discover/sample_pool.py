"""Random points mod p for the relation plans of one basis (hkproof.pipelines.discover.relation_plan): their tangent
orbits, the proven integrals' values and gradients there, and the basis's kernel coordinates, drawn or solved once
and shared by the normalizations of the basis (which differ only in the order of its functions)."""
from __future__ import annotations

import random
from typing import Mapping, Sequence

from hkproof import budget
from hkproof.algebra.fraction import Frac, ModularFrac
from hkproof.algebra.monomials import Exponents
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, UnluckyPrimeError
from hkproof.pipelines.discover.candidates import coordinate_gradients, recipe_b_mod_p
from hkproof.pipelines.discover.screen import TangentOrbit

__all__ = ["SamplePool", "Samples"]


class SamplePool:
    """Random points mod p with their tangent orbits and the proven integrals' values and gradients, drawn once and
    shared by the normalizations of one basis (only the order of the basis differs between them, and the orbits,
    the integrals and their gradients do not depend on it)."""

    def __init__(self, kmap: KahanMap, known: Mapping[str, Frac], p: int, controls: Mapping[str, int],
                 rng: random.Random, length: int):
        self.kmap, self.p, self.rng, self.length = kmap, p, rng, length
        self.modular = kmap.mod(p, controls)
        self.controls = [controls[n] for n in kmap.field.control_names]
        self.known = {k: h.mod_p(p) for k, h in known.items()}
        self.phase = [kmap.ring.index(v) for v in kmap.variables]
        self.points: list[tuple[list[int], TangentOrbit]] = []
        self._values: dict[tuple[int, ...], dict[str, int] | None] = {}
        self._gradients: dict[tuple[int, ...], list[list[int]] | None] = {}
        self._kernels: dict[tuple, tuple[dict[Exponents, int], dict[Exponents, list[int]] | None] | None] = {}

    def point(self, index: int) -> tuple[list[int], TangentOrbit]:
        """The index-th random point and its tangent orbit of `length` steps (drawn when first asked for)."""
        while len(self.points) <= index:
            self.points.append(self._draw())
        return self.points[index]

    def _draw(self) -> tuple[list[int], TangentOrbit]:
        for _ in range(20):
            budget.check("sampling kernel coordinates mod p")
            x = [self.rng.randrange(1, self.p) for _ in self.kmap.variables]
            try:
                return x, TangentOrbit(self.modular, x, self.length)
            except UnluckyPrimeError:
                continue
        raise HKProofError(f"twenty random orbits mod {self.p} met det M = 0: the map looks singular")

    def _ring_point(self, x: Sequence[int]) -> list[int]:
        """x and the control values in the order of the ring's names (for Frac.residue_at)."""
        values = dict(zip(self.kmap.variables, x, strict=True))
        values.update(zip(self.kmap.field.control_names, self.controls, strict=True))
        return [values[n] for n in self.kmap.ring.names]

    def known_values(self, x: Sequence[int]) -> dict[str, int] | None:
        """The proven integrals at x mod p (None where a denominator vanishes), computed once per point."""
        key = tuple(x)
        if key not in self._values:
            at = self._ring_point(x)
            out = {k: h(at) for k, h in self.known.items()}
            self._values[key] = None if any(v is None for v in out.values()) else \
                {k: int(v or 0) for k, v in out.items()}
        return self._values[key]

    def known_gradients(self, x: Sequence[int]) -> list[list[int]] | None:
        """The proven integrals' gradients in the phase variables at x mod p (None at a pole), once per point."""
        key = tuple(x)
        if key not in self._gradients:
            at = self._ring_point(x)
            rows = [h.gradient(at, self.phase) for h in self.known.values()]
            self._gradients[key] = None if any(r is None for r in rows) else rows  # type: ignore[assignment]
        return self._gradients[key]

    def coordinates(self, x: Sequence[int], orbit: TangentOrbit, basis: Sequence[Exponents],
                    gradients: bool = False) -> tuple[list[int], list[list[int]] | None] | None:
        """The kernel coordinates of `basis` at x (its last function normalized to -1), and their gradients when
        asked for, mod p (None where the system of recipe (B) is singular). The normalizations of one basis share
        one kernel: it is solved once per point in the sorted order and renormalized, c'_k = -c_k / c_j, with the
        quotient rule for the gradients; where the sorted order's own normalization is singular, directly."""
        key = (tuple(x), tuple(sorted(basis)))
        if key not in self._kernels or (gradients and (entry := self._kernels[key]) is not None and entry[1] is None):
            self._kernels[key] = _kernel(orbit, list(key[1]), gradients)
        entry = self._kernels[key]
        if entry is None:
            return _direct(orbit, list(basis), gradients)
        values, grads = entry
        p, last = self.p, basis[-1]
        if values[last] == 0:
            return None
        scale = -pow(values[last], -1, p)
        coords = [values[e] * scale % p for e in basis[:-1]]
        if not gradients or grads is None:
            return coords, None
        inverse2, dl = pow(values[last], -2, p), grads[last]
        return coords, [[-(a * values[last] - values[e] * b) * inverse2 % p for a, b in zip(grads[e], dl, strict=True)]
                        for e in basis[:-1]]


class Samples:
    """Kernel coordinates (c_l = -1) of the basis in its order, at the points of a pool, one after another."""

    def __init__(self, basis: Sequence[Exponents], pool: SamplePool):
        if pool.length != len(basis) - 2:
            raise HKProofError(f"a pool of orbits of {pool.length} steps for a basis of {len(basis)} functions")
        self.basis, self.pool = list(basis), pool
        self._next = 0

    @property
    def p(self) -> int:
        return self.pool.p

    @property
    def kmap(self) -> KahanMap:
        return self.pool.kmap

    @property
    def known(self) -> dict[str, ModularFrac]:
        return self.pool.known

    def point(self) -> tuple[list[int], TangentOrbit]:
        self._next += 1
        return self.pool.point(self._next - 1)

    def coordinates(self, x: Sequence[int], orbit: TangentOrbit) -> list[int] | None:
        solved = self.pool.coordinates(x, orbit, self.basis)
        return None if solved is None else solved[0]

    def gradients(self, x: Sequence[int], orbit: TangentOrbit) -> list[list[int]] | None:
        solved = self.pool.coordinates(x, orbit, self.basis, gradients=True)
        return None if solved is None else solved[1]

    def known_values(self, x: Sequence[int]) -> dict[str, int] | None:
        return self.pool.known_values(x)

    def known_gradients(self, x: Sequence[int]) -> list[list[int]] | None:
        return self.pool.known_gradients(x)


def _kernel(orbit: TangentOrbit, basis: list[Exponents], gradients: bool
            ) -> tuple[dict[Exponents, int], dict[Exponents, list[int]] | None] | None:
    """The coordinates of recipe (B) (and their gradients) in the order `basis`, by function, the last one -1."""
    solved = _direct(orbit, basis, gradients)
    if solved is None:
        return None
    coords, grads = solved
    values = dict(zip(basis, [*coords, orbit.p - 1], strict=True))
    if grads is None:
        return values, None
    return values, dict(zip(basis, [*grads, [0] * len(orbit.points[0])], strict=True))


def _direct(orbit: TangentOrbit, basis: list[Exponents], gradients: bool
            ) -> tuple[list[int], list[list[int]] | None] | None:
    """The coordinates of recipe (B) in the order `basis` (and their gradients), solved at the orbit."""
    solved = recipe_b_mod_p(orbit, basis)
    if solved is None:
        return None
    if not gradients:
        return solved[1], None
    grads = coordinate_gradients(orbit, basis)
    return None if grads is None else (solved[1], grads)
