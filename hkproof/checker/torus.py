"""The checker's reading of a torus in an exclusion step (docs/certificates.md, "exclusion"): a linear symmetry A of
the field whose eigen-coordinates y = T x mod p split the columns of invariant bivectors by weight.

Checked here, each on its own: [A x, F] = 0 exactly (then exp(tA) commutes with F, hence with its Kahan map, and the
Lie derivative L_A maps invariant Q/D to invariant ones when grad D . A x = c D, also checked exactly); A is
diagonalizable over the algebraic numbers (s(A) = 0 for the squarefree part s of its characteristic polynomial); the
stated weights are deg s distinct roots of s mod p, so distinct eigenvalues stay distinct mod p and the eigenvectors
mod p reduce eigenvectors over a number field; T A = diag(weights) T mod p with T invertible mod p. Then an invariant
Q != 0 has a non-zero part of one weight, and a full column rank mod p on the columns of each weight (in y) excludes it.
"""
from __future__ import annotations

from typing import Any

import flint

from hkproof.algebra.formula import parse_rational
from hkproof.algebra.fraction import Frac
from hkproof.checker.kahan import KahanData
from hkproof.checker.reading import get, integers
from hkproof.errors import CertificateError, Refutation

__all__ = ["CheckedTorus", "read_torus"]


class CheckedTorus:
    """T and T^-1 mod p and the weights, after every condition of the module docstring held."""

    def __init__(self, rows: list[list[int]], inverse: list[list[int]], weights: list[int], p: int,
                 generator: list[list[flint.fmpq]], chi: flint.fmpq):
        self.rows, self.inverse, self.weights, self.p = rows, inverse, weights, p
        self.generator, self.chi = generator, chi       # A, and chi with grad D . A x = chi D

    def weight(self, pair: tuple[int, int], m: tuple[int, ...]) -> int:
        """sum_c m_c w_c - w_i - w_j mod p: the eigenvalue of L_A on y^m e_i ^ e_j."""
        w = self.weights
        return (sum(e * v for e, v in zip(m, w, strict=True)) - w[pair[0]] - w[pair[1]]) % self.p

    def apply(self, matrix: list[list[int]], v: list[int]) -> list[int]:
        return [sum(a * b for a, b in zip(row, v, strict=True)) % self.p for row in matrix]


def read_torus(f: KahanData, data: Any, denominator: Frac, p: int, where: str) -> CheckedTorus:
    """The torus of an exclusion step, every condition checked (CertificateError or Refutation otherwise)."""
    n, ring = len(f.variables), f.ring
    generator = get(data, "generator", list, where)
    if len(generator) != n or any(not isinstance(r, list) or len(r) != n for r in generator):
        raise CertificateError(f"{where}: the torus generator must be an {n} x {n} matrix of rationals")
    a = [[parse_rational(str(e)) for e in row] for row in generator]
    xs = [ring.gen(v) for v in f.variables]
    const = lambda q: Frac(ring, ring.constant(int(q.p)), ring.constant(int(q.q)))  # noqa: E731
    ax = [sum((const(a[i][j]) * Frac(ring, xs[j]) for j in range(n)), Frac(ring, ring.constant(0))) for i in range(n)]
    for i, fi in enumerate(f.rhs):
        flow = sum((fi.derivative(v) * ax[k] for k, v in enumerate(f.variables)), Frac(ring, ring.constant(0)))
        if flow != sum((const(a[i][j]) * f.rhs[j] for j in range(n)), Frac(ring, ring.constant(0))):
            raise Refutation(f"{where}: [A x, F] != 0 in component {i + 1}: A is no symmetry of the field")
    grad = sum((denominator.derivative(v) * ax[k] for k, v in enumerate(f.variables)), Frac(ring, ring.constant(0)))
    ratio = grad / denominator
    if not ratio.num.is_constant() or not ratio.den.is_constant():
        raise Refutation(f"{where}: grad D . A x is no constant multiple of D: the torus does not keep the class")
    matrix = flint.fmpq_mat(n, n, [e for row in a for e in row])
    c = matrix.charpoly()
    s = c / c.gcd(c.derivative())
    value, power = flint.fmpq_mat(n, n), flint.fmpq_mat(n, n, [int(i == j) for i in range(n) for j in range(n)])
    for coefficient in s.coeffs():
        value, power = value + power * coefficient, power * matrix
    if any(e != 0 for e in value.entries()):
        raise CertificateError(f"{where}: the torus generator is not diagonalizable (s(A) != 0)")
    weights = [w % p for w in integers(data, "weights", where)]
    if len(weights) != n or len(set(weights)) != s.degree() or any(e.q % p == 0 for e in matrix.entries()):
        raise CertificateError(f"{where}: the weights must be the {s.degree()} distinct eigenvalues of A mod p")
    if any(int(s.numer()(w)) % p for w in weights) or s.denom() % p == 0:
        raise CertificateError(f"{where}: a stated weight is no root of the squarefree characteristic polynomial mod p")
    rows = get(data, "rows", list, where)
    if len(rows) != n or any(not isinstance(r, list) or len(r) != n for r in rows):
        raise CertificateError(f"{where}: T must be an {n} x {n} matrix of residues")
    t = flint.nmod_mat([[int(v) % p for v in r] for r in rows], p)
    am = flint.nmod_mat([[int(e.p) * pow(int(e.q), -1, p) % p for e in row] for row in a], p)
    diag = flint.nmod_mat(n, n, [weights[i] * (i == j) for i in range(n) for j in range(n)], p)
    if t.det() == 0 or t * am != diag * t:
        raise CertificateError(f"{where}: T A = diag(weights) T with T invertible does not hold mod {p}")
    inv = t.inv()
    return CheckedTorus([[int(t[i, j]) for j in range(n)] for i in range(n)],
                        [[int(inv[i, j]) for j in range(n)] for i in range(n)], weights, p, a,
                        flint.fmpq(int(ratio.num.leading_coefficient()), int(ratio.den.leading_coefficient()))
                        if not ratio.num.is_zero() else flint.fmpq(0))
