"""The bivectors Q/D fixed by the flow of a linear symmetry, as a basis over Z on a block's columns (issue 38).

With A x commuting with the field and X(D) = chi D for X = A x, the flow exp(tA) maps invariant bivectors of the class
Q/D to invariant ones, and L_X (Q/D) = ((L_X - chi) Q) / D, with the Lie derivative of a bivector

    (L_X Q)^ij = X(Q^ij) - sum_k A_ik Q^kj - sum_k A_jk Q^ik.

When the torus' weights show a class's kernel in weight 0 only, every invariant bivector of the class is fixed by the
flow, so the kernel lies in ker(L_X - chi) on the columns: an exact nullspace over Q (integer operator, free of eps and
the parameters), computed on the connected pieces of the operator (columns that share an image monomial). The search
then solves for coordinates on this basis (the Gaudin magnet at degree 6: 2 110 coordinates instead of 6 920 columns),
in the field's own coordinates, so that the kernel is rebuilt over Q(eps, parameters) as in the plain search.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import flint
import numpy as np

from hkproof.algebra.linalg import nullspace_q, primitive_vector
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.poisson import pairs
from hkproof.hk.poisson_system import Block, SignSymmetry

__all__ = ["FixedColumns", "commutes_with_signs", "fixed_columns"]

Term = tuple[int, int]          # (column of the block, integer coefficient)


@dataclass(frozen=True)
class FixedColumns:
    """A basis over Z of ker(L_X - chi) on the block's columns: each vector a tuple of (column, coefficient), its free
    column first (where the nullspace's reduced form puts 1 and every other vector 0)."""
    block: Block
    vectors: tuple[tuple[Term, ...], ...]

    def __len__(self) -> int:
        return len(self.vectors)

    def project(self, rows: np.ndarray, p: int) -> np.ndarray:
        """The rows on the basis: rows . N mod p (p < 2^31: each product and sum of two stays in int64)."""
        out = np.zeros((rows.shape[0], len(self.vectors)), dtype=np.int64)
        for b, vector in enumerate(self.vectors):
            column = np.zeros(rows.shape[0], dtype=np.int64)
            for c, k in vector:
                column = (column + rows[:, c] * (k % p)) % p
            out[:, b] = column
        return out

    def coordinates(self, vector: Sequence[int], p: int) -> list[int] | None:
        """The coordinates mod p of a vector on the block's columns, None when it is not in the span."""
        coords = [int(vector[v[0][0]]) * pow(v[0][1], -1, p) % p for v in self.vectors]
        back = [0] * len(self.block.columns)
        for x, v in zip(coords, self.vectors, strict=True):
            for c, k in v:
                back[c] = (back[c] + x * k) % p
        return coords if all((a - int(b)) % p == 0 for a, b in zip(back, vector, strict=True)) else None


def commutes_with_signs(a: flint.fmpq_mat, symmetries: Sequence[SignSymmetry]) -> bool:
    """A S = S A for each sign symmetry S: then L_X keeps each character block."""
    n = a.nrows()
    return all(a[i, j] == 0 or s.signs[i] == s.signs[j] for s in symmetries for i in range(n) for j in range(n))


def fixed_columns(kmap: KahanMap, block: Block, a: flint.fmpq_mat, chi: flint.fmpq) -> FixedColumns:
    """ker(L_X - chi) on the block's columns over Q, X = A x (the module docstring), as primitive integer vectors."""
    n = len(kmap.variables)
    scale = math.lcm(*(int(e.q) for e in a.entries()), int(chi.q))
    ai = [[int(a[i, j] * scale) for j in range(n)] for i in range(n)]
    c0 = int(chi * scale)
    index = {pair: k for k, pair in enumerate(pairs(n))}
    images: list[dict[tuple[int, tuple[int, ...]], int]] = []
    for k, m in block.columns:
        image: dict[tuple[int, tuple[int, ...]], int] = {}

        def add(pair: tuple[int, int], mono: tuple[int, ...], c: int) -> None:
            i, j = pair
            if i == j or not c:
                return
            key = (index[(min(i, j), max(i, j))], mono)
            image[key] = image.get(key, 0) + (c if i < j else -c)
        i, j = pairs(n)[k]
        for l in range(n):                           # X(x^m) = sum_l (A x)_l d_l x^m
            if m[l]:
                for r in range(n):
                    if ai[l][r]:
                        mono = list(m)
                        mono[l] -= 1
                        mono[r] += 1
                        add((i, j), tuple(mono), ai[l][r] * m[l])
        for r in range(n):                           # - A_ri e_r ^ e_j - A_rj e_i ^ e_r: the pair (i, j) moved
            add((r, j), m, -ai[r][i])
            add((i, r), m, -ai[r][j])
        add((i, j), m, -c0)
        images.append({key: c for key, c in image.items() if c})
    vectors: list[tuple[Term, ...]] = []
    for piece in _pieces(images):
        keys = sorted({key for c in piece for key in images[c]})
        rows = [[images[c].get(key, 0) for c in piece] for key in keys] if keys else [[0] * len(piece)]
        for v in nullspace_q(rows):
            free = max(t for t in range(len(v)) if v[t] != 0)    # reduced form: the pivots come before it
            w = primitive_vector(v)
            terms = [(piece[t], int(w[t])) for t in range(len(v)) if w[t]]
            terms.sort(key=lambda term: term[0] != piece[free])
            vectors.append(tuple(terms))
    return FixedColumns(block, tuple(vectors))


def _pieces(images: Sequence[dict]) -> list[list[int]]:
    """The columns grouped into connected pieces: two columns meet when their images share a key."""
    parent = list(range(len(images)))

    def root(c: int) -> int:
        while parent[c] != c:
            parent[c] = parent[parent[c]]
            c = parent[c]
        return c
    owner: dict = {}
    for c, image in enumerate(images):
        for key in image:
            if key in owner:
                parent[root(c)] = root(owner[key])
            else:
                owner[key] = c
    groups: dict[int, list[int]] = {}
    for c in range(len(images)):
        groups.setdefault(root(c), []).append(c)
    return list(groups.values())
