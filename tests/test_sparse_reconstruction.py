"""Sparse functional reconstruction over prime fields (hkproof.algebra.sparse_reconstruction and its stages):
each stage on its own, then end-to-end on synthetic black boxes compared exactly with the truth."""
from __future__ import annotations

import itertools
import math
import random
import time
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import flint
import pytest
import sympy

from hkproof.algebra.reconstruction import Rebuilt
from hkproof.algebra.sparse_reconstruction import sparse
from hkproof.algebra.homogeneous_shift import ShiftedPieces
from hkproof.algebra.modular import random_prime
from hkproof.algebra.rational_lifting import CoefficientLifter, crt, rational_reconstruction
from hkproof.algebra.sparse_interpolation import (EARLY_TERMINATION, ExponentialSum, GeometricPoints, ben_or_tiwari,
                                                  distinct_roots, is_smooth_prime, smooth_prime,
                                                  transposed_vandermonde)
from hkproof.algebra.univariate_rational import THIELE_AGREEMENTS, ThieleInterpolator, fit_lines
from hkproof.budget import Budget
from hkproof.errors import BudgetExhausted, HKProofError, ResourceLimitError

Poly = dict[tuple[int, ...], int]


# -- synthetic black boxes -------------------------------------------------------------------------------------------
def random_sparse_polynomial(rng: random.Random, n: int, degree: int, terms: int, height: int = 2 ** 20,
                             constant: bool = True) -> Poly:
    """`terms` distinct random monomials of total degree <= `degree` (one of degree exactly `degree`) with non-zero
    integer coefficients below `height`; without `constant`, no constant term."""
    poly: Poly = {}
    limit = math.comb(n + degree, n) - (0 if constant else 1)
    while len(poly) < min(terms, limit):
        d = degree if not poly else rng.randint(0 if constant else 1, degree)
        cuts = sorted(rng.randint(0, d) for _ in range(n - 1))
        poly[tuple(b - a for a, b in zip([0, *cuts], [*cuts, d]))] = rng.choice([-1, 1]) * rng.randint(1, height)
    return poly


def multiply(a: Poly, b: Poly) -> Poly:
    out: Poly = {}
    for (m1, c1), (m2, c2) in itertools.product(a.items(), b.items()):
        m = tuple(x + y for x, y in zip(m1, m2))
        out[m] = out.get(m, 0) + c1 * c2
    return {m: c for m, c in out.items() if c}


def primitive(num: Poly, den: Poly) -> tuple[Poly, Poly]:
    """The engine's normal form of num/den (already coprime): gcd 1, denominator's leading coefficient positive."""
    g = math.gcd(*num.values(), *den.values())
    lead = max(den, key=lambda m: (sum(m), m))
    sign = -1 if den[lead] < 0 else 1
    return {m: sign * c // g for m, c in num.items()}, {m: sign * c // g for m, c in den.items()}


class RationalBox:
    """f = (product of the numerator factors) / (product of the denominator factors), factors with rational
    coefficients, evaluated mod p with FLINT's nmod_mpoly (None where the denominator vanishes)."""

    def __init__(self, n: int, numerator: list[dict], denominator: list[dict]):
        self.n, self.factors = n, (numerator, denominator)
        self._contexts: dict[int, tuple[list, list]] = {}

    def _reduced(self, p: int) -> tuple[list, list]:
        if p not in self._contexts:
            ctx = flint.nmod_mpoly_ctx.get(("x", self.n), modulus=p)

            def red(poly: dict) -> flint.nmod_mpoly:
                out = {}
                for m, c in poly.items():
                    c = flint.fmpq(c) if not isinstance(c, flint.fmpq) else c
                    out[m] = int(c.p) * pow(int(c.q), -1, p) % p
                return ctx.from_dict(out)
            self._contexts[p] = ([red(f) for f in self.factors[0]], [red(f) for f in self.factors[1]])
        return self._contexts[p]

    def __getstate__(self) -> dict:
        return {**self.__dict__, "_contexts": {}}          # FLINT contexts are rebuilt in each process

    def __call__(self, p: int, points) -> list[int | None]:
        nums, dens = self._reduced(p)
        out: list[int | None] = []
        for x in points:
            q = math.prod(int(f(*x)) for f in dens) % p
            out.append(None if q == 0 else math.prod(int(f(*x)) for f in nums) * pow(q, -1, p) % p)
        return out


def random_target(rng: random.Random, n: int, degree: int, terms: int, den_terms: int, constant: bool = True
                  ) -> tuple[RationalBox, Poly, Poly]:
    """A black box for P/Q with random sparse coprime P, Q, and the expected normal form."""
    num = random_sparse_polynomial(rng, n, degree, terms)
    den = random_sparse_polynomial(rng, n, degree, den_terms, constant=constant)
    return RationalBox(n, [num], [den]), *primitive(num, den)


def assert_exact(result: Rebuilt, num: Poly, den: Poly) -> None:
    assert result.numerator == num
    assert result.denominator == den


# -- univariate stage ------------------------------------------------------------------------------------------------
def test_thiele_reconstructs_and_terminates_early():
    rng, p = random.Random(3), random_prime(random.Random(3))
    num, den = [rng.randrange(p) for _ in range(4)], [1] + [rng.randrange(p) for _ in range(3)]
    g = flint.nmod_poly(num, p), flint.nmod_poly(den, p)
    thiele, used = ThieleInterpolator(p), 0
    while not thiele.terminated:
        t = rng.randrange(1, p)
        thiele.add(t, int(g[0](t)) * pow(int(g[1](t)), -1, p) % p)
        used += 1
    assert thiele.fraction() == (num, den)
    assert used == (3 + 3 + 1) + THIELE_AGREEMENTS      # no point beyond what degrees (3, 3) need, plus agreements


def test_thiele_is_not_fooled_before_enough_points():
    p = 1000003
    thiele = ThieleInterpolator(p)
    for t in range(1, 7 + THIELE_AGREEMENTS):            # 1/(t^3 + 1): Thiele's convergents are diagonal, so
        thiele.add(t, pow(t ** 3 + 1, -1, p))            # type (0, 3) needs the 7 points of type (3, 3),
        assert not thiele.terminated                     # then the agreements
    thiele.add(10, pow(1001, -1, p))
    assert thiele.terminated and thiele.fraction() == ([1], [1, 0, 0, 1])


def test_thiele_nodes_and_values_follow_the_continued_fraction_by_definition():
    """The interpolator's coefficients and values against Thiele's reciprocal differences and the continued fraction
    written out with one modular inverse per level (the textbook definition), on random data over small primes,
    where vanishing differences, poles of a partial fraction and repeated nodes are frequent."""
    rng = random.Random(11)
    for _ in range(400):
        p = rng.choice([5, 7, 11, 13, 101])
        thiele, nodes, coefficients = ThieleInterpolator(p), [], []
        for _ in range(rng.randint(1, 9)):
            t, y = rng.randrange(p), rng.randrange(p)
            def value(u: int) -> int | None:
                if not coefficients:
                    return None
                v = coefficients[-1]
                for a, node in zip(reversed(coefficients[:-1]), reversed(nodes[:-1])):
                    if v == 0:
                        return None
                    v = (a + (u - node) * pow(v, -1, p)) % p
                return v
            agreed = value(t) == y
            thiele.add(t, y)
            if not agreed:
                r = y
                for a, node in zip(coefficients, nodes):
                    if r == a:
                        break
                    r = (t - node) * pow(r - a, -1, p) % p
                else:
                    nodes.append(t)
                    coefficients.append(r)
            assert (thiele.nodes, thiele.coefficients) == (nodes, coefficients)
            assert all(thiele.value(u) == value(u) for u in range(p))


def test_fit_lines_with_known_coefficients():
    p, rng = 1000003, random.Random(4)                   # f = (5 + 7t + 11t^2)/(1 + 3t)
    lines_nodes = [[rng.randrange(1, p) for _ in range(2)] for _ in range(3)]
    values = [[(5 + 7 * t + 11 * t * t) * pow(1 + 3 * t, -1, p) % p for t in ts] for ts in lines_nodes]
    sols = fit_lines(lines_nodes, values, p, [0, 2], [], [{1: 7}] * 3, [{0: 1, 1: 3}] * 3)
    assert sols == [[5, 11]] * 3
    nodes3 = [ts + [rng.randrange(1, p)] for ts in lines_nodes]
    values3 = [[(5 + 7 * t + 11 * t * t) * pow(1 + 3 * t, -1, p) % p for t in ts] for ts in nodes3]
    assert fit_lines(nodes3, values3, p, [0, 2], [1], [{1: 7}] * 3, [{0: 1}] * 3) == [[5, 11, 3]] * 3


# -- rational reconstruction and CRT ---------------------------------------------------------------------------------
def test_rational_reconstruction_recovers_small_fractions_only():
    rng, p = random.Random(5), random_prime(random.Random(5))
    for _ in range(50):
        q = flint.fmpq(rng.randint(-2 ** 29, 2 ** 29), rng.randint(1, 2 ** 29))
        assert rational_reconstruction(int(q.p) * pow(int(q.q), -1, p) % p, p) == q
    big = flint.fmpq(2 ** 40 + 1, 3 ** 25)               # beyond sqrt(p/2): not this fraction
    assert rational_reconstruction(int(big.p) * pow(int(big.q), -1, p) % p, p) != big


def test_crt_and_lifter_need_a_second_prime_for_large_heights():
    p, q = random_prime(random.Random(6)), random_prime(random.Random(7))
    assert crt(3, 7, 4, 11) % 7 == 3 and crt(3, 7, 4, 11) % 11 == 4
    big = flint.fmpq(2 ** 45 + 11, 3 ** 28)
    lifter = CoefficientLifter()
    done, missing = lifter.add({"big": int(big.p) * pow(int(big.q), -1, p) % p, "one": 1}, p)
    assert done == ["one"] and missing == ["big"]
    done, missing = lifter.add({"big": int(big.p) * pow(int(big.q), -1, q) % q, "one": 1}, q)
    assert missing == [] and lifter.rationals["big"] == big


def test_lifter_drops_a_rational_a_new_prime_contradicts():
    p, q = random_prime(random.Random(8)), random_prime(random.Random(9))
    lifter = CoefficientLifter()
    lifter.add({"a": 5}, p)
    assert lifter.rationals["a"] == 5
    lifter.add({"a": 6}, q)                              # 5 is not 6 mod q: rebuilt from the CRT image
    assert lifter.rationals.get("a") != 5


# -- sparse interpolation --------------------------------------------------------------------------------------------
def test_smooth_primes():
    p = smooth_prime(random.Random(10))
    assert p.bit_length() == 62 and is_smooth_prime(p)
    assert is_smooth_prime(2 ** 61 - 1)                   # p - 1 = 2 3^2 5^2 7 11 13 31 41 61 151 331 1321
    assert not is_smooth_prime(1000000007)                # p - 1 = 2 * 500000003
    assert not is_smooth_prime(2 ** 61 + 1)               # not a prime


@pytest.mark.parametrize("nvars,degree,terms", [(1, 5, 3), (4, 6, 40), (7, 9, 300)])
def test_ben_or_tiwari_interpolates_a_sparse_polynomial(nvars, degree, terms):
    rng = random.Random(nvars)
    p = smooth_prime(rng)
    poly = {m: c % p for m, c in random_sparse_polynomial(rng, nvars, degree, terms).items()}
    grid = GeometricPoints.kronecker(p, nvars, degree + 1, rng)
    values = [sum(c * grid.monomial_value(m, j) for m, c in poly.items()) % p
              for j in range(2 * len(poly) + EARLY_TERMINATION)]
    assert ben_or_tiwari(values[:-1], grid, degree) is None                 # one short: not terminated yet
    assert ben_or_tiwari(values, grid, degree) == poly


def test_transposed_vandermonde_and_exponential_sums():
    rng, p = random.Random(11), random_prime(random.Random(11))
    bases, weights = [rng.randrange(1, p) for _ in range(30)], [rng.randrange(p) for _ in range(30)]
    values = [sum(w * pow(b, j, p) for w, b in zip(weights, bases)) % p for j in range(45)]
    assert ExponentialSum(zip(weights, bases), p).values(0, 45) == values
    assert ExponentialSum(zip(weights, bases), p).values(40, 45) == values[40:]
    assert transposed_vandermonde(bases, values, p) == weights


def test_exponential_terms_give_a_polynomials_values_at_the_points():
    rng = random.Random(15)
    p = smooth_prime(rng)
    grid = GeometricPoints.random(p, 3, rng)
    poly = {(2, 0, 1): 5, (0, 3, 0): p - 2, (0, 0, 0): 7, (1, 1, 1): 11}
    values = [sum(c * grid.monomial_value(m, j) for m, c in poly.items()) % p for j in range(12)]
    assert ExponentialSum(grid.exponential_terms(poly.items(), 3), p).values(0, 12) == values


def test_exponential_sums_over_many_chunks(monkeypatch):
    """The product tree works chunk by chunk (a generator is read once); every chunk size gives the same values."""
    from hkproof.algebra import sparse_interpolation as si
    rng, p = random.Random(12), random_prime(random.Random(12))
    bases, weights = [rng.randrange(1, p) for _ in range(37)], [rng.randrange(p) for _ in range(37)]
    values = [sum(w * pow(b, j, p) for w, b in zip(weights, bases)) % p for j in range(50)]
    for leaves in (1, 2, 3, 5, 64):
        monkeypatch.setattr(si, "LEAVES", leaves)
        summed = ExponentialSum(((w, b) for w, b in zip(weights, bases)), p)
        assert summed.terms == 37 and summed.values(0, 50) == values
    assert ExponentialSum(iter(()), p).values(0, 3) == [0, 0, 0]
    assert transposed_vandermonde(bases, values, p) == weights


def test_distinct_roots_refuses_what_does_not_split():
    p = random_prime(random.Random(12))
    roots = [3, 5, 7]
    poly = flint.fmpz_mod_poly_ctx(p)([1])
    for r in roots:
        poly *= flint.fmpz_mod_poly_ctx(p)([-r, 1])
    assert sorted(distinct_roots(poly, p, random.Random(1))) == roots
    assert distinct_roots(poly * flint.fmpz_mod_poly_ctx(p)([-3, 1]), p, random.Random(1)) is None
    # x^2 - a for a non-residue a has no root
    a = next(a for a in range(2, 100) if pow(a, (p - 1) // 2, p) == p - 1)
    assert distinct_roots(flint.fmpz_mod_poly_ctx(p)([-a, 0, 1]), p, random.Random(1)) is None


# -- the homogeneous subtraction (Cuyt–Lee) --------------------------------------------------------------------------
def test_shift_contributions_match_sympy_expansion():
    """The degree-r part of sum_k P_k(z + s) over the homogeneous pieces P_k is [t^r] P(t z + s), for a sparse
    shift (sympy's expansion)."""
    rng, p, n = random.Random(13), 1000003, 3
    poly = random_sparse_polynomial(rng, n, 5, 12, height=50)
    shift = [0, 4, 9]
    t, zs = sympy.Symbol("t"), sympy.symbols("z0:3")
    expanded = sympy.Poly(sympy.expand(sum(c * sympy.prod((t * z + s) ** e for z, s, e in zip(zs, shift, m))
                                           for m, c in poly.items())), t, *zs)
    expected: dict[int, dict] = {}
    for (k, *m), c in expanded.terms():
        if int(c) % p:
            expected.setdefault(k, {})[tuple(m)] = int(c) % p
    moved = ShiftedPieces(n, shift, p)
    for k in range(6):
        moved.add({m: c % p for m, c in poly.items() if sum(m) == k})
    got = {r: dict(moved.part(r)) for r in range(6)}
    assert {r: d for r, d in got.items() if d} == expected
    assert all(sum(m) == r for r, d in got.items() for m in d)


def test_a_piece_is_expanded_in_chunks_with_checks_and_refused_above_the_limit(monkeypatch):
    from hkproof.algebra import homogeneous_shift as hs
    rng, p = random.Random(14), 1000003
    piece = {m: c % p for m, c in random_sparse_polynomial(rng, 4, 6, 40, height=50).items() if sum(m) == 6}
    whole = ShiftedPieces(4, [3, 0, 5, 0], p)
    whole.add(piece)
    monkeypatch.setattr(hs, "CHUNK_TERMS", 10)
    checks: list[str] = []

    class Counting(Budget):
        def check(self, doing: str) -> None:
            checks.append(doing)
    chunked = ShiftedPieces(4, [3, 0, 5, 0], p)
    with Counting(None).active():                  # the active budget is checked between chunks
        chunked.add(piece)
    assert chunked.total == whole.total and len(checks) >= 3
    bound = min(sum((m[0] + 1) * (m[2] + 1) for m in piece), math.comb(6 + 4, 4))   # x0, x2 shifted; dense cap
    with pytest.raises(ResourceLimitError, match="could reach"):
        ShiftedPieces(4, [3, 0, 5, 0], p, limit=bound - 1).add(piece)
    ShiftedPieces(4, [3, 0, 5, 0], p, limit=bound).add(piece)


def test_no_shift_leaves_a_piece_alone():
    moved = ShiftedPieces(2, [0, 0], 101)
    moved.add({(1, 2): 5})
    assert [list(moved.part(r)) for r in range(4)] == [[], [], [], [((1, 2), 5)]]


# -- end to end ------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("n", range(1, 11))
def test_random_targets_in_1_to_10_variables(n):
    rng = random.Random(100 + n)
    degree = min(12, 3 + n)
    box, num, den = random_target(rng, n, degree, 4 * n + 3, 2 * n + 1, constant=n % 2 == 0)
    assert_exact(sparse(box, n, rng=random.Random(n)), num, den)


def test_reduced_form_cross_checked_with_sympy_cancel():
    """The black box evaluates an unreduced fraction; the engine finds the reduced one, as sympy's cancel does."""
    x, y, z = sympy.symbols("x0:3")
    expr = ((x ** 2 - sympy.Rational(2, 7) * y * z + 3) * (x * y - 5 * z ** 3)) / (
        (sympy.Rational(1, 3) * x * z + y ** 2) * (x * y - 5 * z ** 3))
    box = RationalBox(3, [{(2, 0, 0): 1, (0, 1, 1): flint.fmpq(-2, 7), (0, 0, 0): 3}, {(1, 1, 0): 1, (0, 0, 3): -5}],
                      [{(1, 0, 1): flint.fmpq(1, 3), (0, 2, 0): 1}, {(1, 1, 0): 1, (0, 0, 3): -5}])
    result = sparse(box, 3, rng=random.Random(1))
    num, den = sympy.fraction(sympy.cancel(sympy.together(expr)))

    def to_dict(e: sympy.Expr) -> Poly:
        return {m: int(c) for m, c in sympy.Poly(e, x, y, z).terms()}
    assert_exact(result, *primitive(to_dict(num), to_dict(den)))


def test_a_sparse_shift_where_the_black_box_fails_at_the_shift_point():
    """Q(0) = 0, Q(s) != 0 for s on x1 and x3 alone, and a black box undefined wherever a coordinate is 0 (as an orbit
    through a point with zero coordinates degenerates): the engine still takes a shift of at most two variables,
    by lines through the candidates that failed their probe, and rebuilds f exactly."""
    num = {(1, 0, 0, 0): 1, (0, 1, 1, 0): 3, (0, 0, 0, 2): -2}
    den = {(2, 0, 0, 0): 1, (0, 1, 0, 1): 5, (0, 0, 2, 0): 7}
    exact = RationalBox(4, [num], [den])

    def box(p: int, points):
        values = exact(p, points)
        return [None if any(v % p == 0 for v in x) else value for x, value in zip(points, values)]
    result = sparse(box, 4, rng=random.Random(5))
    assert_exact(result, *primitive(num, den))
    assert 0 < sum(1 for s in result.stats.shift if s) <= 2


def test_a_denominator_whose_monomials_each_involve_three_variables_gets_a_three_or_four_variable_shift():
    """Q = x0 x1 x2 + x3 x4 x5 + x0 x3 x5 + x1 x2 x4 vanishes at every shift of at most two variables and has no
    monomial factor to clear; a shift of three (or, if the random subsets miss, four) variables is found before the
    full shift of six, and f is rebuilt exactly."""
    num = {(1, 0, 0, 0, 0, 0): 1, (0, 1, 1, 0, 0, 0): 3, (0, 0, 0, 0, 1, 1): -2}
    den = {(1, 1, 1, 0, 0, 0): 1, (0, 0, 0, 1, 1, 1): 5, (1, 0, 0, 1, 0, 1): 7, (0, 1, 1, 0, 1, 0): 2}
    result = sparse(RationalBox(6, [num], [den]), 6, rng=random.Random(3))
    assert_exact(result, *primitive(num, den))
    assert not any(result.stats.cleared) and 3 <= sum(1 for s in result.stats.shift if s) <= 4


def test_a_monomial_factor_of_the_denominator_is_cleared_before_the_shift():
    """Q = x0 x1^2 x2 (x3^2 + x0 x2) vanishes at every shift of at most two variables; the engine finds the pole
    orders along each x_i = 0, rebuilds x0 x1^2 x2 f with a one-variable shift, and returns f exactly."""
    num = {(1, 0, 0, 0): 1, (0, 1, 1, 0): 3, (0, 0, 0, 2): 1}
    den = {(1, 2, 1, 2): 1, (2, 2, 2, 0): 1}
    result = sparse(RationalBox(4, [num], [den]), 4, rng=random.Random(1))
    assert_exact(result, *primitive(num, den))
    assert result.stats.cleared == (1, 2, 1, 0)
    assert sum(1 for s in result.stats.shift if s) == 1


def test_a_pole_order_read_too_high_still_gives_lowest_terms(monkeypatch):
    """Should the pole orders along x_i = 0 come out too high (an unlucky line), x^k f has x_i in its numerator; the
    engine cancels it again and returns f in lowest terms."""
    from hkproof.algebra import sparse_reconstruction as fr
    honest = fr._Engine._poles
    monkeypatch.setattr(fr._Engine, "_poles", lambda self, p: tuple(k + 1 for k in honest(self, p)))
    num = {(1, 0, 0, 0): 1, (0, 1, 1, 0): 3, (0, 0, 0, 2): 1}
    den = {(1, 2, 1, 2): 1, (2, 2, 2, 0): 1}
    result = sparse(RationalBox(4, [num], [den]), 4, rng=random.Random(1))
    assert result.stats.cleared == (2, 3, 2, 1)
    assert_exact(result, *primitive(num, den))


def test_medium_target_with_shift_and_two_primes():
    """Q(0) = 0 forces a shift; coefficients of height ~2^45 need a second prime."""
    rng = random.Random(14)
    box, num, den = random_target(rng, 6, 8, 400, 60, constant=False)
    big = {m: c * (2 ** 25 + 3) + 1 for m, c in box.factors[0][0].items()}
    box = RationalBox(6, [big], box.factors[1])
    num, den = primitive(big, box.factors[1][0])
    result = sparse(box, 6, rng=random.Random(2))
    assert_exact(result, num, den)
    assert any(result.stats.shift) and len(result.stats.primes_used) >= 2
    stats = result.stats
    assert stats.probes == sum(stats.probes_by_stage.values())
    assert set(stats.seconds) >= {"probes", "univariate", "sparse", "crt", "check"}
    assert (stats.terms_numerator, stats.terms_denominator) == (len(num), len(den))
    assert (stats.degree_numerator, stats.degree_denominator) == (8, 8)


def test_a_polynomial_and_the_value_of_the_result():
    rng = random.Random(23)
    num = random_sparse_polynomial(rng, 5, 7, 60)
    result = sparse(RationalBox(5, [num], [{(0,) * 5: 7}]), 5, rng=random.Random(8))
    assert_exact(result, *primitive(num, {(0,) * 5: 7}))
    p, point = random_prime(rng), [rng.randrange(10 ** 6) for _ in range(5)]
    assert result.value_mod_p(point, p) == RationalBox(5, [num], [{(0,) * 5: 7}])(p, [point])[0]


def test_zero_and_constant_functions():
    zero = sparse(lambda p, pts: [0] * len(pts), 3, rng=random.Random(1))
    assert zero.numerator == {} and zero.denominator == {(0, 0, 0): 1}
    half = sparse(lambda p, pts: [pow(2, -1, p)] * len(pts), 2, rng=random.Random(1))
    assert half.numerator == {(0, 0): 1} and half.denominator == {(0, 0): 2}


# -- unlucky primes --------------------------------------------------------------------------------------------------
def _unlucky_target(bad: int) -> tuple[RationalBox, Poly, Poly]:
    """f = P/Q whose denominator's normalizing coefficient (no constant term: the lowest monomial, x3) is 3 * bad:
    every normalized coefficient has `bad` in its denominator."""
    rng = random.Random(15)
    num = random_sparse_polynomial(rng, 4, 5, 30, height=2 ** 40)
    den = random_sparse_polynomial(rng, 4, 5, 12, height=2 ** 40, constant=False)
    den[(0, 0, 0, 1)] = 3 * bad
    return RationalBox(4, [num], [den]), *primitive(num, den)


def test_an_unlucky_support_prime_is_detected_and_replaced():
    rng = random.Random(16)
    bad = smooth_prime(rng)
    box, num, den = _unlucky_target(bad)
    result = sparse(box, 4, rng=random.Random(3),
                                  primes=itertools.chain([bad], iter(lambda: smooth_prime(rng), None)))
    assert_exact(result, num, den)
    reasons = [why for q, why in result.stats.primes_rejected if q == bad]
    assert reasons and "support" in reasons[0]
    assert bad not in result.stats.primes_used


def test_an_unlucky_coefficient_prime_is_detected_and_replaced():
    rng = random.Random(17)
    bad = next(q for q in iter(lambda: random_prime(rng), None) if not is_smooth_prime(q))
    box, num, den = _unlucky_target(bad)
    good = smooth_prime(rng)                                # support; heights 2^80 need more coefficient primes
    result = sparse(box, 4, rng=random.Random(4),
                                  primes=itertools.chain([bad, good], iter(lambda: random_prime(rng), None)))
    assert_exact(result, num, den)
    assert result.stats.primes_used[0] == good
    reasons = [why for q, why in result.stats.primes_rejected if q == bad]
    assert len(reasons) == 1 and "divides the normalizing coefficient of the denominator" in reasons[0]


# -- poles, failures, limits -----------------------------------------------------------------------------------------
def test_poles_and_black_box_failures_are_skipped():
    box, num, den = random_target(random.Random(18), 4, 6, 40, 10, constant=False)
    flaky_rng = random.Random(0)

    def flaky(p, points):   # undefined at a fifth of the points on top of the poles
        return [None if flaky_rng.random() < 0.2 else v for v in box(p, points)]
    result = sparse(flaky, 4, rng=random.Random(5))
    assert_exact(result, num, den)
    assert result.stats.undefined_probes > 0


def test_a_black_box_undefined_everywhere_is_reported():
    with pytest.raises(HKProofError, match="undefined almost everywhere"):
        sparse(lambda p, pts: [None] * len(pts), 3, rng=random.Random(1))


def test_a_degree_above_max_degree_is_a_resource_limit():
    box, _, _ = random_target(random.Random(19), 2, 9, 10, 5)
    with pytest.raises(ResourceLimitError, match="max_degree = 4"):
        sparse(box, 2, rng=random.Random(1), max_degree=4)


def test_a_black_box_that_answers_the_wrong_count_is_reported():
    with pytest.raises(HKProofError, match="returned 1 values for"):
        sparse(lambda p, pts: [1], 2, rng=random.Random(1))


def test_the_budget_stops_a_long_reconstruction_promptly():
    box, _, _ = random_target(random.Random(20), 8, 10, 3000, 300)
    start = time.monotonic()
    with pytest.raises(BudgetExhausted):
        sparse(box, 8, rng=random.Random(1), budget=Budget(0.5))
    assert time.monotonic() - start < 10          # a hang guard, not a timing claim


class _CountingBudget(Budget):
    """A budget without a deadline that records, at each check, the lines fitted since the previous check."""

    def __init__(self) -> None:
        super().__init__()
        self.fitted = 0
        self.between: list[int] = []

    def check(self, doing: str) -> None:
        self.between.append(self.fitted)
        self.fitted = 0


def test_lines_are_probed_and_fitted_in_waves_between_budget_checks(monkeypatch):
    """No batch of lines runs unchecked: at most LINES_PER_WAVE lines are fitted between two budget checks (a
    structural test: the first so(4) flow's batches of thousands of lines once overran a 100 s budget by 90 s)."""
    from hkproof.algebra import sparse_reconstruction as fr
    budget = _CountingBudget()
    original = fr.fit_lines

    def counted(nodes, *args):
        budget.fitted += len(nodes)
        return original(nodes, *args)
    monkeypatch.setattr(fr, "fit_lines", counted)
    monkeypatch.setattr(fr, "LINES_PER_WAVE", 8)
    box, num, den = random_target(random.Random(22), 4, 7, 150, 20)
    assert_exact(sparse(box, 4, rng=random.Random(2), budget=budget), num, den)
    assert max(budget.between) <= 8 and sum(budget.between) + budget.fitted > 40


def test_a_large_exponential_sum_checks_the_budget_between_chunks(monkeypatch):
    from hkproof.algebra import sparse_interpolation as si
    monkeypatch.setattr(si, "LEAVES", 4)
    calls: list[str] = []

    class Counting(Budget):
        def check(self, doing: str) -> None:
            calls.append(doing)
    with Counting(None).active():
        ExponentialSum(((1, b) for b in range(1, 18)), 101)
    assert len(calls) == 4                       # five chunks of at most 4 terms, a check before each later one


# -- mapper and progress ---------------------------------------------------------------------------------------------
def test_a_mapper_runs_the_batches_and_progress_is_reported():
    box, num, den = random_target(random.Random(21), 5, 7, 200, 30)
    jobs: list[int] = []
    reports: list[dict] = []

    def pool_map(fn, items):
        jobs.extend(len(points) for _, points in items)
        with ThreadPoolExecutor(2) as pool:
            return list(pool.map(fn, items))
    result = sparse(box, 5, rng=random.Random(6), mapper=pool_map, batch_size=64,
                                  progress=reports.append)
    assert_exact(result, num, den)
    assert sum(jobs) == result.stats.probes and max(jobs) <= 64
    assert reports and all("probes" in r for r in reports)


def test_a_process_pool_runs_the_batches():
    box, num, den = random_target(random.Random(22), 3, 5, 30, 8)
    with ProcessPoolExecutor(2) as pool:
        result = sparse(box, 3, rng=random.Random(7), mapper=lambda fn, jobs: pool.map(fn, jobs))
    assert_exact(result, num, den)


# -- large targets (outside the default suite) -----------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("n,terms", [(6, 1000), (8, 3000), (10, 10000)])
def test_large_sparse_targets(n, terms):
    box, num, den = random_target(random.Random(n), n, 12, terms, terms // 10)
    assert_exact(sparse(box, n, rng=random.Random(n)), num, den)


def test_a_shift_too_large_for_memory_is_a_clean_limit(monkeypatch):
    """The shifted contributions are counted; above SHIFTED_TERMS_LIMIT the engine raises ResourceLimitError (what
    discover reports as a stage stopped by a limit), never an allocation failure that aborts the process."""
    from hkproof.algebra import sparse_reconstruction as fr
    from hkproof.errors import ResourceLimitError
    monkeypatch.setattr(fr, "SHIFTED_TERMS_LIMIT", 0)
    num = {(1, 0, 0, 0): 1, (0, 1, 1, 0): 3, (0, 0, 0, 4): 1}
    den = {(1, 2, 1, 2): 1, (2, 2, 2, 0): 1}
    with pytest.raises(ResourceLimitError, match="shifted terms|shift's contributions") as info:
        sparse(RationalBox(4, [num], [den]), 4, rng=random.Random(1))
    assert info.value.limit == "0 shifted terms per reconstruction"


def test_engines_with_equal_seeds_share_their_probes_whatever_the_degrees():
    """Every point an engine probes is drawn from its seed and the stage's key alone: two coordinates of one vector
    black box (a common denominator, numerators of different degrees and supports), rebuilt with equal seeds, meet at
    most of their points (a memoized vector black box pays once), and each is still exact."""
    rng = random.Random(31)
    den = random_sparse_polynomial(rng, 3, 4, 5, constant=False)
    targets = [(RationalBox(3, [num], [den]), *primitive(num, den))
               for num in (random_sparse_polynomial(rng, 3, d, 12) for d in (3, 6))]
    asked: list[set] = [set(), set()]

    def component(k: int):
        def box(p, points):
            asked[k].update((p, tuple(x)) for x in points)
            return targets[k][0](p, points)
        return box
    for k, (_, num, den) in enumerate(targets):
        assert_exact(sparse(component(k), 3, rng=random.Random(7)), num, den)
    shared = asked[0] & asked[1]
    assert len(shared) >= len(asked[0]) // 2, (len(shared), len(asked[0]), len(asked[1]))
    other = set()
    sparse(lambda p, pts: (other.update((p, tuple(x)) for x in pts), targets[1][0](p, pts))[1], 3,
           rng=random.Random(8))
    assert not other & asked[1]                         # another seed, other points


def test_memoized_values_compute_each_point_once_in_order():
    from hkproof.algebra.reconstruction import memoized_values
    asked: list[list[tuple[int, ...]]] = []

    def compute(points):
        asked.append(list(points))
        return [sum(x) for x in points]
    memo: dict = {}
    assert memoized_values(memo, [[1, 2], [3, 4], [1, 2]], compute) == [3, 7, 3]
    assert memoized_values(memo, [(3, 4), (5, 6)], compute) == [7, 11]
    assert asked == [[(1, 2), (3, 4)], [(5, 6)]]
