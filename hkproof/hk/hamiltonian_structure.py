"""A quadratic field as F = J grad H with J constant and skew and H cubic, found from the field alone (exact).

A constant skew J with F = J grad H is preserved by the flow: L_F J = -(F' J + J F'^T) = 0, which is linear in the
entries of J; the field's Jacobian F' is affine in x, so this is a finite linear system over Q(parameters). Given
such a J, F = J grad H is linear in the coefficients of H. Conversely L_F J = 0 alone does not make F Hamiltonian
(J = 0 always passes; a degenerate J needs F tangent to its leaves), which is why H is solved for and F = J grad H
checked exactly at the end (`hkproof.hk.modified_hamiltonian.check_inputs`). This is the input of the modified
Hamiltonian of Celledoni, McLachlan, Owren, Quispel (2013).
"""
from __future__ import annotations

from typing import NamedTuple, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.algebra.monomials import Exponents, exponents_upto
from hkproof.algebra.ring import Ring
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import NotHamiltonianError
from hkproof.hk.modified_hamiltonian import check_inputs, field_jacobian

__all__ = ["HamiltonianStructure", "hamiltonian_structure", "invariant_poisson_matrices"]

Row = dict[int, Frac]


class HamiltonianStructure(NamedTuple):
    """F = J grad H: J constant and skew (entries in Q(parameters)), H a polynomial of degree <= 3 without constant
    term, both in the ring of the field."""

    poisson: list[list[Frac]]
    hamiltonian: Frac

    def poisson_text(self) -> str:
        """J as '[[a, b], [c, d]]' (the form `hkproof hamiltonian --poisson` reads)."""
        return "[" + ", ".join("[" + ", ".join(str(e) for e in row) + "]" for row in self.poisson) + "]"


def hamiltonian_structure(field: QuadraticField) -> HamiltonianStructure | None:
    """J constant and skew and H cubic with F = J grad H, or None.

    J runs over the constant skew matrices with L_F J = 0 (`invariant_poisson_matrices`): when they form a line
    (the usual case) None is exact, there is no such pair. When they form a larger space, a combination with
    coefficients 1, 2, 3, ... and then each basis element are tried, and None only says that none of them works.

    >>> s = hamiltonian_structure(QuadraticField("oscillator", ("q", "p"), (), ("p", "-q - q**2")))
    >>> s.poisson_text(), str(s.hamiltonian)
    ('[[0, 1], [-1, 0]]', '(2*q**3 + 3*q**2 + 3*p**2)/(6)')
    >>> hamiltonian_structure(QuadraticField("lv", ("x", "y"), (), ("x*(1 - y)", "y*(x - 1)"))) is None
    True
    """
    basis = invariant_poisson_matrices(field)
    ring = field.ring
    trials = basis if len(basis) < 2 else [_combination(ring, basis, range(1, len(basis) + 1)), *basis]
    kmap = KahanMap(field)
    for j in trials:
        h = _hamiltonian_for(field, j)
        if h is None:
            continue
        try:
            check_inputs(kmap, h, j)
        except NotHamiltonianError:      # the exact check decides; the solve above only proposes
            continue
        return HamiltonianStructure(j, h)
    return None


def invariant_poisson_matrices(field: QuadraticField) -> list[list[list[Frac]]]:
    """A basis of the constant skew J with F'(x) J + J F'(x)^T = 0 for all x (L_F J = 0), over Q(parameters); each
    scaled so that its first non-zero entry above the diagonal is 1."""
    ring, xs = field.ring, field.variables
    n = len(xs)
    pairs = [(a, b) for a in range(n) for b in range(a + 1, n)]
    index = {pair: k for k, pair in enumerate(pairs)}

    def entry(r: int, c: int) -> tuple[int, int] | None:
        """(unknown, sign) of J[r][c]: J[r][c] = sign * u_(min, max), None on the diagonal."""
        if r == c:
            return None
        return (index[r, c], 1) if r < c else (index[c, r], -1)

    jac = [[_coefficients(e, xs) for e in row] for row in field_jacobian(KahanMap(field))]
    rows: list[Row] = []
    for a, b in pairs:
        terms: dict[Exponents, Row] = {}
        # (F' J + J F'^T)_ab = sum_k F'_ak J_kb + sum_k J_ak F'_bk
        for k in range(n):
            for coefficients, unknown in ((jac[a][k], entry(k, b)), (jac[b][k], entry(a, k))):
                if unknown is None:
                    continue
                u, sign = unknown
                for mono, c in coefficients.items():
                    row = terms.setdefault(mono, {})
                    row[u] = row.get(u, _zero(ring)) + c * sign
        rows += terms.values()
    echelon = _echelon(rows)
    pivots = {c for c, _ in echelon}
    out = []
    for free in (u for u in range(len(pairs)) if u not in pivots):
        vector = {free: Frac(ring, 1)}
        vector.update({c: -r[free] for c, r in echelon if free in r})
        j = [[_zero(ring)] * n for _ in range(n)]
        for u, value in vector.items():
            a, b = pairs[u]
            j[a][b], j[b][a] = value, -value
        first = next(value for value in (j[a][b] for a, b in pairs) if not value.is_zero())
        out.append([[e / first for e in row] for row in j])
    return out


def _hamiltonian_for(field: QuadraticField, j: Sequence[Sequence[Frac]]) -> Frac | None:
    """The H of degree <= 3 without constant term with J grad H = F (Casimir directions set to 0), or None when the
    linear system has no solution."""
    ring, xs = field.ring, field.variables
    n = len(xs)
    monomials = [e for e in exponents_upto(n, 3) if any(e)]
    rhs = len(monomials)                     # the column of the right-hand side
    rows: list[Row] = []
    for i, f in enumerate(field.rhs):
        terms: dict[Exponents, Row] = {mono: {rhs: c} for mono, c in _coefficients(f, xs).items()}
        for u, e in enumerate(monomials):
            for b in range(n):
                if e[b] and not j[i][b].is_zero():
                    lower = tuple(k - (a == b) for a, k in enumerate(e))
                    row = terms.setdefault(lower, {})
                    row[u] = row.get(u, _zero(ring)) + j[i][b] * e[b]
        rows += terms.values()
    echelon = _echelon(rows)
    if any(c == rhs for c, _ in echelon):
        return None
    h = _zero(ring)
    for c, r in echelon:
        h += r.get(rhs, _zero(ring)) * _monomial(ring, xs, monomials[c])
    return h


def _echelon(rows: Sequence[Row]) -> list[tuple[int, Row]]:
    """Gauss-Jordan elimination of sparse rows over Q(parameters): (pivot column, row) pairs of the reduced
    row-echelon form, each row 1 at its pivot and 0 at every other pivot."""
    done: list[tuple[int, Row]] = []
    for given in rows:
        row = dict(given)
        for c, r in done:
            if c in row:
                row = _minus(row, row[c], r)
        row = {k: v for k, v in row.items() if not v.is_zero()}
        if not row:
            continue
        pivot = min(row)
        lead = row[pivot]
        row = {k: v / lead for k, v in row.items()}
        done = [(c, _minus(r, r[pivot], row) if pivot in r else r) for c, r in done]
        done.append((pivot, row))
    return done


def _minus(row: Row, factor: Frac, other: Row) -> Row:
    """row - factor * other, zeros dropped."""
    out = dict(row)
    for k, v in other.items():
        out[k] = out[k] - factor * v if k in out else -factor * v
    return {k: v for k, v in out.items() if not v.is_zero()}


def _coefficients(f: Frac, xs: Sequence[str]) -> dict[Exponents, Frac]:
    """f (polynomial in the phase variables xs) as {exponents in xs: coefficient in Q(parameters)}."""
    ring = f.ring
    at = [ring.index(x) for x in xs]
    parts: dict[Exponents, dict[tuple[int, ...], int]] = {}
    for exps, c in f.num.to_dict().items():
        rest = tuple(0 if k in at else e for k, e in enumerate(exps))
        parts.setdefault(tuple(exps[k] for k in at), {})[rest] = int(c)
    return {mono: Frac(ring, ring.ctx.from_dict(terms), f.den) for mono, terms in parts.items()}


def _monomial(ring: Ring, xs: Sequence[str], e: Exponents) -> Frac:
    out = ring.constant(1)
    for x, k in zip(xs, e, strict=True):
        out *= ring.gen(x) ** k
    return Frac(ring, out)


def _combination(ring: Ring, basis: Sequence[list[list[Frac]]], weights: Sequence[int]) -> list[list[Frac]]:
    """sum_k weights[k] basis[k]."""
    n = len(basis[0])
    return [[sum((w * b[a][c] for w, b in zip(weights, basis, strict=True)), _zero(ring)) for c in range(n)]
            for a in range(n)]


def _zero(ring: Ring) -> Frac:
    return Frac(ring, 0)

