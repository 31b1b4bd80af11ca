"""Kernel coordinates as a black box mod p: recipe (B) on a batch of points, the input of sparse reconstruction.

For a minimal HK-basis phi_1..phi_l (one-dimensional kernel), the coordinates c with c_l = -1 solve
sum_k c_k phi_k(f^i x) = phi_l(f^i x), i = 0..l-2 (eq. "smaller system"). The basis functions are monomials or
polynomials in the phase variables whose coefficients are polynomials in eps and the parameters (integrals of the
continuous flow, hkproof.pipelines.discover.integral_bases). The orbit and this system are taken on a whole batch at
once (hkproof.dynamics.batch_map), projectively: a term of degree e in x at X / W is X^e W^(d-e) after clearing W^d.
The black box answers c_k / c_j mod p at each point, None where the orbit or the system is singular mod p there.
"""
from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from hkproof import budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.monomials import Exponents
from hkproof.algebra.reconstruction import memoized_values
from hkproof.dynamics.batch_map import BatchKahanMap, mulmod, power_table, solve_projective
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError

__all__ = ["KernelBlackBox", "basis_terms"]

Terms = tuple[tuple[int, tuple[int, ...]], ...]     # (integer coefficient, exponents over the ring's names)

_WORKER_MAPS: dict[tuple[QuadraticField, int], BatchKahanMap] = {}    # a worker process's batch maps, by prime
# a process's kernel vectors mod p, by basis and prime, then by point: the coordinates of one basis, rebuilt with equal
# seeds (hkproof.algebra.sparse_reconstruction), probe the same points and pay for each once
_KERNELS: dict[tuple, dict[tuple[int, ...], tuple[int, ...] | None]] = {}
KERNELS_KEPT = 1 << 19
"""Kernel vectors a process keeps, about 100 MB for bases of five functions (all of them dropped before a call whose
points could pass this)."""


def basis_terms(kmap: KahanMap, phi: Exponents | Frac) -> Terms:
    """A basis function as integer terms over the ring's names: x^e for a monomial, the numerator of a polynomial."""
    names = kmap.ring.names
    if isinstance(phi, Frac):
        if not phi.den.is_one():
            raise HKProofError(f"a basis function of the black box must be a polynomial, got {phi}")
        return tuple((int(c), tuple(int(e) for e in m)) for m, c in phi.num.to_dict().items())
    full = [0] * len(names)
    for v, e in zip(kmap.variables, phi, strict=True):
        full[names.index(v)] = e
    return ((1, tuple(full)),)


class KernelBlackBox:
    """c_k / c_j of the kernel of `basis` (its last element normalized by c_l = -1), as a function of the names
    `inputs` (the other ring names fixed to `fixed`), evaluated mod primes below 2^50 on batches of points."""

    def __init__(self, kmap: KahanMap, basis: Sequence[Exponents | Frac], k: int, j: int, inputs: Sequence[str],
                 fixed: Mapping[str, int] | None = None):
        self.kmap, self.k, self.j = kmap, k, j
        self.basis = [basis_terms(kmap, phi) for phi in basis]
        self.inputs, self.fixed = list(inputs), dict(fixed or {})
        missing = set(kmap.ring.names) - set(self.inputs) - set(self.fixed)
        if missing:
            raise ValueError(f"no value for {sorted(missing)}")
        names = kmap.ring.names
        self.phase = [names.index(v) for v in kmap.variables]
        self.controls = [i for i in range(len(names)) if i not in self.phase]
        terms = [t for phi in self.basis for t in phi]
        self.degree = max(sum(m[i] for i in self.phase) for _, m in terms)
        self.control_degree = max((m[i] for _, m in terms for i in self.controls), default=0)
        # every term of every basis function as rows of exponent arrays: a row of the system is then a few products
        # of (terms x points) arrays, one per variable, not a product per term and variable
        self._phase_exponents = np.array([[m[q] for q in self.phase] for _, m in terms], dtype=np.int64)
        self._control_exponents = np.array([[m[q] for q in self.controls] for _, m in terms], dtype=np.int64)
        self._homogenizing = self.degree - self._phase_exponents.sum(axis=1)
        self._coefficients = [c for c, _ in terms]
        ends = np.cumsum([len(phi) for phi in self.basis])
        self._slices = list(zip([0, *ends[:-1]], ends, strict=True))
        self._maps: dict[int, BatchKahanMap] = {}
        self.probes = 0
        self._memo_key = (kmap.field, tuple(self.basis), tuple(self.inputs), tuple(sorted(self.fixed.items())))

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
        names = self.kmap.ring.names
        c_pow = {i: np.stack(power_table(values[names[i]], self.control_degree, p)) for i in self.controls}
        coefficients = np.array([c % p for c in self._coefficients], dtype=np.int64)[:, None]
        for i, (xs, w) in enumerate(orbit[:l - 1]):
            budget.check("evaluating the functions of a basis along orbits mod p")     # l - 1 rows of l functions
            ok &= w != 0
            terms = np.stack(power_table(w, self.degree, p))[self._homogenizing]      # (terms, points)
            if (coefficients != 1).any():
                terms = mulmod(terms, coefficients, p)
            for col, x in enumerate(xs):
                if self._phase_exponents[:, col].any():
                    powers = np.stack(power_table(x, self.degree, p))
                    terms = mulmod(terms, powers[self._phase_exponents[:, col]], p)
            for col, q in enumerate(self.controls):
                if self._control_exponents[:, col].any():
                    terms = mulmod(terms, c_pow[q][self._control_exponents[:, col]], p)
            for c, (start, stop) in enumerate(self._slices):
                rows[:, i, c] = _sum_mod(terms[start:stop], p)
        nums, den = solve_projective(rows, p)
        ok &= den != 0
        self.probes += count
        return [nums[:, c] for c in range(l - 1)] + [(p - den) % p], ok

    def kernels(self, p: int, points: Sequence[Sequence[int]]) -> list[tuple[int, ...] | None]:
        """The kernel vector (projectively, as `vectors`) at each point, None where it is undefined mod p; each point
        computed once per process for every black box of the same basis (_KERNELS)."""
        if sum(map(len, _KERNELS.values())) + len(points) > KERNELS_KEPT:
            _KERNELS.clear()

        def compute(missing: list[tuple[int, ...]]) -> list[tuple[int, ...] | None]:
            coords, ok = self.vectors(p, missing)
            return [tuple(c) if good else None
                    for c, good in zip(np.stack(coords, axis=1).tolist(), ok.tolist(), strict=True)]
        return memoized_values(_KERNELS.setdefault((self._memo_key, p), {}), points, compute)

    def __call__(self, p: int, points: Sequence[Sequence[int]]) -> list[list[int] | None]:
        """[c_k / c_j] mod p at each point (None where undefined mod p): the black box of
        hkproof.algebra.reconstruction, one function."""
        out: list[list[int] | None] = []
        for c in self.kernels(p, points):
            if c is None or c[self.j] == 0:
                out.append(None)
            else:
                out.append([c[self.k] * pow(c[self.j], -1, p) % p])
        return out


def _sum_mod(block: np.ndarray, p: int) -> np.ndarray:
    """The column sums of residues mod p < 2^50, in chunks of 2^13 rows (each chunk's sum fits in int64)."""
    total = np.zeros(block.shape[1], dtype=np.int64)
    for start in range(0, len(block), 1 << 13):
        total = (total + block[start:start + (1 << 13)].sum(axis=0) % p) % p
    return total

