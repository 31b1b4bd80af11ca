"""The Kahan map on many points at once, modulo a prime below 2^50, projectively and without a single division.

A point x = X / W goes to X~ = N, W~ = D with M'(X, W) N = D b'(X, W), where M' = M0 W + sum_k X_k M_k and
b' = b0 W + B X are the matrix form of eq. "Kahan gen" cleared of W (M and b are affine in x), and (N, D) comes from
a division-free elimination. eps and the parameters may differ from point to point. numpy int64 arrays hold the
residues; a product of two residues is reduced with a floating-point quotient and an exact correction in wrapping
64-bit arithmetic (`mulmod`: exact for p < 2^50). A point where D = 0 mod p is reported, not guessed.
This is the fast black box behind sparse reconstruction; `KahanMap.mod` is the one-point modular map.
"""
from __future__ import annotations

from typing import Mapping

import numpy as np

from hkproof import budget
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError

__all__ = ["MAX_BATCH_PRIME", "BatchKahanMap", "Projective", "mulmod", "power_table", "solve_projective"]

MAX_BATCH_PRIME = 2**50
Array = np.ndarray
Projective = tuple[list[Array], Array]      # (X_1..X_n, W): the points X / W of a batch


def mulmod(a: Array, b: Array, p: int) -> Array:
    """a * b mod p elementwise for residues in [0, p), p < 2^50: the quotient from float64 (off by at most one), so
    a * b - q p, exact in wrapping int64 arithmetic, lies in (-p, 2p) and one floor remainder finishes (for the short
    arrays of sparse reconstruction every numpy call costs microseconds: four calls, not eight). At least one of a, b
    must be an array: numpy wraps integer arrays silently, and an errstate context around the product cost more
    than the product on these arrays.

    >>> p = 2**50 - 27
    >>> int(mulmod(np.array([p - 1]), np.array([p - 2]), p)[0]) == (p - 1) * (p - 2) % p
    True
    """
    r = a * b
    r -= (a * (1.0 / p) * b).astype(np.int64) * p
    return r % p


def solve_projective(a: Array, b: Array, p: int) -> tuple[Array, Array]:
    """(N, D) with A N = D b mod p for a batch of square systems, A of shape (B, n, n) and b of shape (B, n), by
    division-free elimination and back substitution over a common denominator; D = 0 where A is singular mod p
    (or an unlucky pivot vanished)."""
    a, b = a.copy(), b.copy()
    count, n, _ = a.shape
    for k in range(n):          # every row below the pivot at once: O(n) array operations, each on O(n^2) entries
        budget.check("solving a batch of kernel systems mod p")
        pivot = a[:, k, k].copy()
        minus = (p - a[:, k + 1:, k]) % p
        a[:, k + 1:, k:] = (mulmod(pivot[:, None, None], a[:, k + 1:, k:], p)
                            + mulmod(minus[:, :, None], a[:, k, None, k:], p)) % p
        b[:, k + 1:] = (mulmod(pivot[:, None], b[:, k + 1:], p) + mulmod(minus, b[:, k, None], p)) % p
    nums = np.zeros((count, n), dtype=np.int64)
    den = np.ones(count, dtype=np.int64)
    for j in range(n - 1, -1, -1):
        budget.check("solving a batch of kernel systems mod p")
        acc = mulmod(b[:, j], den, p)
        if j + 1 < n:       # n - j - 1 residues below 2^50 per point: their sum fits in int64
            acc = (acc + mulmod((p - a[:, j, j + 1:]) % p, nums[:, j + 1:], p).sum(axis=1)) % p
        u = a[:, j, j]
        nums[:, j + 1:] = mulmod(nums[:, j + 1:], u[:, None], p)
        nums[:, j] = acc
        den = mulmod(den, u, p)
    return nums, den


def power_table(values: Array, top: int, p: int) -> list[Array]:
    """[v^0, v^1, ..., v^top] mod p, elementwise."""
    out = [np.ones_like(values)]
    for _ in range(top):
        out.append(mulmod(out[-1], values, p))
    return out


class BatchKahanMap:
    """f(., eps) on batches of points mod p (p < 2^31); every ring name (phase variables, eps, parameters) has one
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

        def compile_entry(entry: dict) -> dict:
            return {k: compile_part(poly) for k, poly in entry.items()}
        self.m_parts = [[compile_entry(e) for e in row] for row in m_parts]
        self.b_parts = [compile_entry(e) for e in b_parts]
        self.n = len(kmap.variables)

    def coefficients(self, values: Mapping[str, Array]) -> tuple[list[list[dict]], list[dict]]:
        """The pieces e0, e_k of every entry of M and b at each point's eps and parameters (arrays mod p)."""
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
        return ([[{k: evaluate(t) for k, t in entry.items()} for entry in row] for row in self.m_parts],
                [{k: evaluate(t) for k, t in entry.items()} for entry in self.b_parts])

    def step(self, point: Projective, coefficients: tuple[list[list[dict]], list[dict]]) -> Projective:
        """One step X / W -> N / D; D = 0 marks points where det M(x) = 0 mod p (or W was 0)."""
        xs, w = point
        p, n = self.p, self.n
        m_coef, b_coef = coefficients
        count = len(w)

        def affine(entry: dict) -> Array:
            total = mulmod(entry[None], w, p) if None in entry else np.zeros(count, dtype=np.int64)
            for k, c in entry.items():
                if k is not None:
                    total = (total + mulmod(c, xs[k], p)) % p
            return total
        a = np.empty((count, n, n), dtype=np.int64)
        for i in range(n):
            for j in range(n):
                a[:, i, j] = affine(m_coef[i][j])
        b = np.stack([affine(e) for e in b_coef], axis=1)
        nums, den = solve_projective(a, b, p)
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
