"""Invariant Poisson bivectors Pi = Q / D of a Kahan map and their exact proofs (docs/poisson.md).

Invariance Pi(f(x)) = Df(x) Pi(x) Df(x)^T is checked through the Kahan equations: with the lemma
M(x, eps) Df(x) = M(f(x), -eps) (hkproof.hk.jacobian.matrix_identity_holds) it is the polynomial identity

    M(x, eps) Q(x~) M(x, eps)^T D(x) Delta^(dD + 2) = D~ M~ Q(x) M~^T Delta^dQ,   x~ = N / Delta,

where Q(x~) Delta^dQ, D(x~) Delta^dD = D~ and M(x~, -eps) Delta = M~ are homogenized compositions (no Df, no gcd).
Jacobi is the Schouten bracket [Pi, Pi] = 0, compatibility [Pi1, Pi2] = 0 (Magri), each cleared of D.
Casimirs (Pi grad C = 0) and involution ({I, J} = grad I . Pi grad J = 0) are exact identities in Q(x, eps, params).
"""
from __future__ import annotations

import itertools
import random
from collections import deque
from dataclasses import dataclass
from typing import Callable, Iterator, Sequence

import flint

from hkproof import budget
from hkproof.algebra.fraction import Frac, homogenized_compose, poly_str
from hkproof.algebra.linalg import Element as E, lcm, rank_over_fraction_field
from hkproof.algebra.ring import Ring
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ShapeError
from hkproof.hk.jacobian import pulled_matrix

__all__ = ["antisymmetric", "Bivector", "bracket", "bracket_relations_mod", "brackets_independent_mod", "casimir_combination", "compatible", "generic_rank",
           "invariance_holds", "is_casimir", "is_poisson", "pairs", "schouten"]


def pairs(n: int) -> list[tuple[int, int]]:
    """The index pairs i < j of a bivector's independent entries, in order."""
    return list(itertools.combinations(range(n), 2))


@dataclass(frozen=True)
class Bivector:
    """Pi = Q / D: the entries Q_ij (i < j) of an antisymmetric matrix of polynomials over one denominator D."""

    ring: Ring
    variables: tuple[str, ...]
    upper: tuple[flint.fmpz_mpoly, ...]     # Q_ij for the pairs i < j, in the order of `pairs(n)`
    denominator: flint.fmpz_mpoly

    def __post_init__(self) -> None:
        if len(self.upper) != len(pairs(len(self.variables))):
            raise ShapeError(f"a bivector in {len(self.variables)} variables has {len(pairs(len(self.variables)))} "
                             f"entries above the diagonal, got {len(self.upper)}")
        if self.denominator.is_zero():
            raise ShapeError("the denominator of a bivector is zero")

    @classmethod
    def from_matrix(cls, ring: Ring, variables: Sequence[str], matrix: Sequence[Sequence[Frac]]) -> Bivector:
        """The bivector of an antisymmetric matrix of rational functions (over the lcm of its denominators)."""
        n = len(variables)
        if len(matrix) != n or any(len(row) != n for row in matrix):
            raise ShapeError(f"a bivector in {n} variables is an {n} x {n} matrix")
        for i, j in itertools.product(range(n), repeat=2):
            if matrix[i][j] != -matrix[j][i]:
                raise ShapeError(f"the matrix is not antisymmetric at ({i + 1}, {j + 1})")
        entries = [matrix[i][j] for i, j in pairs(n)]
        den = lcm([e.den for e in entries]) if entries else ring.constant(1)
        return cls(ring, tuple(variables), tuple(e.num * (den / e.den) for e in entries), den)

    def entry(self, i: int, j: int) -> flint.fmpz_mpoly:
        """Q_ij (antisymmetric)."""
        if i == j:
            return self.ring.constant(0)
        k = pairs(len(self.variables)).index((min(i, j), max(i, j)))
        return self.upper[k] if i < j else -self.upper[k]

    def fracs(self) -> list[list[Frac]]:
        """Pi as a matrix of fractions in lowest terms."""
        n = len(self.variables)
        return [[Frac(self.ring, self.entry(i, j), self.denominator) for j in range(n)] for i in range(n)]

    def texts(self) -> list[list[str]]:
        """Pi_ij as formulas hkproof's parser reads."""
        return [[str(e) for e in row] for row in self.fracs()]

    def degree(self) -> int:
        """The largest total degree of the Q_ij in the phase variables."""
        idx = [self.ring.index(v) for v in self.variables]
        return max((sum(m[i] for i in idx) for q in self.upper for m in q.monoms()), default=0)

    def scaled(self, c: flint.fmpz_mpoly) -> Bivector:
        """c Pi for a polynomial c."""
        return Bivector(self.ring, self.variables, tuple(q * c for q in self.upper), self.denominator)

    def plus(self, other: Bivector) -> Bivector:
        """Pi + Pi' over the product of the denominators (or the common one)."""
        if other.denominator == self.denominator:
            return Bivector(self.ring, self.variables, tuple(a + b for a, b in zip(self.upper, other.upper,
                                                                                   strict=True)), self.denominator)
        return Bivector(self.ring, self.variables,
                        tuple(a * other.denominator + b * self.denominator
                              for a, b in zip(self.upper, other.upper, strict=True)),
                        self.denominator * other.denominator)

    def __str__(self) -> str:
        entries = ", ".join(f"{{{self.variables[i]}, {self.variables[j]}}} = {poly_str(q)}"
                            for (i, j), q in zip(pairs(len(self.variables)), self.upper, strict=True) if not q.is_zero())
        return f"({entries}) / ({poly_str(self.denominator)})"


# ---- invariance ---------------------------------------------------------------------------------------------------
def invariance_holds(kmap: KahanMap, pi: Bivector) -> bool:
    """Pi(f(x)) = Df Pi(x) Df^T exactly, as the polynomial identity of the module docstring (given the lemma
    M(x, eps) Df = M(f(x), -eps), which the caller proves once with matrix_identity_holds)."""
    ring, n = kmap.ring, len(kmap.variables)
    nums, delta = kmap.explicit
    m = kmap.matrix[0]
    mt = pulled_matrix(kmap)                       # M(x~, -eps) Delta
    composed = [homogenized_compose(ring, q, kmap.variables, nums, delta) for q in pi.upper]
    dq = max((d for q, d in composed if not q.is_zero()), default=0)
    qt = [q * delta ** (dq - d) for q, d in composed]                   # Q(x~) Delta^dQ
    dt, dd = homogenized_compose(ring, pi.denominator, kmap.variables, nums, delta)   # D(x~) Delta^dD
    left = _congruence(m, antisymmetric(qt, n, ring.constant(0)), ring)
    right = _congruence(mt, antisymmetric(pi.upper, n, ring.constant(0)), ring)
    common = min(dd + 2, dq)                       # Delta^common cancels from both sides: smaller products
    scale_l = pi.denominator * delta ** (dd + 2 - common)
    scale_r = dt * delta ** (dq - common)
    return all(left[i][j] * scale_l == right[i][j] * scale_r for i, j in pairs(n))


def antisymmetric(upper: Sequence[E], n: int, zero: E) -> list[list[E]]:
    """The n x n antisymmetric matrix with the entries `upper` above its diagonal (in the order of `pairs(n)`)."""
    out = [[zero] * n for _ in range(n)]
    for (i, j), q in zip(pairs(n), upper, strict=True):
        out[i][j], out[j][i] = q, -q
    return out


def _congruence(a: Sequence[Sequence[flint.fmpz_mpoly]], q: Sequence[Sequence[flint.fmpz_mpoly]], ring: Ring
                ) -> list[list[flint.fmpz_mpoly]]:
    """A Q A^T for polynomial matrices."""
    n = len(a)
    zero = ring.constant(0)
    aq = [[sum((a[i][k] * q[k][j] for k in range(n) if not q[k][j].is_zero()), zero) for j in range(n)]
          for i in range(n)]
    return [[sum((aq[i][k] * a[j][k] for k in range(n)), zero) for j in range(n)] for i in range(n)]


# ---- Schouten bracket, rank, Casimirs, involution ----------------------------------------------------------------------
def schouten(a: Bivector, b: Bivector, derivation: Callable[[flint.fmpz_mpoly, int], flint.fmpz_mpoly] | None = None
             ) -> list[flint.fmpz_mpoly]:
    """[Pi_a, Pi_b]^ijk (i < j < k) times D_a^2 D_b^2: sum over cyclic (i, j, k) and l of
    Pi_a^il d_l Pi_b^jk + Pi_b^il d_l Pi_a^jk (zero for both iff the two are compatible; [Pi, Pi] = 0 is Jacobi).
    `derivation(p, l)`: d_l p, the partial derivative in the l-th phase variable unless given (hkproof.hk.nambu
    passes the total derivative of a ring of jets)."""
    ring, n = a.ring, len(a.variables)
    if derivation is None:
        idx = [ring.index(v) for v in a.variables]
        derivation = lambda p, l: p.derivative(idx[l])  # noqa: E731
    d_ = derivation
    da, db = a.denominator, b.denominator
    grad_da = [d_(da, k) for k in range(n)]
    grad_db = [d_(db, k) for k in range(n)]

    def half(p: Bivector, q: Bivector, dp: flint.fmpz_mpoly, dq: flint.fmpz_mpoly, grad_dq: list,
             i: int, j: int, k: int) -> flint.fmpz_mpoly:
        # sum_l Q_p^il (D_q d_l Q_q^jk - Q_q^jk d_l D_q), times D_p D_q^2 relative to Pi_p^il d_l Pi_q^jk
        qjk = q.entry(j, k)
        return sum((p.entry(i, l) * (dq * d_(qjk, l) - qjk * grad_dq[l]) for l in range(n)
                    if l != i), ring.constant(0))
    out = []
    for i, j, k in itertools.combinations(range(n), 3):
        budget.check("a component of the Schouten bracket")
        total = ring.constant(0)
        for r, s, t in ((i, j, k), (j, k, i), (k, i, j)):
            total += half(a, b, da, db, grad_db, r, s, t) * da + half(b, a, db, da, grad_da, r, s, t) * db
        out.append(total)
    return out


def is_poisson(pi: Bivector) -> bool:
    """The Jacobi identity [Pi, Pi] = 0, exactly."""
    return all(c.is_zero() for c in schouten(pi, pi))


def brackets_independent_mod(members: Sequence[Bivector], p: int) -> bool:
    """The brackets [Pi_a, Pi_b] (a <= b) of bivectors with one denominator and residue coefficients (a basis of a
    kernel mod p at one specialization) are linearly independent mod p: then no member sum c_a Pi_a != 0 satisfies
    Jacobi mod p ([sum c_a Pi_a, same] = sum c_a c_b [Pi_a, Pi_b]); for one bivector, [Pi, Pi] != 0 mod p. Shown by
    the values of the polynomials `schouten(a, b)` at up to N + 2 random points mod p (N brackets), a linear image of
    their coefficients, when they have full row rank; each value comes from the values of Q, D and their first
    derivatives at the point, no bracket is expanded (the Gaudin magnet's 21 brackets at degree 7 have about a
    million terms). False when the values do not show it: then the brackets are dependent, but for a chance of
    about deg/p per point (the checker decides the same way)."""
    return any(int(flint.nmod_mat(values, p).rank()) == len(values) for values in _bracket_values(members, p))


def bracket_relations_mod(members: Sequence[Bivector], p: int) -> list[list[list[int]]]:
    """The linear relations mod p among the brackets [Pi_a, Pi_b] (a <= b), from their values at N + 2 random points
    (as `brackets_independent_mod`), each as the symmetric matrix W with sum_ab W_ab [Pi_a, Pi_b] = 0: a member
    sum c_a Pi_a satisfies Jacobi mod p iff c c^T is in their span, two such members c, d are compatible iff
    c d^T + d c^T is."""
    last = deque(_bracket_values(members, p), maxlen=1)
    if not last:
        return []
    kernel, dim = flint.nmod_mat(last[0], p).transpose().nullspace()
    r, half = len(members), pow(2, -1, p)
    forms = []
    for t in range(dim):
        w = [[0] * r for _ in range(r)]
        for k, (a, b) in enumerate(itertools.combinations_with_replacement(range(r), 2)):
            w[a][b] = w[b][a] = int(kernel[k, t]) * (1 if a == b else half) % p
        forms.append(w)
    return forms


def _bracket_values(members: Sequence[Bivector], p: int) -> Iterator[list[list[int]]]:
    """The values mod p of every bracket [Pi_a, Pi_b] (a <= b; one row each, the components i < j < k at each point
    side by side), after each of N + 2 random points (seeded by p)."""
    if not members or len(members[0].variables) < 3:        # no components (dimension < 3)
        return
    n, ring = len(members[0].variables), members[0].ring
    idx = [ring.index(v) for v in members[0].variables]
    polys = [[*m.upper, m.denominator] for m in members]                 # Q_ij (i < j), then D
    grads = [[[q.derivative(k) for k in idx] for q in qs] for qs in polys]
    index = {pair: k for k, pair in enumerate(pairs(n))}
    brackets = list(itertools.combinations_with_replacement(range(len(members)), 2))
    rng, nvars = random.Random(p), polys[0][0].context().nvars()
    values: list[list[int]] = [[] for _ in brackets]
    for _ in range(len(brackets) + 2):
        budget.check("the Schouten brackets of a kernel's members at a point mod p")
        x = [rng.randrange(p) for _ in range(nvars)]
        val = [[int(q(*x)) % p for q in qs] for qs in polys]
        der = [[[int(g(*x)) % p for g in gs] for gs in gss] for gss in grads]

        def q_at(a: int, i: int, j: int, l: int | None = None) -> int:
            k = index.get((min(i, j), max(i, j)))
            v = 0 if k is None else val[a][k] if l is None else der[a][k][l]
            return v if i < j else -v

        def half(a: int, b: int, i: int, j: int, k: int) -> int:      # schouten's half, at x
            d_b, grad_b = val[b][-1], der[b][-1]
            return sum(q_at(a, i, l) * (d_b * q_at(b, j, k, l) - q_at(b, j, k) * grad_b[l]) for l in range(n))
        for row, (a, b) in zip(values, brackets, strict=True):
            row.extend(sum(half(a, b, r, s, t) * val[a][-1] + half(b, a, r, s, t) * val[b][-1]
                           for r, s, t in ((i, j, k), (j, k, i), (k, i, j))) % p
                       for i, j, k in itertools.combinations(range(n), 3))
        yield values


def compatible(a: Bivector, b: Bivector) -> bool:
    """[Pi_a, Pi_b] = 0 exactly: with Jacobi for both, every Pi_a + t Pi_b is Poisson (a bi-Hamiltonian pair)."""
    return all(c.is_zero() for c in schouten(a, b))


def generic_rank(pi: Bivector) -> int:
    """The rank of Pi over Q(x, eps, params), exactly (fraction-free elimination)."""
    return rank_over_fraction_field(pi.fracs())


def _gradient(h: Frac, variables: Sequence[str]) -> list[Frac]:
    return [h.derivative(v) for v in variables]


def is_casimir(pi: Bivector, c: Frac) -> bool:
    """Pi grad C = 0 exactly (D cleared: Q grad C = 0)."""
    grad = _gradient(c, pi.variables)
    n = len(pi.variables)
    return all(sum((Frac(pi.ring, pi.entry(i, j)) * grad[j] for j in range(n)), Frac(pi.ring, 0)).is_zero()
               for i in range(n))


def bracket(pi: Bivector, f: Frac, g: Frac) -> Frac:
    """{f, g} = grad f . Pi grad g, exactly."""
    gf, gg = _gradient(f, pi.variables), _gradient(g, pi.variables)
    n = len(pi.variables)
    total = Frac(pi.ring, 0)
    for i, j in pairs(n):
        total += Frac(pi.ring, pi.entry(i, j)) * (gf[i] * gg[j] - gf[j] * gg[i])
    return total / Frac(pi.ring, pi.denominator)


def casimir_combination(pi: Bivector, g: Frac, h: Frac | None = None) -> Frac | None:
    """g itself when Pi grad g = 0; else g - c h when Pi grad g = c Pi grad h with c free of the phase variables
    (then g - c h is a Casimir, checked exactly); None otherwise."""
    n = len(pi.variables)

    def hamiltonian(f: Frac) -> list[Frac]:
        grad = _gradient(f, pi.variables)
        return [sum((Frac(pi.ring, pi.entry(i, j)) * grad[j] for j in range(n)), Frac(pi.ring, 0)) for i in range(n)]
    u = hamiltonian(g)
    if all(x.is_zero() for x in u):
        return g
    if h is None:
        return None
    w = hamiltonian(h)
    k = next((i for i, x in enumerate(w) if not x.is_zero()), None)
    if k is None:
        return None
    c = u[k] / w[k]
    if c.variables() & set(pi.variables):
        return None
    return g - c * h if all((a - c * b).is_zero() for a, b in zip(u, w, strict=True)) else None
