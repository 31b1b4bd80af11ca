"""algebra.factored (sums of products over factored denominators) against Frac arithmetic and sympy's exact values,
and hk.completion's refusals."""
from __future__ import annotations

import random

import pytest
import sympy

from hkproof.algebra import Frac, Ring
from hkproof.algebra.factored import Quotient, factor, sum_of_products
from hkproof.dynamics.catalogue import kahan_map
from hkproof.errors import HKProofError
from hkproof.hk.completion import complete_coordinates
from hkproof.hk.reduced import Relation
from tests.sympy_bridge import poly_from_sympy

R = Ring(("x", "y", "eps"))
SYMS = sympy.symbols("x y eps")


def _random_frac(rng: random.Random) -> tuple[Frac, sympy.Expr]:
    def poly() -> sympy.Expr:
        while True:
            p = sum(rng.randint(-4, 4) * SYMS[0] ** rng.randint(0, 2) * SYMS[1] ** rng.randint(0, 2)
                    * SYMS[2] ** rng.randint(0, 1) for _ in range(3))
            if p != 0:
                return sympy.expand(p)
    shared = [sympy.expand(SYMS[0] + SYMS[1]), sympy.expand(SYMS[2] ** 2 - SYMS[0]), sympy.Integer(6)]
    num, den = poly(), sympy.expand(poly() * rng.choice(shared) ** rng.randint(0, 2))
    return Frac(R, poly_from_sympy(R, num)[0], poly_from_sympy(R, den)[0]), num / den


@pytest.mark.parametrize("seed", range(25))
def test_sum_of_products_agrees_with_sympy(seed):
    rng = random.Random(seed)
    terms, expected = [], sympy.Integer(0)
    for _ in range(rng.randint(1, 3)):
        factors = [_random_frac(rng) for _ in range(rng.randint(1, 3))]
        terms.append([f for f, _ in factors])
        expected += sympy.Mul(*[e for _, e in factors])
    got = sum_of_products(terms)
    for _ in range(3):      # sympy's exact value at rational points where no denominator vanishes
        at = {x: sympy.Rational(rng.randint(-50, 50), rng.randint(1, 9)) for x in SYMS}
        want = expected.subs(at)
        if want.is_finite:
            assert got.to_sympy().subs(at) == want
    plain = sum((_product(t) for t in terms), Frac(R, 0))
    assert (got.num, got.den) == (plain.num, plain.den)    # the same lowest terms and sign as Frac arithmetic


@pytest.mark.parametrize("seed", range(10))
def test_sum_of_products_reduces_terms_not_in_lowest_terms(seed):
    """Quotient inputs (num and den sharing factors) give the lowest terms that Frac arithmetic gives; a wrong
    cofactor in one term changes the sum."""
    rng = random.Random(100 + seed)
    terms = [[_random_frac(rng)[0] for _ in range(rng.randint(1, 2))] for _ in range(rng.randint(1, 3))]
    common = R.gen("x") * 3 + R.gen("eps") ** 2 + 1
    loose = [[Quotient(R, f.num * common, f.den * common) for f in t] for t in terms]
    got, plain = sum_of_products(loose), sum((_product(t) for t in terms), Frac(R, 0))
    assert (got.num, got.den) == (plain.num, plain.den)
    wrong = [[Quotient(R, loose[0][0].num * 2, loose[0][0].den), *loose[0][1:]], *loose[1:]]
    assert sum_of_products(wrong) != plain


def _product(factors):
    out = Frac(R, 1)
    for f in factors:
        out = out * f
    return out


def test_factor_divides_out_known_factors_and_agrees_with_flint():
    """A denominator that is a known one times new factors is factored by dividing out the known irreducibles and
    factoring the rest: the same content and irreducible factors with multiplicities as FLINT's own factorization,
    whether the known factors come first or not, with a repeated factor and a negative content."""
    x, y, e = (R.gen(v) for v in R.names)
    known = (x + y * e + 3) * (x ** 2 - y) ** 2 * e
    bigger = -6 * known * (x + y * e + 3) * (y ** 3 + x * e - 1) * (x - 2)
    factor(known)
    for p in (bigger, known * (x - 2), -known):
        content, factors = factor(p)
        want_content, want = p.factor()
        assert content == want_content
        assert sorted((str(q), k) for q, k in factors) == sorted((str(q), k) for q, k in want)


def test_learned_factors_and_polynomials_that_share_a_fingerprint():
    """`learn_factors` makes a later factorization of their product one of divisions, with FLINT's answer; two
    different polynomials with the same fingerprint (length, degrees, first and last coefficient) are told apart."""
    from hkproof.algebra.factored import _fingerprint, learn_factors
    x, y, e = (R.gen(v) for v in R.names)
    pieces = [x * y + e ** 2 + 7, x ** 3 - 5 * y * e + 1]
    learn_factors(pieces)
    product = 4 * pieces[0] ** 2 * pieces[1]
    content, factors = factor(product)
    want_content, want = product.factor()
    assert content == want_content and sorted((str(q), k) for q, k in factors) == sorted((str(q), k) for q, k in want)
    p, q = x ** 2 + 2 * x * y + 5 * e + 3, x ** 2 + 2 * x * e + 5 * y + 3
    assert _fingerprint(p) == _fingerprint(q) and p != q
    assert [str(g) for g, _ in factor(p)[1]] == [str(p)] and [str(g) for g, _ in factor(q)[1]] == [str(q)]


def test_completion_refuses_relations_that_leave_the_wrong_number_of_unknowns():
    f = kahan_map("clebsch-flow2")
    lifted = f.ring.extend(["L"])
    basis = [Frac.parse(f.ring, t) for t in ("p1**2", "p2**2", "m1*p1")]
    one_relation = [Relation([Frac(lifted, 1), Frac(lifted, -1)], Frac(lifted, 0))]   # a1 = a2: one unknown left
    with pytest.raises(HKProofError, match="leave 1 unknowns free"):
        complete_coordinates(f, [basis], one_relation, {"L": Frac(f.ring, 1)}, ((0,), Frac(f.ring, 1)), [0])
    with pytest.raises(HKProofError, match="homogeneous"):
        complete_coordinates(f, [basis], [Relation([Frac(lifted, 1), Frac(lifted, -1)], Frac(lifted, 1))],
                             {"L": Frac(f.ring, 1)}, ((0,), Frac(f.ring, 1)), [0])
    with pytest.raises(HKProofError, match="no relations"):
        complete_coordinates(f, [basis], [], {"L": Frac(f.ring, 1)}, ((0,), Frac(f.ring, 1)), [0])
    with pytest.raises(HKProofError, match="relation rows of length 3"):
        complete_coordinates(f, [basis], [Relation([Frac(lifted, 1)] * 3, Frac(lifted, 0))], {"L": Frac(f.ring, 1)},
                             ((0,), Frac(f.ring, 1)), [0])


def test_components_fixed_by_the_found_ones():
    """u = columns . t with t = (t0, t1): u2 = t0 + L t1 and u3 = t1 follow from u0 = t0, u1 = t1 (with L
    substituted); from u0 alone neither does, but u0 fixes a component that is a multiple of it."""
    from hkproof.hk.completion import _determined, generic_point
    from hkproof.hk.transport import Substitution
    lifted = R.extend(["L"])
    one, zero, big_l = Frac(lifted, 1), Frac(lifted, 0), Frac.parse(lifted, "L")
    columns = [[one, zero], [zero, one], [one, big_l], [zero, one], [big_l * 2, zero]]
    value_l = Frac.parse(R, "x/(1 + eps**2*y)")
    sigma = Substitution(lifted, R, {"L": value_l})
    point = generic_point(lifted.names)
    found = {0: Frac.parse(R, "x*y/(x + 1)"), 1: Frac.parse(R, "1/(x + 1)")}
    got = _determined(columns, found, [2, 3], sigma, point)
    assert got[2] == found[0] + value_l * found[1] and got[3] == found[1]
    assert _determined(columns, {0: found[0]}, [2, 3], sigma, point) == {}
    assert _determined(columns, {0: found[0]}, [2, 3, 4], sigma, point) == {4: 2 * value_l * found[0]}
    assert _determined([[zero, zero], *columns[1:]], {0: Frac(R, 0)}, [2], sigma, point) == {}


def test_found_components_carried_block_to_block_by_the_symmetry():
    """Images (0 -> 1, perm) then (1 -> 2, perm): target component k is tau(source component perm[k]); the
    normalized last element is not an unknown, and components already found are kept."""
    from hkproof.hk.block_system import BlockSymmetry
    from hkproof.hk.completion import _carried
    x = Frac.parse(R, "x")
    tau = BlockSymmetry(lambda h: h * x, lambda kmap: True, ((0, 1, (1, 0, 2)), (1, 2, (1, 0, 2))))
    a0 = Frac.parse(R, "y")
    got = _carried({0: a0}, [2, 2, 2], tau)
    assert got == {3: a0 * x, 4: a0 * x * x}
    assert _carried({0: a0, 3: Frac(R, 5)}, [2, 2, 2], tau) == {4: Frac(R, 5) * x}
