"""The exact algebra against sympy on random inputs: fractions, parity, composition, determinants, Cramer, kernels."""
from __future__ import annotations

import random

import flint
import pytest
import sympy

from hkproof.algebra import Frac, Parity, Ring, cramer, det, homogenized_compose, nullspace_q, rank_mod_p, rank_q
from hkproof.algebra.linalg import rank_over_fraction_field, rank_q, solve_by_inverse
from hkproof.errors import ParseError, SingularPointError, SingularSystemError, UnknownSymbolError
from tests.sympy_bridge import poly_from_sympy

R = Ring(("x", "y", "eps", "a"))
X, Y, E, A = sympy.symbols("x y eps a")
E_ = Frac.parse(R, "eps")


def random_poly(rng: random.Random, terms: int = 4, degree: int = 3) -> sympy.Expr:
    expr = sympy.Integer(0)
    for _ in range(terms):
        c = sympy.Rational(rng.randint(-9, 9), rng.randint(1, 4))
        expr += c * X**rng.randint(0, degree) * Y**rng.randint(0, degree) * E**rng.randint(0, 2) * A**rng.randint(0, 1)
    return expr if expr != 0 else sympy.Integer(1)


def as_frac(expr: sympy.Expr) -> Frac:
    return Frac.parse(R, str(expr))


def same(f: Frac, expr: sympy.Expr) -> bool:
    return sympy.cancel(f.to_sympy() - expr) == 0


@pytest.mark.parametrize("seed", range(12))
def test_field_arithmetic_matches_sympy(seed):
    rng = random.Random(seed)
    p, q, r, s = (random_poly(rng) for _ in range(4))
    f, g = as_frac(p / q), as_frac(r / s)
    assert same(f + g, p / q + r / s)
    assert same(f * g, p / q * r / s)
    assert same(f - g, p / q - r / s)
    if r != 0:
        assert same(f / g, (p / q) / (r / s))
    assert same(f.derivative("x"), sympy.diff(p / q, X))


@pytest.mark.parametrize("seed", range(6))
def test_lowest_terms_and_sign(seed):
    rng = random.Random(seed)
    p, q, g = (random_poly(rng) for _ in range(3))
    f = as_frac(sympy.expand(p * g) / sympy.expand(-q * g))
    assert f == as_frac(-p / q)
    assert f.num.gcd(f.den).is_constant()
    assert f.den.coefficient(len(f.den) - 1) > 0


def test_parity_exact():
    assert Frac.parse(R, "(1 + eps**2*x)/(y - eps**4)").parity("eps") is Parity.EVEN
    assert Frac.parse(R, "eps*x/(1 + eps**2)").parity("eps") is Parity.ODD
    assert Frac.parse(R, "(1 + eps)/(1 - eps)").parity("eps") is Parity.NEITHER
    # even only after cancelling a non-even common factor (the paper's "miraculous cancellation")
    assert Frac.parse(R, "(1 + eps*x)*(1 + eps**2)/((1 + eps*x)*y)").is_even_in("eps")
    assert Frac.parse(R, "eps/(eps**3 + x*eps)").parity("eps") is Parity.EVEN      # odd over odd
    assert Frac(R, 0).parity("eps") is Parity.EVEN and Frac.parse(R, "eps**3").parity("eps") is Parity.ODD


@pytest.mark.parametrize("seed", range(6))
def test_parity_from_exponents_agrees_with_the_substitution_eps_to_minus_eps(seed):
    """The parity read from the exponents of num and den against its definition h(-eps) = +-h(eps), computed by
    sympy, on random functions built even, odd or neither."""
    rng = random.Random(seed)
    x, y, eps, a = sympy.symbols("x y eps a")
    def part(power: int) -> sympy.Expr:
        return sum(rng.randint(-3, 3) * x ** rng.randint(0, 2) * a ** rng.randint(0, 1) * eps ** (power + 2 * k)
                   for k in range(3)) + y * eps ** power
    for top, bottom in ((0, 0), (1, 1), (0, 1), (1, 0)):
        for h in (part(top) / part(bottom), (part(top) + eps ** (5 + top)) / part(bottom)):
            f = Frac.parse(R, str(h))
            flipped = sympy.cancel(h.subs(eps, -eps))
            want = Parity.EVEN if sympy.cancel(flipped - h) == 0 else \
                Parity.ODD if sympy.cancel(flipped + h) == 0 else Parity.NEITHER
            assert f.parity("eps") is want


@pytest.mark.parametrize("seed", range(4))
def test_homogenized_compose_is_substitution(seed):
    rng = random.Random(seed)
    p = random_poly(rng, 3, 2)
    n1, n2, d = (random_poly(rng, 2, 1) for _ in range(3))
    pp, _ = poly_from_sympy(R, p)
    imgs = [poly_from_sympy(R, sympy.expand(n))[0] for n in (n1, n2)]
    dd = poly_from_sympy(R, d)[0]
    # scale images consistently: they were cleared of denominators separately, so use Frac pullback instead
    f = Frac(R, pp).pullback(imgs, dd, ("x", "y"))
    ni = [R.to_sympy(i) for i in imgs]
    expected = p.subs({X: ni[0] / R.to_sympy(dd), Y: ni[1] / R.to_sympy(dd)}, simultaneous=True)
    assert same(f, sympy.Rational(1) * expected * poly_from_sympy(R, p)[1])
    q, deg = homogenized_compose(R, pp, ("x", "y"), imgs, dd)
    assert deg == max(sum(m[:2]) for m in pp.monoms())


def random_int_poly(rng: random.Random) -> sympy.Expr:
    return sum((rng.randint(-5, 5) * X**rng.randint(0, 1) * Y**rng.randint(0, 1) * E**rng.randint(0, 1)
                for _ in range(2)), sympy.Integer(0))


@pytest.mark.parametrize("n,seed", [(2, 0), (3, 1), (4, 2), (5, 3)])
def test_det_matches_sympy(n, seed):
    rng = random.Random(seed)
    entries = [[random_int_poly(rng) for _ in range(n)] for _ in range(n)]
    polys = [[poly_from_sympy(R, e)[0] for e in row] for row in entries]
    assert same(Frac(R, det(polys)), sympy.Matrix(entries).det(method="berkowitz"))


@pytest.mark.parametrize("n", [6, 9])
def test_laplace_and_bareiss_agree(n):
    from hkproof.algebra.linalg import _det_bareiss, _det_laplace
    rng = random.Random(n)
    polys = [[poly_from_sympy(R, random_int_poly(rng))[0] for _ in range(n)] for _ in range(n)]
    polys[1] = list(polys[0]) if n == 6 else polys[1]  # a singular case too
    assert _det_laplace(polys) == _det_bareiss(polys)


def test_cramer_matches_sympy():
    rng = random.Random(7)
    a = [[random_poly(rng, 2, 1) / random_poly(rng, 1, 1) for _ in range(3)] for _ in range(3)]
    b = [random_poly(rng, 2, 1) for _ in range(3)]
    sol, _ = cramer([[as_frac(e) for e in row] for row in a], [as_frac(e) for e in b])
    values = [s.to_sympy() for s in sol]
    for row, rhs in zip(a, b):
        assert sympy.cancel(sympy.together(sum(e * v for e, v in zip(row, values)) - rhs)) == 0


def test_cramer_singular_system_is_reported():
    row = [Frac.parse(R, "x"), Frac.parse(R, "y")]
    with pytest.raises(SingularSystemError):
        cramer([row, [r * 2 for r in row]], [Frac(R, 1), Frac(R, 2)])


def test_rank_over_fraction_field():
    v = [Frac.parse(R, "x/(1+eps)"), Frac.parse(R, "y")]
    w = [Frac.parse(R, "x*y/(1+eps)"), Frac.parse(R, "y**2")]
    assert rank_over_fraction_field([v, w]) == 1
    assert rank_over_fraction_field([v, [Frac(R, 1), Frac(R, 0)]]) == 2


@pytest.mark.parametrize("seed", range(4))
def test_rank_with_a_big_right_hand_side_column(seed):
    # relations with small coefficients and a big right-hand side: consistent iff the rhs respects the dependence
    rng = random.Random(seed)
    big = [as_frac(random_poly(rng, 6, 4) / random_poly(rng, 5, 3)) for _ in range(2)]
    rows = [[Frac(R, 1), Frac.parse(R, "a"), big[0]], [Frac.parse(R, "eps"), Frac.parse(R, "a*eps"), big[0] * E_],
            [Frac(R, 0), Frac(R, 1), big[1]]]
    assert rank_over_fraction_field(rows) == 2
    rows[1][2] = rows[1][2] + 1
    assert rank_over_fraction_field(rows) == 3
    assert sympy.Matrix([[x.to_sympy() for x in row] for row in rows]).rank(simplify=True) == 3


def test_is_ratio_compares_without_reducing():
    g = Frac.parse(R, "(x + y)/(1 + eps*a)")
    k = R.ctx.from_dict({(1, 0, 2, 0): 3, (0, 0, 0, 0): 1})  # 3 x eps^2 + 1
    assert g.is_ratio(g.num * k, g.den * k)
    assert not g.is_ratio(g.num * k, g.den * k + 1)
    assert not g.is_ratio(g.num * k + 1, g.den * k)
    assert Frac(R, 0).is_ratio(R.ctx.from_dict({}), k)
    with pytest.raises(ZeroDivisionError):
        g.is_ratio(g.num, R.ctx.from_dict({}))


def test_parse_is_memoized_but_errors_are_not():
    assert Frac.parse(R, "x/(1 + eps)") is Frac.parse(R, "x/(1 + eps)")
    for _ in range(2):
        with pytest.raises(ParseError):
            Frac.parse(R, "x/(1 - 1)")


@pytest.mark.parametrize("seed", range(5))
def test_nullspace_q_matches_sympy(seed):
    rng = random.Random(seed)
    rows = [[rng.randint(-3, 3) for _ in range(5)] for _ in range(3)]
    rows.append([rows[0][j] + 2 * rows[1][j] for j in range(5)])
    kernel = nullspace_q(rows)
    m = sympy.Matrix(rows)
    assert len(kernel) == len(m.nullspace()) == 5 - rank_q(rows)
    for v in kernel:
        assert all(sum(sympy.Rational(int(x.p), int(x.q)) * r for x, r in zip(v, row)) == 0 for row in rows)
    assert rank_mod_p(rows, 1000003) == m.rank()


def test_evaluation_and_errors():
    f = Frac.parse(R, "x/(y - 1)")
    assert f.evaluate({"x": 3, "y": "1/2", "eps": 0, "a": 0}) == -6
    with pytest.raises(SingularPointError):
        f.evaluate({"x": 3, "y": 1, "eps": 0, "a": 0})
    with pytest.raises(UnknownSymbolError):
        Frac.parse(R, "x + z")
    with pytest.raises(ParseError):
        Frac.parse(R, "x +* y")
    with pytest.raises(ParseError):
        Frac.parse(R, "x/0")


def test_specialize_to_smaller_ring():
    f = Frac.parse(R, "(x + a*eps)/(y + a/3)")
    small = R.drop(["a"])
    g = f.specialize({"a": "3/2"}, small)
    assert g == Frac.parse(small, "(x + 3*eps/2)/(y + 1/2)")


def test_solve_by_inverse_agrees_with_cramer():
    rows = [[Frac.parse(R, t) for t in row] for row in (["1", "x", "0"], ["y", "1", "1"], ["0", "x - y", "2"])]
    rhs = [Frac.parse(R, t) for t in ("x**3*y + 1", "y**2/(x + 1)", "x*y - 5")]
    sol = solve_by_inverse(rows, rhs)
    assert sol == cramer(rows, rhs)[0]
    assert all(sum((a * v for a, v in zip(row, sol)), Frac(R, 0)) == b for row, b in zip(rows, rhs))
    assert solve_by_inverse(rows, [rhs[0] + 1, *rhs[1:]]) != sol


def test_echelon_mod_p_grows_with_the_rank_and_stays_below_the_rank_over_q():
    """Rows added one by one: the rank mod p grows exactly when a row is independent mod p; a row with no image mod
    p, or one dependent mod p only, raises nothing, and the rank over Q is then larger (relation_space re-primes)."""
    from hkproof.algebra.modular import EchelonModP
    q = flint.fmpq
    p = 2 ** 61 - 1
    rows = [[q(1, 2), q(3, 5), q(0)], [q(1, 4), q(3, 10), q(0)], [q(0), q(1, 3), q(2)], [q(1), q(1), q(1)],
            [q(5), q(7), q(-3, 4)]]
    echelon = EchelonModP(p)
    assert [echelon.add(r) for r in rows] == [True, False, True, True, False]
    assert echelon.rank == rank_q(rows) == 3
    unlucky = [[q(1, p), q(3, 5)], [q(p), q(0)], [q(0), q(p)]]
    echelon = EchelonModP(p)
    assert [echelon.add(r) for r in unlucky] == [False, False, False] and rank_q(unlucky) == 2
    other = EchelonModP(1000003)
    assert [other.add(r) for r in unlucky] == [True, True, False]


def test_lcm_of_repeated_and_trivial_denominators():
    """lcm skips repeated polynomials and 1 but not a multiple: the same result as the product over the gcds."""
    from hkproof.algebra.linalg import lcm
    x, y, eps = (R.gen(v) for v in ("x", "y", "eps"))
    a, b, c = x + eps, y ** 2 - 3, x * y + 1
    one = R.constant(1)
    got = lcm([a * b, one, a * b, b * c, a * b, a ** 2])
    assert got == a ** 2 * b * c or got == -(a ** 2 * b * c)
    assert lcm([one, one]) == one


@pytest.mark.parametrize("seed", range(6))
def test_the_gcd_after_small_factors_is_flints_gcd(monkeypatch, seed):
    """linalg._gcd_after_small_factors: the shared monomial and the factors of A's small entries divided out first,
    then FLINT's gcd of the rest; the product is the gcd itself (up to sign), also when a small factor divides only
    one side, divides to a higher power on one side, or a big factor is shared."""
    import random

    from hkproof.algebra import linalg
    from hkproof.algebra.ring import get_ring
    monkeypatch.setattr(linalg, "BIG_GCD", 0)
    rng = random.Random(seed)
    ring = get_ring(("x", "y", "w1", "w2"))
    x, y, w1, w2 = (ring.gen(n) for n in ("x", "y", "w1", "w2"))

    def poly():
        return sum((rng.randint(-5, 5) * x ** rng.randint(0, 3) * y ** rng.randint(0, 3) * w1 ** rng.randint(0, 2)
                    for _ in range(6)), ring.constant(1))
    big, small = poly(), w1 - w2
    num = x ** rng.randint(0, 2) * small ** rng.randint(0, 3) * big * poly()
    den = x ** rng.randint(0, 2) * y * small ** rng.randint(0, 3) * big * poly()
    a = [[small * x, w1 + 3 * w2], [ring.constant(2), y ** 2 + w1]]
    got, want = linalg._gcd_after_small_factors(num, den, a), num.gcd(den)
    assert got == want or got == -want
    assert (num / got).gcd(den / got).is_one() or (num / got).gcd(den / got) == -ring.constant(1)


def test_nmod_matrix_takes_lists_numpy_arrays_and_numpy_scalars_alike():
    """Every form of rows the kernels mod p receive gives the same matrix (negative and big entries reduced)."""
    import numpy as np

    from hkproof.algebra.modular import nmod_matrix
    p = 10007
    plain = [[3, -2, 10 ** 30], [0, p + 5, 7]]
    want = flint.nmod_mat([[3, p - 2, 10 ** 30 % p], [0, 5, 7]], p)
    arrays = np.array([[3, p - 2, 10 ** 30 % p], [0, 5, 7]], dtype=np.int64)
    assert nmod_matrix(plain, p) == nmod_matrix(arrays, p) == nmod_matrix(list(arrays), p) == want
    assert nmod_matrix([[np.int64(v) for v in row] for row in arrays.tolist()], p) == want
    assert nmod_matrix([], p).nrows() == 0
