"""Affine scaling derivations of a quadratic field, found from the field alone.

E(x, a) = W x + V a + b on the phase space, a_l -> w_l a_l on the parameters and a number c such that
D_x F . E + sum_l w_l a_l dF/da_l - W F = c F: the one-parameter group x -> lambda^W x + ..., a -> lambda^w a,
t -> t / lambda^c maps the flow to itself (c = 0: its affine symmetries). These are linear equations in (W, V, b, w, c),
solved exactly over Q with every parameter symbolic. A change of chart y = T x + t carries every derivation to one of
the transformed field, so what is read off them is chart-free: the centre, where E vanishes (a translation to it makes
a weighted-homogeneous field weighted-homogeneous again, whatever the chart), and the eigenspaces of W (variables of
different weight, hk.normal_form).
"""
from __future__ import annotations

import random
from dataclasses import dataclass

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import nullspace_q
from hkproof.dynamics.field import QuadraticField

__all__ = ["Derivation", "scaling_centre", "scaling_derivations"]


@dataclass(frozen=True)
class Derivation:
    """One derivation: W (n x n), V (n x parameters), b, the parameters' weights w and the time weight c."""

    linear: flint.fmpq_mat
    parameters: flint.fmpq_mat
    shift: tuple[flint.fmpq, ...]
    weights: tuple[flint.fmpq, ...]
    time: flint.fmpq


def scaling_derivations(field: QuadraticField) -> list[Derivation]:
    """A basis over Q of the affine scaling derivations of the field (every parameter symbolic)."""
    names, params = field.variables, field.parameters
    n, p = len(names), len(params)
    ring = field.ring
    xs = [Frac(ring, ring.gen(v)) for v in names]
    av = [Frac(ring, ring.gen(a)) for a in params]
    zero = Frac(ring, 0)
    grad = [[f.derivative(v) for v in names] for f in field.rhs]
    columns: list[list[Frac]] = []
    for i in range(n):                                   # W_ij: D_x F_k . x_j e_i - delta_ki F_j
        for j in range(n):
            columns.append([grad[k][i] * xs[j] - (field.rhs[j] if k == i else zero) for k in range(n)])
    for i in range(n):                                   # V_il: D_x F_k . a_l e_i
        for a in av:
            columns.append([grad[k][i] * a for k in range(n)])
    for i in range(n):                                   # b_i
        columns.append([grad[k][i] for k in range(n)])
    for name, a in zip(params, av, strict=True):         # w_l: a_l dF_k/da_l
        columns.append([a * f.derivative(name) for f in field.rhs])
    columns.append([-f for f in field.rhs])              # c
    kernel = nullspace_q(_coefficient_rows(columns, n))
    return [_derivation(v, n, p) for v in kernel]


def scaling_centre(field: QuadraticField, seed: int = 0) -> list[str] | None:
    """-x0 (text, affine in the parameters) where a scaling derivation with c = 1 vanishes: W x0 + V a + b = 0 for a
    random combination of the derivations with c != 0 (a particular solution when W is singular); None when the
    field has no such derivation, or its centre is the origin already, or W x0 = -(V a + b) has no solution."""
    basis = scaling_derivations(field)
    scaled = [d for d in basis if d.time != 0]
    if not scaled:
        return None
    rng = random.Random(seed)
    coefficients = [flint.fmpq(rng.randint(1, 97)) for _ in basis]
    total = sum((c * d.time for c, d in zip(coefficients, basis, strict=True)), flint.fmpq(0))
    if total == 0:
        coefficients = [flint.fmpq(int(d is scaled[0])) for d in basis]
        total = scaled[0].time
    n, p = basis[0].linear.nrows(), basis[0].parameters.ncols()
    w = sum((d.linear * c for c, d in zip(coefficients, basis, strict=True)), flint.fmpq_mat(n, n)) / total
    v = sum((d.parameters * c for c, d in zip(coefficients, basis, strict=True)), flint.fmpq_mat(n, p)) / total
    b = [sum((c * d.shift[i] for c, d in zip(coefficients, basis, strict=True)), flint.fmpq(0)) / total
         for i in range(n)]
    if not any(b) and not any(v[i, j] for i in range(n) for j in range(p)):
        return None
    rhs = flint.fmpq_mat(n, p + 1, [x for i in range(n) for x in [-v[i, j] for j in range(p)] + [-b[i]]])
    solution = _particular(w, rhs)
    if solution is None:
        return None
    params = field.parameters
    out = []
    for i in range(n):
        terms = [(solution[i, j], params[j]) for j in range(p) if solution[i, j] != 0]
        text = " + ".join(f"({-c})*{a}" for c, a in terms)
        constant = -solution[i, p]
        out.append((text + (f" + ({constant})" if constant != 0 else "")) if terms else str(constant))
    return out


def _coefficient_rows(columns: list[list[Frac]], n: int) -> list[list[flint.fmpq]]:
    """The linear equations sum_u x_u columns[u][k] = 0 for every k, one per monomial: each component is brought to
    one denominator (the lcm of its entries' denominators) and compared coefficient by coefficient."""
    rows: list[list[flint.fmpq]] = []
    for k in range(n):
        den = columns[0][k].den
        for col in columns[1:]:
            d = col[k].den
            den = den * d // den.gcd(d)
        tables = [(col[k].num * (den // col[k].den)).to_dict() for col in columns]
        for mono in sorted({m for t in tables for m in t}):
            rows.append([flint.fmpq(t.get(mono, 0)) for t in tables])
    return rows


def _derivation(v: list[flint.fmpq], n: int, p: int) -> Derivation:
    at = 0
    linear = flint.fmpq_mat(n, n, v[at:at + n * n])
    at += n * n
    parameters = flint.fmpq_mat(n, p, v[at:at + n * p])
    at += n * p
    shift = tuple(v[at:at + n])
    at += n
    return Derivation(linear, parameters, shift, tuple(v[at:at + p]), v[at + p])


def _particular(w: flint.fmpq_mat, rhs: flint.fmpq_mat) -> flint.fmpq_mat | None:
    """X with W X = rhs (the free unknowns 0), or None when there is none."""
    n, k = w.nrows(), rhs.ncols()
    augmented = flint.fmpq_mat(n, n + k, [x for i in range(n) for x in [w[i, j] for j in range(n)]
                                          + [rhs[i, j] for j in range(k)]])
    reduced, rank = augmented.rref()
    out = flint.fmpq_mat(n, k)
    for i in range(rank):
        pivot = next(j for j in range(n + k) if reduced[i, j] != 0)
        if pivot >= n:
            return None
        for j in range(k):
            out[pivot, j] = reduced[i, n + j]
    return out
