"""Kernel coordinates as a black box mod p: recipe (B) on a batch of points, the input of sparse reconstruction.

For a minimal HK-basis of monomials phi_1..phi_l (one-dimensional kernel), the coordinates c with c_l = -1 solve
sum_k c_k phi_k(f^i x) = phi_l(f^i x), i = 0..l-2 (eq. "smaller system"). The orbit and this system are taken on a
whole batch at once (hkproof.dynamics.batch_map), projectively: a monomial of degree e at X / W is X^e W^(d-e)
after clearing W^d. The black box answers c_k / c_j mod p at each point, None where the orbit or the system is
singular mod p there.
"""
from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from hkproof.algebra.monomials import Exponents
from hkproof.dynamics.batch_map import BatchKahanMap, mulmod, power_table, solve_projective
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap

__all__ = ["KernelBlackBox"]

_WORKER_MAPS: dict[tuple[QuadraticField, int], BatchKahanMap] = {}    # a worker process's batch maps, by prime


class KernelBlackBox:
    """c_k / c_j of the kernel of `basis` (its last element normalized by c_l = -1), as a function of the names
    `inputs` (the other ring names fixed to `fixed`), evaluated mod primes below 2^50 on batches of points."""

    def __init__(self, kmap: KahanMap, basis: Sequence[Exponents], k: int, j: int, inputs: Sequence[str],
                 fixed: Mapping[str, int] | None = None):
        self.kmap, self.basis, self.k, self.j = kmap, list(basis), k, j
        self.inputs, self.fixed = list(inputs), dict(fixed or {})
        missing = set(kmap.ring.names) - set(self.inputs) - set(self.fixed)
        if missing:
            raise ValueError(f"no value for {sorted(missing)}")
        self.degree = max(sum(e) for e in self.basis)
        self._maps: dict[int, BatchKahanMap] = {}
        self.probes = 0

    def _map(self, p: int) -> BatchKahanMap:
        if p not in self._maps:
            key = (self.kmap.field, p)
            if key not in _WORKER_MAPS:
                _WORKER_MAPS.clear()
                _WORKER_MAPS[key] = BatchKahanMap(self.kmap, p)
            self._maps = {p: _WORKER_MAPS[key]}
        return self._maps[p]

    def __getstate__(self) -> dict:
        """Sent to a worker as data: the field, not its Kahan map (rebuilt there once, hkproof.dynamics.catalogue)."""
        return {**self.__dict__, "kmap": self.kmap.field, "_maps": {}}

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state, kmap=kahan_map(state["kmap"]))

    def vectors(self, p: int, points: Sequence[Sequence[int]]) -> tuple[list[np.ndarray], np.ndarray]:
        """The kernel vectors projectively: c = (N_1, ..., N_(l-1), -D) up to a factor, and a mask of the points
        where the orbit and the system are regular mod p."""
        batch = np.asarray(points, dtype=np.int64).reshape(len(points), len(self.inputs)) % p
        count = len(points)
        values = {name: batch[:, i] for i, name in enumerate(self.inputs)}
        values.update({name: np.full(count, v % p, dtype=np.int64) for name, v in self.fixed.items()})
        l = len(self.basis)
        orbit = self._map(p).orbit(values, l - 2)
        rows = np.empty((count, l - 1, l), dtype=np.int64)
        ok = np.ones(count, dtype=bool)
        for i, (xs, w) in enumerate(orbit[:l - 1]):
            ok &= w != 0
            x_pow = [power_table(x, self.degree, p) for x in xs]
            w_pow = power_table(w, self.degree, p)
            for c, e in enumerate(self.basis):
                v = w_pow[self.degree - sum(e)].copy()
                for table, a in zip(x_pow, e, strict=True):
                    if a:
                        v = mulmod(v, table[a], p)
                rows[:, i, c] = v
        nums, den = solve_projective(rows[:, :, :l - 1], rows[:, :, l - 1], p)
        ok &= den != 0
        self.probes += count
        return [nums[:, c] for c in range(l - 1)] + [(p - den) % p], ok

    def __call__(self, p: int, points: Sequence[Sequence[int]]) -> list[int | None]:
        """c_k / c_j mod p at each point (None where undefined mod p)."""
        coords, ok = self.vectors(p, points)
        top, bottom = coords[self.k], coords[self.j]
        ok &= bottom != 0
        inverse = _inverse(np.where(ok, bottom, 1), p)
        values = mulmod(top, inverse, p)
        return [int(v) if good else None for v, good in zip(values, ok, strict=True)]


def _inverse(values: np.ndarray, p: int) -> np.ndarray:
    """Elementwise inverse mod p by Fermat's little theorem (values non-zero)."""
    result = np.ones_like(values)
    base = values % p
    e = p - 2
    while e:
        if e & 1:
            result = mulmod(result, base, p)
        base = mulmod(base, base, p)
        e >>= 1
    return result
