"""Continuous linear symmetries of a quadratic field and eigen-coordinates of one of them mod p (issue 38).

A linear vector field A x with [A x, F] = 0 (DF(x) A x = A F(x) identically) has a flow exp(tA) that commutes with F,
hence with its Kahan map (the discretization is equivariant under every linear map that commutes with F); so the Lie
derivative L_A maps invariant bivectors Q/D to invariant ones when D is semi-invariant (grad D . A x = c D). When A
is diagonalizable, L_A is diagonal on the bivectors y^m e_a ^ e_b of eigen-coordinates y = T x, with the weight
sum_c m_c l_c - l_a - l_b, and the invariant bivectors split by weights: each weight is searched or excluded on its
own columns. The Gaudin magnet's rotation about the field axis (eigenvalues 0, +-i) splits its 25 740 columns of
degree 7 into 19 weights instead of 2 sign characters. Mod p (p = 1 mod 4 for +-i) the weights are residues; distinct
eigenvalues stay distinct mod p, so the eigenvectors mod p are reductions of eigenvectors over the number field.
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass
from typing import Sequence

import flint

from hkproof.algebra.linalg import lcm, nullspace_q
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap

__all__ = ["Torus", "commuting_linear_fields", "eigen_coordinates", "generic_generator", "is_semi_invariant",
           "semi_invariance_character", "squarefree_charpoly", "torus_data"]


def commuting_linear_fields(field: QuadraticField) -> list[flint.fmpq_mat]:
    """A basis of the matrices A with DF(x) A x = A F(x) identically in x and the parameters (exact nullspace)."""
    ring, xs = field.ring, list(field.variables)
    n = len(xs)
    common = lcm([f.den for f in field.rhs])
    if any(common.degrees()[ring.index(v)] for v in xs):
        return []                                   # a field with x in a denominator: not searched
    rhs = [f.num * (common / f.den) for f in field.rhs]
    columns: list[dict[tuple[int, tuple[int, ...]], int]] = []
    for k in range(n):
        for m in range(n):                          # E_km: (E_km x)_j = delta_jk x_m
            residual = [rhs[i].derivative(ring.index(xs[k])) * ring.gen(xs[m]) - (rhs[m] if i == k else 0)
                        for i in range(n)]
            columns.append({(i, tuple(e)): int(c) for i, r in enumerate(residual) for e, c in r.to_dict().items()})
    keys = sorted({key for col in columns for key in col})
    if not keys:
        return []
    return [flint.fmpq_mat(n, n, v) for v in nullspace_q([[col.get(key, 0) for col in columns] for key in keys])]


def squarefree_charpoly(a: flint.fmpq_mat) -> flint.fmpq_poly:
    """The squarefree part of the characteristic polynomial of A over Q."""
    c = a.charpoly()
    return c / c.gcd(c.derivative())


@dataclass(frozen=True)
class Torus:
    """y = T x mod p with T A = diag(weights) T: eigen-coordinates mod `prime` of the symmetry generator A."""
    generator: flint.fmpq_mat
    prime: int
    rows: tuple[tuple[int, ...], ...]
    inverse: tuple[tuple[int, ...], ...]
    weights: tuple[int, ...]


def eigen_coordinates(a: flint.fmpq_mat, p: int) -> Torus | None:
    """T mod p with T A = diag(l) T and T invertible, when A is diagonalizable over Q-bar (the squarefree part s of its
    characteristic polynomial kills it) and s has deg s distinct roots mod p; None otherwise."""
    n = a.nrows()
    s = squarefree_charpoly(a)
    if s.degree() < 2 or any(c.q % p == 0 for c in a.entries()):
        return None                                 # one eigenvalue (A scalar): no splitting
    value, power = flint.fmpq_mat(n, n), flint.fmpq_mat(n, n, [int(i == j) for i in range(n) for j in range(n)])
    for c in s.coeffs():                            # s(A) = sum c_k A^k
        value, power = value + power * c, power * a
    if any(e != 0 for e in value.entries()):
        return None                                 # not diagonalizable over Q-bar
    numer, denom = s.numer(), s.denom()
    if denom % p == 0:
        return None
    reduced = flint.nmod_poly([int(c) % p for c in numer.coeffs()], p)
    roots: list[int] = [int(r) for r, _ in reduced.roots()]
    if len(roots) != s.degree():
        return None
    am = flint.nmod_mat([[int(e.p) * pow(int(e.q), -1, p) % p for e in row] for row in _rows(a)], p)
    rows: list[list[int]] = []
    weights: list[int] = []
    for lam in roots:
        shifted = am.transpose() - flint.nmod_mat(n, n, [lam * (i == j) for i in range(n) for j in range(n)], p)
        kernel, dim = shifted.nullspace()
        for col in range(dim):
            rows.append([int(kernel[r, col]) for r in range(n)])
            weights.append(lam)
    if len(rows) != n:
        return None
    t = flint.nmod_mat(rows, p)
    if t.det() == 0:
        return None
    inv = t.inv()
    return Torus(a, p, tuple(tuple(r) for r in rows), tuple(tuple(int(inv[i, j]) for j in range(n)) for i in range(n)),
                 tuple(weights))


def torus_data(torus: Torus) -> dict[str, list]:
    """The torus as JSON: the generator A (rational entries as text), T mod p (rows) and the weights mod p."""
    return {"generator": [[str(e) for e in row] for row in _rows(torus.generator)],
            "rows": [list(r) for r in torus.rows], "weights": list(torus.weights)}


def _rows(a: flint.fmpq_mat) -> list[list[flint.fmpq]]:
    n = a.ncols()
    entries = a.entries()
    return [list(entries[i * n:(i + 1) * n]) for i in range(a.nrows())]


def generic_generator(basis: Sequence[flint.fmpq_mat], rng: random.Random) -> flint.fmpq_mat | None:
    """A random integer combination of the basis (a generic element separates the weights of a torus), or None."""
    if not basis:
        return None
    out = basis[0] * 0
    for b in basis:
        out += b * rng.randint(1, 97)
    return out


def is_semi_invariant(kmap: KahanMap, a: flint.fmpq_mat, d: flint.fmpz_mpoly) -> bool:
    """grad D . (A x) = c D with c a rational constant: then L_A keeps the class Q/D."""
    return semi_invariance_character(kmap, a, d) is not None


def semi_invariance_character(kmap: KahanMap, a: flint.fmpq_mat, d: flint.fmpz_mpoly) -> flint.fmpq | None:
    """chi with grad D . (A x) = chi D, exactly; None when D is not semi-invariant."""
    ring, xs = kmap.ring, list(kmap.variables)
    scale = math.lcm(*(int(e.q) for e in a.entries()))
    moved = ring.constant(0)
    for i, v in enumerate(xs):
        ax = sum((ring.gen(xs[j]) * int(a[i, j] * scale) for j in range(len(xs))), ring.constant(0))
        moved += d.derivative(ring.index(v)) * ax
    if moved.is_zero():
        return flint.fmpq(0)
    if moved * d.leading_coefficient() != d * moved.leading_coefficient():
        return None
    return flint.fmpq(int(moved.leading_coefficient()), int(d.leading_coefficient())) / scale
