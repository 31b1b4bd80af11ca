"""algebra.modular_identity: an identity decided modulo primes beyond twice a proven coefficient bound -- the same
verdicts as the expansion and the lattice, a bound that is reached, and a wrong verdict where the primes fall short."""
from __future__ import annotations

import random

import pytest

from hkproof.algebra import Frac
from hkproof.algebra.lattice_identity import horner
from hkproof.algebra.modular_identity import coefficient_bound, primes_beyond, vanishes_modulo
from hkproof.algebra.ring import get_ring
from hkproof.budget import Budget
from hkproof.dynamics import kahan_map
from hkproof.errors import BudgetExhausted
from hkproof.hk.reduced import prove_by_evenness
from hkproof.hk.row_check import RouteCosts, decide_identity, row_holds
from hkproof.proof.certificate import Certificate

R = get_ring(("x", "y", "eps", "a"))
X, Y, E, A = R.gens()
ROUTES = ("horner", "lattice", "modular")


def max_coefficient(p) -> int:
    return max((abs(int(c)) for c in p.coeffs()), default=0)


def test_a_row_of_the_euler_top_is_decided_alike_by_all_three_routes_and_a_perturbed_one_refuted_by_each():
    f = kahan_map("euler-top")
    basis = [Frac.parse(f.ring, t) for t in ("x1**2", "x2**2", "x3**2")]
    sol = prove_by_evenness(Certificate("t", "t", "-", "-"), f, basis[:2], basis[2], ("c1", "c2"))
    bad = [sol[0] + Frac.parse(f.ring, "eps**2*a1"), sol[1]]
    for route in ROUTES:
        good_row, bad_row = (row_holds(f, basis[:2], basis[2], 1, s, route=route) for s in (sol, bad))
        assert good_row.holds and good_row.by == route
        assert not bad_row.holds and bad_row.by == route
    assert "modulo" in row_holds(f, basis[:2], basis[2], 1, bad, route="modular").route


def test_a_synthetic_identity_agrees_on_all_three_routes():
    """G (F1 F2) - (G F1) F2 with eps and a inside: zero; one more term of the same weights: not zero."""
    rng = random.Random(3)
    f1 = sum(rng.randrange(-9, 10) * X ** i * Y ** (2 - i) for i in range(3)) + E * A * X ** 3
    f2 = sum(rng.randrange(-9, 10) * X ** i * Y ** (1 - i) for i in range(2)) + E * A ** 2 * Y ** 3
    g = (X + 3 * Y) ** 4 + 5 * E * A * X ** 4 * Y ** 2
    terms = {(1, 1): g, (1, 0): -g * f2}
    bad = {**terms, (0, 0): X * Y * E * A}
    for route in ROUTES:
        assert decide_identity(terms, [f1, f2], R.names, ("eps", "a"), route, "t", "F").holds
        assert not decide_identity(bad, [f1, f2], R.names, ("eps", "a"), route, "t", "F").holds


def test_the_bound_is_reached_by_a_binomial_identity():
    """(1 + x + ... + x^n) (1 + x)^n: the coefficient of x^n is sum_k C(n, k) = 2^n = |T|_inf |1 + x|_1^n."""
    for n in (1, 5, 40, 100):
        t = sum((X ** k for k in range(n + 1)), R.constant(0))
        terms, factors = {(n,): t}, [1 + X]
        assert coefficient_bound(terms, factors) == 2 ** n == max_coefficient(horner(terms, factors))


@pytest.mark.parametrize("seed", range(6))
def test_the_bound_holds_on_random_identities(seed):
    rng = random.Random(seed)

    def poly(n: int):
        return sum((rng.randrange(-99, 100) * X ** rng.randrange(4) * Y ** rng.randrange(4) * A ** rng.randrange(3)
                    for _ in range(n)), R.constant(0))
    factors = [poly(4), poly(6), poly(2)]
    terms = {tuple(rng.randrange(4) for _ in factors): poly(8) for _ in range(5)}
    expanded = horner(terms, factors)
    assert 0 < max_coefficient(expanded) <= coefficient_bound(terms, factors)


def test_primes_whose_product_does_not_exceed_twice_the_coefficients_give_a_wrong_verdict():
    """R = T (1 + x)^n - (its expansion with M subtracted from the coefficient of x^n) = M x^n is not zero, yet it
    vanishes modulo two primes of product M <= 2 * (its largest coefficient M). The primes the bound asks for
    refute it."""
    n = 70
    t = sum((X ** k for k in range(n + 1)), R.constant(0))
    q1, q2 = primes_beyond(2 ** 64)[:2]
    m = q1 * q2
    terms, factors = {(n,): t, (0,): -(horner({(n,): t}, [1 + X]) - m * X ** n)}, [1 + X]
    assert horner(terms, factors) == m * X ** n
    assert vanishes_modulo(terms, factors, [q1, q2]) == (True, None)          # wrong: R != 0
    primes = primes_beyond(coefficient_bound(terms, factors))
    assert len(primes) > 2 and vanishes_modulo(terms, factors, primes)[0] is False


def test_the_primes_are_as_few_as_the_bound_allows():
    assert primes_beyond(0) == []                    # every summand is 0: so is R
    for bound in (1, 2 ** 61, 2 ** 62, 2 ** 200, 3 ** 500):
        primes = primes_beyond(bound)
        product = 1
        for p in primes[:-1]:
            product *= p
        assert product <= 2 * bound < product * primes[-1] and all(p < 2 ** 63 for p in primes)


def test_the_cost_model_takes_the_primes_only_for_large_coefficients_on_many_cores():
    """Coefficients of ~950 bits: on two cores the expansion over Z stays cheaper (measured), on 16 cores the primes
    run side by side; with small coefficients (one prime) the expansion over Z wins everywhere."""
    big = 3 ** 600
    f1, f2 = big * X + Y, big * Y - X
    g = (X + Y) ** 6
    terms = {(1, 1): g, (1, 0): -g * f2, (0, 0): X * Y}
    many, two = (RouteCosts(terms, [f1, f2], R.names, ("eps",), jobs=j) for j in (16, 2))
    assert many.cheapest == "modular" and two.cheapest == "horner" and len(many.modular.primes) > 2
    small = {(1, 1): g, (1, 0): -g * (Y - X)}
    assert RouteCosts(small, [X + Y, Y - X], R.names, ("eps",), jobs=16).cheapest == "horner"
    assert vanishes_modulo(terms, [f1, f2], many.modular.primes, jobs=2)[0] is False
    del terms[(0, 0)]
    assert vanishes_modulo(terms, [f1, f2], many.modular.primes, jobs=2) == (True, None)


def test_the_modular_route_respects_the_budget():
    terms, factors = {(3,): (X + Y) ** 5}, [X - Y]
    primes = primes_beyond(coefficient_bound(terms, factors))
    for jobs in (1, 2):
        with Budget(0.0).active(), pytest.raises(BudgetExhausted):
            vanishes_modulo(terms, factors, primes * 2, jobs=jobs)


@pytest.mark.parametrize("system", ["euler-top", "zhukovsky-volterra-1"])
def test_darboux_identities_are_decided_alike_by_all_three_routes(system):
    from hkproof.hk.darboux import darboux_identity_checks
    from hkproof.pipelines.darboux import search_darboux
    f = kahan_map(system)
    found = search_darboux(f, 2)
    d = found.darboux[0]
    polys = [d.poly, d.poly + f.ring.gen(f.variables[0]) ** 2 + 1]
    for route in ROUTES:
        checks = darboux_identity_checks(f, found.atoms, d.cofactor, polys, route=route)
        assert [c.holds for c in checks] == [True, False] and {c.by for c in checks} == {route}
