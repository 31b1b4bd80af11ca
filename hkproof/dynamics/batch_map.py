"""The Kahan map on many points at once, modulo a prime below 2^50, projectively and without a single division.

A point x = X / W goes to X~ = N, W~ = D with M'(X, W) N = D b'(X, W), where M' = M0 W + sum_k X_k M_k and
b' = b0 W + B X are the matrix form of eq. "Kahan gen" cleared of W (M and b are affine in x), and (N, D) comes from
a division-free elimination. eps and the parameters may differ from point to point. numpy int64 arrays hold the
residues; a product of two residues is reduced with a floating-point quotient and an exact correction in wrapping
64-bit arithmetic (`mulmod`: exact for p < 2^50). A point where D = 0 mod p is reported, not guessed.
This is the fast black box behind sparse reconstruction; `KahanMap.mod` is the one-point modular map.
"""
from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from hkproof import budget
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError

__all__ = ["MAX_BATCH_PRIME", "BatchKahanMap", "dotmod", "Projective", "mulmod", "mulmod_sum", "power_table",
           "solve_projective"]

MAX_BATCH_PRIME = 2**50
Array = np.ndarray
Projective = tuple[list[Array], Array]      # (X_1..X_n, W): the points X / W of a batch


def mulmod(a: Array, b: Array, p: int) -> Array:
    """a * b mod p elementwise for residues in [0, p), p < 2^50 (`mulmod_sum` of one product).

    >>> p = 2**50 - 27
    >>> int(mulmod(np.array([p - 1]), np.array([p - 2]), p)[0]) == (p - 1) * (p - 2) % p
    True
    """
    return mulmod_sum(((a, b),), p)


def mulmod_sum(products: Sequence[tuple[Array | int, Array]], p: int) -> Array:
    """sum a_i * b_i mod p elementwise for a few pairs of residues in [0, p] (p itself stands for 0), p < 2^50,
    finished by `_remainder` (for the short arrays of sparse reconstruction every numpy call costs microseconds:
    5 + 5 per pair calls, not 7 per pair and 2 per sum). One of each pair must be an array: numpy wraps integer
    arrays silently, and an errstate context around the product cost more than the product here."""
    inverse = 1.0 / p
    (a, b), *rest = products
    r = a * b
    q = (a * inverse) * b
    for a, b in rest:
        r = r + a * b
        q = q + (a * inverse) * b
    return _remainder(r, q, p)


def dotmod(a: Array, b: Array, p: int) -> Array:
    """sum_k a[..., k] * b[..., k] mod p for residues in [0, p], p < 2^50: 64 products at a time, each chunk
    finished by `_remainder` (the float64 quotient of such a sum is off by less than 2^10)."""
    total = None
    for start in range(0, max(a.shape[-1], b.shape[-1]), 64):
        x, y = a[..., start:start + 64], b[..., start:start + 64]
        r = _remainder((x * y).sum(axis=-1), ((x * (1.0 / p)) * y).sum(axis=-1), p)
        total = r if total is None else (total + r) % p
    return total if total is not None else np.zeros(np.broadcast_shapes(a.shape, b.shape)[:-1], dtype=np.int64)


def _remainder(exact: Array, quotient: Array, p: int) -> Array:
    """S mod p from `exact`, S wrapped to int64, and `quotient`, a float64 estimate of S / p off by less than 2^12:
    S - floor(quotient) p is exact in wrapping int64 arithmetic and within 2^13 p of [0, p) (inside int64 for
    p < 2^50), so one floor remainder finishes."""
    exact -= quotient.astype(np.int64) * p
    return exact % p


def solve_projective(ab: Array, p: int) -> tuple[Array, Array]:
    """(N, D) with A N = D b mod p for a batch of square systems given as [A | b] of shape (B, n, n + 1), by
    division-free elimination and back substitution over a common denominator; D = 0 where A is singular mod p (or
    an unlucky pivot vanished)."""
    count, n = ab.shape[:2]
    ab = ab.copy()
    for k in range(n):          # every row below the pivot at once: O(n) array operations, each on O(n^2) entries
        budget.check("solving a batch of kernel systems mod p")
        ab[:, k + 1:, k:] = mulmod_sum(((ab[:, k, k, None, None], ab[:, k + 1:, k:]),
                                        (p - ab[:, k + 1:, k, None], ab[:, k, None, k:])), p)
    z = np.zeros((count, n + 1), dtype=np.int64)     # (N_1, ..., N_n, -D): row j reads sum_k ab[j, k] z_k = 0
    z[:, n] = p - 1
    for j in range(n - 1, -1, -1):
        budget.check("solving a batch of kernel systems mod p")
        acc = (p - dotmod(ab[:, j, j + 1:], z[:, j + 1:], p)) % p
        z[:, j + 1:] = mulmod(z[:, j + 1:], ab[:, j, j, None], p)
        z[:, j] = acc
    return z[:, :n], (p - z[:, n]) % p


def power_table(values: Array, top: int, p: int) -> list[Array]:
    """[v^0, v^1, ..., v^top] mod p, elementwise."""
    out = [np.ones_like(values)]
    for _ in range(top):
        out.append(mulmod(out[-1], values, p))
    return out


class BatchKahanMap:
    """f(., eps) on batches of points mod p (p < 2^50); every ring name (phase variables, eps, parameters) has one
    residue per point."""

    def __init__(self, kmap: KahanMap, p: int):
        if not 2 < p < MAX_BATCH_PRIME:
            raise HKProofError(f"the batch map works modulo a prime below 2^50, got {p}")
        self.kmap, self.p = kmap, p
        self.controls = kmap.field.control_names
        m_parts, b_parts = kmap.affine_matrix
        idx = [kmap.ring.index(c) for c in self.controls]
        self.degrees = [0] * len(self.controls)

        def compile_part(poly) -> tuple[tuple[int, tuple[int, ...]], ...]:
            terms = []
            for mono, c in poly.to_dict().items():
                exps = tuple(int(mono[i]) for i in idx)
                self.degrees = [max(d, e) for d, e in zip(self.degrees, exps, strict=True)]
                terms.append((int(c) % p, exps))
            return tuple(terms)

        # the parts of [M | b] that are not zero, entry by entry (row-major): (entry, 0 for W or k + 1 for X_k, terms)
        self.n = n = len(kmap.variables)
        rows = [[*m_parts[i], b_parts[i]] for i in range(n)]
        self._parts = [(i * (n + 1) + j, 0 if k is None else k + 1, compile_part(poly))
                       for i in range(n) for j in range(n + 1) for k, poly in sorted(
                           rows[i][j].items(), key=lambda kv: -1 if kv[0] is None else kv[0]) if not poly.is_zero()]
        self._variable_of_part = np.array([v for _, v, _ in self._parts], dtype=np.int64)
        self._entries = np.array(sorted({e for e, _, _ in self._parts}), dtype=np.int64)
        self._entry_starts = np.searchsorted([e for e, _, _ in self._parts], self._entries)

    def coefficients(self, values: Mapping[str, Array]) -> Array:
        """The non-zero parts of [M | b] (as affine functions of W, X_1, ..., X_n) at each point's eps and
        parameters: an array of shape (points, parts), residues mod p."""
        p = self.p
        count = len(next(iter(values.values())))
        powers = [power_table(np.asarray(values[c], dtype=np.int64) % p, d, p)
                  for c, d in zip(self.controls, self.degrees, strict=True)]

        def evaluate(terms) -> Array:
            total = np.zeros(count, dtype=np.int64)
            for c, exps in terms:
                term = np.full(count, c, dtype=np.int64)
                for table, e in zip(powers, exps, strict=True):
                    if e:
                        term = mulmod(term, table[e], p)
                total = (total + term) % p
            return total
        return np.stack([evaluate(terms) for _, _, terms in self._parts], axis=1).reshape(count, len(self._parts))

    def step(self, point: Projective, coefficients: Array) -> Projective:
        """One step X / W -> N / D; D = 0 marks points where det M(x) = 0 mod p (or W was 0)."""
        xs, w = point
        p, n = self.p, self.n
        count = len(w)
        products = mulmod(coefficients, np.stack([w, *xs], axis=1)[:, self._variable_of_part], p)
        ab = np.zeros((count, n * (n + 1)), dtype=np.int64)
        ab[:, self._entries] = np.add.reduceat(products, self._entry_starts, axis=1) % p    # n + 1 parts at most
        nums, den = solve_projective(ab.reshape(count, n, n + 1), p)
        return [nums[:, k] for k in range(n)], den * (w != 0)

    def orbit(self, values: Mapping[str, Array], steps: int) -> list[Projective]:
        """x, f(x), ..., f^steps(x) for a batch (values: one residue per point for every ring name)."""
        coefficients = self.coefficients(values)
        x: Projective = ([np.asarray(values[v], dtype=np.int64) % self.p for v in self.kmap.variables],
                         np.ones(len(next(iter(values.values()))), dtype=np.int64))
        out = [x]
        for _ in range(steps):
            x = self.step(x, coefficients)
            out.append(x)
        return out
