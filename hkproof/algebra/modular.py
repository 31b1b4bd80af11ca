"""Arithmetic modulo a word-size prime: random primes, residues of rationals, ranks, kernels and solves (nmod_mat).

Every modular computation of hkproof (screening, degrees, Darboux searches, reconstruction) uses these; a rank mod p
is a lower bound of the rank over Q, which is what makes a modular screen exact in one direction.

>>> residue(flint.fmpq(1, 3), 7), residue_or_none(flint.fmpq(1, 7), 7)
(5, None)
>>> rank_mod_p([[1, 2], [2, 4]], 7), kernel_mod_p([[1, 2], [2, 4]], 7)
(1, [[2, 6]])
"""
from __future__ import annotations

import random
from typing import Sequence, cast

import flint
import numpy as np

from hkproof.algebra.monomials import Exponents, columns_mod_p, exponents_upto, value_mod_p
from hkproof.errors import UnluckyPrimeError

__all__ = ["EchelonModP", "free_kernel_mod_p", "kernel_mod_p", "nmod_matrix", "polynomial_mod_p", "random_prime",
           "rank_mod_p", "rational_fit_mod_p", "residue", "residue_or_none", "solve_mod_p"]

Rows = Sequence[Sequence[int]] | np.ndarray      # integer rows, or a numpy array of them


def random_prime(rng: random.Random, bits: int = 62) -> int:
    """A random prime of exactly `bits` bits (nmod types take moduli below 2^64)."""
    while True:
        n = flint.fmpz(rng.getrandbits(bits) | (1 << (bits - 1)) | 1)
        if n.is_prime():
            return int(n)


def residue_or_none(q: flint.fmpq | flint.fmpz | int, p: int) -> int | None:
    """q mod p, or None when p divides its denominator."""
    if isinstance(q, (int, flint.fmpz)):
        return int(q) % p
    den = int(q.q) % p
    return None if den == 0 else int(q.p) * pow(den, -1, p) % p


def residue(q: flint.fmpq | flint.fmpz | int, p: int) -> int:
    """q mod p; UnluckyPrimeError when p divides its denominator (another prime will do)."""
    r = residue_or_none(q, p)
    if r is None:
        raise UnluckyPrimeError(f"the denominator of {q} is divisible by p = {p}")
    return r


class EchelonModP:
    """Rows added one at a time, kept as an echelon basis mod `prime`: one row reduction per row tells whether
    the rank mod p grew (a lower bound of the rank over Q at every prefix; a row with a denominator divisible by p
    counts as not raising it)."""

    def __init__(self, prime: int = 2 ** 61 - 1) -> None:
        self.prime = prime
        self._basis: list[tuple[int, list[int]]] = []    # (pivot column, row with 1 there)

    @property
    def rank(self) -> int:
        return len(self._basis)

    def add(self, row: Sequence[flint.fmpq | flint.fmpz | int]) -> bool:
        """Add `row`; whether the rank mod p grew."""
        p = self.prime
        v = [residue_or_none(x, p) for x in row]
        if any(x is None for x in v):
            return False
        w = cast(list[int], v)
        for col, b in self._basis:
            c = w[col]
            if c:
                w = [(x - c * y) % p for x, y in zip(w, b)]
        lead = next((j for j, x in enumerate(w) if x), None)
        if lead is None:
            return False
        inverse = pow(w[lead], -1, p)
        self._basis.append((lead, [x * inverse % p for x in w]))
        return True


def rank_mod_p(rows: Sequence[Sequence[int]], p: int) -> int:
    """The rank over Z/p of integer rows (0 for no rows)."""
    if not rows:
        return 0
    return flint.nmod_mat([[int(v) % p for v in r] for r in rows], p).rank()


def nmod_matrix(rows: Rows, p: int) -> flint.nmod_mat:
    """The rows (lists of integers, or a numpy array of residues) as an nmod_mat. Lists go to FLINT's constructor at
    once (1.5-1.9 times faster than filling entries one by one); a numpy array is filled one row at a time, since a
    list of lists of all its entries as Python ints costs eight times the matrix (11 GB for a 12 900 x 12 900
    block)."""
    if not len(rows):
        return flint.nmod_mat(0, 0, p)
    if not isinstance(rows, np.ndarray):
        try:
            return flint.nmod_mat([row.tolist() if isinstance(row, np.ndarray) else list(row) for row in rows], p)
        except TypeError:       # entries FLINT does not take as they are (numpy scalars): one by one below
            pass
    matrix = flint.nmod_mat(len(rows), len(rows[0]), p)
    for i, row in enumerate(rows):
        for j, v in enumerate(row.tolist() if hasattr(row, "tolist") else row):
            if v:
                matrix[i, j] = int(v) % p
    return matrix


def free_kernel_mod_p(rows: Rows, p: int, free_value: int = -1) -> list[tuple[int, list[int]]]:
    """A basis of the right kernel mod p from the reduced row echelon form, one vector per free column: that column
    set to `free_value` (recipe (B)'s normalization -1 by default), the other free columns 0; (free column, vector).
    The rows may be a numpy array."""
    if not len(rows):
        return []
    r, rank = nmod_matrix(rows, p).rref()
    ncols = r.ncols()
    pivots: list[int] = []
    j = 0
    for i in range(rank):
        while int(r[i, j]) == 0:
            j += 1
        pivots.append(j)
    scale = free_value % p
    out = []
    for free in (j for j in range(ncols) if j not in pivots):
        v = [0] * ncols
        v[free] = scale
        for i, pj in enumerate(pivots):
            v[pj] = -int(r[i, free]) * scale % p
        out.append((free, v))
    return out


def kernel_mod_p(rows: Sequence[Sequence[int]], p: int, free_value: int = -1) -> list[list[int]]:
    """A basis of the right kernel mod p (free columns set to `free_value`, -1 by default)."""
    return [v for _, v in free_kernel_mod_p(rows, p, free_value)]


def solve_mod_p(matrix: Sequence[Sequence[int]], rhs: Sequence[int], p: int) -> list[int] | None:
    """The solution of a square system mod p, None when it is singular mod p."""
    try:
        sol = flint.nmod_mat([[int(v) % p for v in r] for r in matrix], p).solve(
            flint.nmod_mat([[int(v) % p] for v in rhs], p))
    except ZeroDivisionError:
        return None
    return [int(sol[i, 0]) for i in range(len(rhs))]


SparseMod = dict[Exponents, int]      # a polynomial mod p: exponents -> coefficient


def polynomial_mod_p(part: SparseMod, x: Sequence[int], p: int) -> int:
    """The value of a sparse polynomial mod p at x."""
    return sum(c * value_mod_p(m, x, p) for m, c in part.items()) % p


def rational_fit_mod_p(values: Sequence[int], points: Sequence[Sequence[int]], degrees: tuple[int, int], p: int
                       ) -> tuple[SparseMod, SparseMod] | None:
    """N, D of total degrees <= `degrees` with values * D = N at every point mod p (the dense ansatz, D normalized by
    its first non-zero monomial), or None unless the solution is unique up to scale.

    >>> rational_fit_mod_p([(2 * x + 1) * pow(x + 3, -1, 101) % 101 for x in range(1, 6)], [[x] for x in range(1, 6)],
    ...                    (1, 1), 101)
    ({(1,): 2, (0,): 1}, {(1,): 1, (0,): 3})
    """
    n = len(points[0]) if points else 0
    n_monos, d_monos = exponents_upto(n, degrees[0]), exponents_upto(n, degrees[1])
    columns = columns_mod_p(n_monos, points, p) + [[(p - y) * v % p for y, v in zip(values, column, strict=True)]
                                                   for column in columns_mod_p(d_monos, points, p)]
    rows = [list(row) for row in zip(*columns)]
    solutions = free_kernel_mod_p(rows, p, free_value=1)
    if len(solutions) != 1:
        return None
    vec = solutions[0][1]
    num, den = vec[:len(n_monos)], vec[len(n_monos):]
    lead = next((c for c in den if c), 0)
    if not lead:
        return None
    inv = pow(lead, -1, p)
    return ({m: c * inv % p for m, c in zip(n_monos, num, strict=True) if c},
            {m: c * inv % p for m, c in zip(d_monos, den, strict=True) if c})
