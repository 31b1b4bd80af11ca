"""Exact linear algebra: fraction-free determinants and Cramer's rule over Z[v]; ranks and kernels over Q and Z/p."""
from __future__ import annotations

from typing import Mapping, Sequence, TypeVar

import flint

from hkproof import budget
from hkproof.algebra.factored import cancel_common
from hkproof.algebra.fraction import Frac, normalize_sign
from hkproof.algebra.ring import Rational, Ring, to_fmpq
from hkproof.errors import ShapeError, SingularSystemError

__all__ = ["clear_row_denominators", "cleared_system", "cramer", "cramer_polynomials", "det", "Element", "LAPLACE_MAX",
           "lcm", "maximal_minors", "nullspace_q", "pivots_at", "PolyMatrix", "primitive_vector", "q_matrix",
           "rank_over_fraction_field", "rank_q", "solve_by_inverse", "solve_cleared", "solve_overdetermined"]

PolyMatrix = Sequence[Sequence[flint.fmpz_mpoly]]
Element = TypeVar("Element", flint.fmpz_mpoly, flint.fmpq)

LAPLACE_MAX = 8


def det(matrix: PolyMatrix) -> flint.fmpz_mpoly:
    """Determinant of a square polynomial matrix: memoized Laplace expansion (n <= 8) or Bareiss."""
    n = len(matrix)
    if any(len(row) != n for row in matrix):
        raise ValueError("det needs a square matrix")
    if n <= LAPLACE_MAX:
        return _det_laplace(matrix)
    return _det_bareiss(matrix)


def _det_laplace(matrix: PolyMatrix) -> flint.fmpz_mpoly:
    """Determinant by memoized Laplace expansion (the one maximal minor of a square matrix)."""
    n = len(matrix)
    return maximal_minors(matrix).get((1 << n) - 1, matrix[0][0] - matrix[0][0])


def maximal_minors(matrix: Sequence[Sequence[Element]]) -> dict[int, Element]:
    """All non-zero n x n minors of an n x m matrix (m >= n) of polynomials or rationals, keyed by the bit mask of
    their columns.

    Expansion along rows from the bottom, memoizing the minor of the last rows on each column subset, so
    that the minors share their sub-minors (one pass gives det M and every Cramer numerator of [M | b]).
    """
    n, m = len(matrix), len(matrix[0])
    one = matrix[0][0] - matrix[0][0] + 1
    minors: dict[int, Element] = {0: one}
    for size in range(1, n + 1):
        budget.check(f"the minors of size {size} of a {n} x {m} polynomial matrix")
        row = matrix[n - size]
        new: dict[int, Element] = {}
        for mask, sub in minors.items():
            for j in range(m):
                bit = 1 << j
                if mask & bit or row[j].is_zero():
                    continue
                term = row[j] * sub
                if bin(mask & (bit - 1)).count("1") % 2:  # sign: columns of mask before j
                    term = -term
                key = mask | bit
                acc = new.get(key)
                new[key] = term if acc is None else acc + term
        minors = {k: v for k, v in new.items() if not v.is_zero()}
    return minors


def cramer_polynomials(a: PolyMatrix, b: Sequence[flint.fmpz_mpoly], columns: Sequence[int] | None = None
                       ) -> tuple[flint.fmpz_mpoly, list[flint.fmpz_mpoly]]:
    """(det A, [det A_j]) with A_j = A with column j replaced by b: Cramer's rule, fraction-free (det A_j only for
    j in `columns` if given, zero elsewhere).

    det A_j = sum_i b_i C_ij with the cofactors C_ij of A: every minor is built from A's small entries, and each
    (typically big) b_i enters one product per wanted column. Th. "dC Theta" needs one column: its Cramer step
    went from 11.5 s (all minors of [A | b]) to about 4 s. When every column is wanted and b is no bigger than
    A's smallest entries (the map f = M^-1 x itself), one pass over the minors of [A | b] is cheaper: 1.3 ms against
    3.1 ms for the 6 x 6 Clebsch matrix.
    """
    n = len(a)
    zero = b[0] - b[0]
    if n > LAPLACE_MAX:
        return _det_bareiss(a), [_det_bareiss([[(b[i] if k == j else a[i][k]) for k in range(n)] for i in range(n)])
                                 if columns is None or j in columns else zero for j in range(n)]
    if n == 1:
        return a[0][0], [b[0]]
    full = (1 << n) - 1
    if columns is None and max(len(x) for x in b) <= min(len(x) for row in a for x in row if not x.is_zero()):
        # b as small as A's smallest entries: one pass over [A | b] gives det A and every det A_j (b moved from
        # the last place to j)
        minors = maximal_minors([list(row) + [x] for row, x in zip(a, b, strict=True)])
        nums = [minors.get((full & ~(1 << j)) | (1 << n), zero) for j in range(n)]
        return minors.get(full, zero), [-x if (n - 1 - j) % 2 else x for j, x in enumerate(nums)]
    total, nums = zero, [zero] * n
    for i in range(n):
        if i and b[i].is_zero():
            continue
        budget.check(f"Cramer's rule: the cofactors of row {i + 1} of a {n} x {n} polynomial matrix")
        minors = maximal_minors([row for k, row in enumerate(a) if k != i])
        for j in range(n):
            minor = minors.get(full & ~(1 << j))
            if minor is None:
                continue
            cofactor = -minor if (i + j) % 2 else minor
            if i == 0:
                total += a[0][j] * cofactor
            if not b[i].is_zero() and (columns is None or j in columns):
                nums[j] += b[i] * cofactor
    return total, nums


def _det_bareiss(matrix: PolyMatrix) -> flint.fmpz_mpoly:
    """Fraction-free Gaussian elimination (Bareiss); every division is exact."""
    a = [list(row) for row in matrix]
    n = len(a)
    one = a[0][0] - a[0][0] + 1
    prev = one
    sign = 1
    for k in range(n - 1):
        if a[k][k].is_zero():
            swap = next((i for i in range(k + 1, n) if not a[i][k].is_zero()), None)
            if swap is None:
                return one - one
            a[k], a[swap] = a[swap], a[k]
            sign = -sign
        budget.check(f"step {k + 1} of a fraction-free elimination of a {n} x {n} polynomial matrix")
        for i in range(k + 1, n):
            for j in range(k + 1, n):
                a[i][j] = (a[i][j] * a[k][k] - a[i][k] * a[k][j]) / prev
        prev = a[k][k]
    return a[n - 1][n - 1] if sign > 0 else -a[n - 1][n - 1]


def clear_row_denominators(row: Sequence[Frac]) -> list[flint.fmpz_mpoly]:
    """Multiply a row of fractions by the lcm of its denominators: a polynomial row with the same kernel."""
    common = lcm([f.den for f in row])
    return [f.num * (common / f.den) for f in row]


def cramer(rows: Sequence[Sequence[Frac]], rhs: Sequence[Frac],
           columns: Sequence[int] | None = None) -> tuple[list[Frac], flint.fmpz_mpoly]:
    """Solve A c = b for square A over Q(v) by Cramer's rule, gcds cancelled once at the end.

    Returns the solution (in lowest terms; only the components in `columns` if given) and det of the
    fraction-free matrix; raises SingularSystemError when that determinant vanishes identically.
    """
    return solve_cleared(rhs[0].ring, *cleared_system(rows, rhs), columns)


def solve_by_inverse(rows: Sequence[Sequence[Frac]], rhs: Sequence[Frac]) -> list[Frac]:
    """x with rows x = rhs for a small square matrix and large right-hand sides (the A, B, C, D system of sec. 6.7):
    the inverse's columns by Cramer's rule, then one linear combination of the right-hand sides per unknown."""
    r = rhs[0].ring
    n = len(rows)
    columns = [cramer(rows, [Frac(r, int(i == k)) for i in range(n)])[0] for k in range(n)]
    return [sum((columns[k][j] * rhs[k] for k in range(n)), Frac(r, 0)) for j in range(n)]


def solve_cleared(ring: Ring, a: PolyMatrix, b: Sequence[flint.fmpz_mpoly], common: flint.fmpz_mpoly,
                  columns: Sequence[int] | None = None) -> tuple[list[Frac], flint.fmpz_mpoly]:
    """The solution of A x = b / common (a `cleared_system`) by Cramer's rule, in lowest terms, with one big gcd:
    the factor cancelled from the first component is divided out of the others first, when it divides them."""
    d, nums = cramer_polynomials(a, b, columns)
    if d.is_zero():
        raise SingularSystemError(
            "the determinant of the linear system vanishes identically: its solution is not unique "
            "(check that the basis functions are independent and the rows are not redundant)")
    solution, factor = [], None
    for j in (range(len(a)) if columns is None else columns):
        num, den = nums[j], d
        lowest = False
        if factor is None and not num.is_zero():
            factor, lowest = _gcd_after_small_factors(num, d, a), True   # this component divided by it: lowest terms
        if factor is not None and not factor.is_one():  # it usually divides the other components too
            q, rem = divmod(num, factor)
            if rem.is_zero():
                num, den = q, d / factor
        h = Frac(ring, *normalize_sign(num, den), reduced=True) if lowest else Frac(ring, num, den)
        solution.append(h / Frac(ring, common))
    return solution, d


SMALL_ENTRY = 32      # entries of A with at most this many terms are factored for `_gcd_after_small_factors`
BIG_GCD = 2 * 10**4   # ... for a quotient with at least this many terms in all (below, FLINT's gcd at once)


def _gcd_after_small_factors(num: flint.fmpz_mpoly, den: flint.fmpz_mpoly, a: PolyMatrix) -> flint.fmpz_mpoly:
    """gcd(num, den) for a big Cramer quotient: the monomial they share and the irreducible factors of A's small
    entries (where a determinant's common factors often come from, e.g. w_i - w_j of a relation's row) are divided
    out of both first while they divide both, so FLINT's gcd runs on smaller polynomials; gcd = taken * gcd(rest)."""
    if len(num) + len(den) < BIG_GCD:
        return num.gcd(den)
    shared = [min(u, v) for u, v in zip(num.deflation_index()[1], den.deflation_index()[1], strict=True)]
    monomial = den.context().from_dict({tuple(shared): 1})
    if any(shared):
        num, den = num / monomial, den / monomial
    small = (q for row in a for x in row if 0 < len(x) <= SMALL_ENTRY and not x.is_constant()
             for q, _ in x.factor()[1] if len(q) > 1)      # monomial factors: in `monomial`
    num, den, taken = cancel_common(num, den, small)
    return monomial * taken * num.gcd(den)


def cleared_system(rows: Sequence[Sequence[Frac]], rhs: Sequence[Frac]
                   ) -> tuple[list[list[flint.fmpz_mpoly]], list[flint.fmpz_mpoly], flint.fmpz_mpoly]:
    """(A, b, L) with A x = b / L equivalent to rows x = rhs: each row cleared by the lcm of its coefficients'
    denominators, the right-hand side column by its own common denominator L (so A keeps small entries)."""
    a, scaled = [], []
    for r, b in zip(rows, rhs, strict=True):
        row_lcm = lcm([f.den for f in r])
        a.append([f.num * (row_lcm / f.den) for f in r])
        scaled.append(b * Frac(b.ring, row_lcm))
    common = lcm([b.den for b in scaled])
    return a, [b.num * (common / b.den) for b in scaled], common


def pivots_at(rows: Sequence[Sequence[Frac]], point: Mapping[str, Rational]) -> tuple[list[int], list[int]]:
    """(independent rows, pivot columns) of a matrix of rational functions, read off its values at one rational point.

    A minor that is non-zero at the point is a non-zero rational function, so the rows chosen are independent over
    Q(v) and the pivots are valid generically (the caller's solve checks the rest exactly).

    >>> from hkproof.algebra.ring import get_ring
    >>> r = get_ring(("e",))
    >>> e = Frac.parse(r, "e")
    >>> pivots_at([[e, 2 * e, Frac(r, 1)], [Frac(r, 2), Frac(r, 4), Frac(r, 0)], [e, 2 * e, e]], {"e": 1})
    ([0, 1], [0, 2])
    """
    values = [[c.evaluate(point) for c in row] for row in rows]
    chosen: list[int] = []
    for k in range(len(values)):
        if flint.fmpq_mat([values[i] for i in chosen + [k]]).rank() == len(chosen) + 1:
            chosen.append(k)
    if not chosen:
        return [], []
    reduced, rank = flint.fmpq_mat([values[k] for k in chosen]).rref()
    return chosen, [next(j for j in range(len(values[0])) if reduced[i, j] != 0) for i in range(rank)]


def lcm(polys: Sequence[flint.fmpz_mpoly]) -> flint.fmpz_mpoly:
    """The least common multiple of polynomials (one gcd per distinct polynomial: the components of one solution
    often share their denominator, and a gcd of a 10 000-term polynomial with itself costs a tenth of a second)."""
    out, seen = polys[0], [polys[0]]
    for p in polys[1:]:
        if p.is_one() or any(p == q for q in seen):
            continue
        seen.append(p)
        out = out * (p / out.gcd(p))
    return out


def rank_over_fraction_field(rows: Sequence[Sequence[Frac]]) -> int:
    """Exact rank over Q(v) of a matrix of rational functions (fraction-free elimination).

    Each column is cleared by the lcm of its own denominators (column scaling keeps the rank), so that one big
    column, e.g. the right-hand sides of relations with small coefficients, does not swell the others; pivots are
    the smallest entries, and a row's content is divided out (its gcd stops as soon as it is constant).
    """
    rows = [list(r) for r in rows if r]
    if len({len(r) for r in rows}) > 1:
        raise ShapeError(f"a matrix needs rows of one length, got lengths {[len(r) for r in rows]}")
    if not rows:
        return 0
    lcms = [lcm([row[j].den for row in rows]) for j in range(len(rows[0]))]
    work = [[f.num * (m / f.den) for f, m in zip(row, lcms, strict=True)] for row in rows]
    rank = 0
    for col in range(len(lcms)):
        candidates = [r for r in range(rank, len(work)) if not work[r][col].is_zero()]
        if not candidates:
            continue
        pivot = min(candidates, key=lambda r: len(work[r][col]))
        work[rank], work[pivot] = work[pivot], work[rank]
        p = work[rank]
        for r in range(rank + 1, len(work)):
            c = work[r][col]
            if not c.is_zero():
                work[r] = [a * p[col] - c * b for a, b in zip(work[r], p, strict=True)]
                g = _row_content(work[r])
                if g is not None:
                    work[r] = [a / g for a in work[r]]
        rank += 1
    return rank


def _row_content(row: Sequence[flint.fmpz_mpoly]) -> flint.fmpz_mpoly | None:
    """The gcd of the non-zero entries, smallest first; None as soon as it is a constant."""
    g = None
    for a in sorted((a for a in row if not a.is_zero()), key=len):
        g = a if g is None else g.gcd(a)
        if g.is_constant():
            return None
    return g


# ---- matrices of numbers --------------------------------------------------------------------------
def q_matrix(rows: Sequence[Sequence[Rational]]) -> flint.fmpq_mat:
    return flint.fmpq_mat([[to_fmpq(v) for v in r] for r in rows])


def rank_q(rows: Sequence[Sequence[Rational]]) -> int:
    """Exact rank over Q."""
    if not rows:
        return 0
    return q_matrix(rows).rank()


def nullspace_q(rows: Sequence[Sequence[Rational]]) -> list[list[flint.fmpq]]:
    """A basis of the right kernel over Q, from the reduced row echelon form (pivot-free columns set to 1)."""
    m = q_matrix(rows)
    r, rank = m.rref()
    ncols = m.ncols()
    pivots = []
    for i in range(rank):
        pivots.append(next(j for j in range(ncols) if r[i, j] != 0))
    basis = []
    for free in (j for j in range(ncols) if j not in pivots):
        v = [flint.fmpq(0)] * ncols
        v[free] = flint.fmpq(1)
        for i, pj in enumerate(pivots):
            v[pj] = -r[i, free]
        basis.append(v)
    return basis


def primitive_vector(values: Sequence[Rational]) -> list[flint.fmpz]:
    """The rationals times the lcm of their denominators, divided by the gcd of the results, the first non-zero entry
    positive: the primitive integer vector on the same line (zeros stay zeros).

    >>> primitive_vector([flint.fmpq(-1, 2), 3, 0])
    [1, -6, 0]
    """
    qs = [to_fmpq(v) for v in values]
    den = flint.fmpz(1)
    for q in qs:
        den = den.lcm(q.q)
    ints = [flint.fmpz(q.p * (den // q.q)) for q in qs]
    g = flint.fmpz(0)
    for n in ints:
        g = g.gcd(n)
    if g == 0:
        return ints
    sign = 1 if next(n for n in ints if n) > 0 else -1
    return [sign * (n // g) for n in ints]


def solve_overdetermined(system: flint.fmpq_mat, values: Sequence[Rational]) -> list[flint.fmpq]:
    """The exact solution of a consistent overdetermined system A y = v by the normal equations A^T A y = A^T v
    (A of full column rank; the solution is only a candidate until the caller checks it)."""
    if system.nrows() != len(values):
        raise ShapeError(f"the system has {system.nrows()} rows and {len(values)} values")
    t = system.transpose()
    try:
        sol = (t * system).solve(t * flint.fmpq_mat([[to_fmpq(v)] for v in values]))
    except ZeroDivisionError:
        raise SingularSystemError(f"the {system.nrows()} x {system.ncols()} system has rank below "
                                  f"{system.ncols()}: too few or special points") from None
    return [sol[i, 0] for i in range(sol.nrows())]
