"""algebra.lattice_identity: a polynomial identity decided at the points of a unisolvent lattice after a weighted
dehomogenization -- agrees with the plain expansion, and each shortcut is refused where it would be unsound."""
from __future__ import annotations

import random

import flint
import pytest

from hkproof.algebra import Frac
from hkproof.algebra.lattice_identity import horner, plan_lattice, vanishes_on_lattice
from hkproof.algebra.ring import get_ring
from hkproof.budget import Budget
from hkproof.dynamics import kahan_map
from hkproof.errors import BudgetExhausted
from hkproof.hk.row_check import row_holds
from hkproof.hk.reduced import prove_by_evenness
from hkproof.proof.certificate import Certificate

R = get_ring(("x", "y", "eps", "a", "b"))
X, Y, E, A, B = R.gens()


def bihomogeneous(rng: random.Random, degree: int, terms: int, top: int = 2) -> flint.fmpz_mpoly:
    """A random polynomial homogeneous under (x, y, eps) -> (l x, l y, eps / l) and (a, b, eps) -> (m a, m b,
    eps / m): each monomial x^i y^(d-i+k) eps^k a^j b^(k-j)."""
    out = R.constant(0)
    for _ in range(terms):
        k, i = rng.randrange(top + 1), rng.randrange(degree + 1)
        j = rng.randrange(k + 1)
        out += rng.randrange(-9, 10) * X ** i * Y ** (degree - i + k) * E ** k * A ** j * B ** (k - j)
    return out


def zero_identity(seed: int, top: int = 2) -> tuple[dict, list]:
    """T_(1,0) F1 + T_(0,1) F2 with T_(1,0) = G F2, T_(0,1) = -G F1: zero, and not by inspection."""
    rng = random.Random(seed)
    f1, f2, g = bihomogeneous(rng, 2, 12), bihomogeneous(rng, 2, 12), bihomogeneous(rng, 3, 30, top)
    return {(1, 0): g * f2, (0, 1): -g * f1}, [f1, f2]


@pytest.mark.parametrize("seed", range(4))
def test_a_zero_identity_vanishes_on_its_lattice_and_a_perturbed_one_does_not(seed):
    terms, factors = zero_identity(seed)
    assert horner(terms, factors).is_zero()
    plan = plan_lattice(terms, factors, R.names, ("eps", "a", "b"), ("a", "b"))
    assert len(plan.ones) == 2 and "eps" in plan.ones        # two gradings: eps and a or b set to 1
    assert plan.lattice == tuple(n for n in ("a", "b") if n not in plan.ones)
    assert vanishes_on_lattice(terms, factors, plan) == (True, None)
    bad = dict(terms)
    bad[(1, 0)] = terms[(1, 0)] + X * Y ** 2 * E * A        # one more term, of the same weights
    holds, point = vanishes_on_lattice(bad, factors, plan_lattice(bad, factors, R.names, ("eps", "a", "b"), ("a", "b")))
    assert not holds and point is not None and not horner(bad, factors).is_zero()


def test_a_polynomial_zero_at_all_but_the_last_lattice_point_is_refuted():
    """R = x prod_{c < 5} (a - c): zero at a = 0..4; its degree 5 puts a = 5 on the lattice."""
    t = X
    for c in range(5):
        t = t * (A - c)
    terms, factors = {(0,): t}, [Y]
    plan = plan_lattice(terms, factors, R.names, ("eps", "a", "b"), ("a", "b"))
    assert "a" not in plan.ones and plan.degree == 5          # not homogeneous in a: a stays on the lattice
    assert vanishes_on_lattice(terms, factors, plan) == (False, {"a": 5, "b": 0} if "b" in plan.lattice else {"a": 5})


def test_eps_is_not_set_to_1_when_the_identity_is_not_homogeneous():
    """R = (eps - 1) x vanishes at eps = 1 only: the gradings must not allow that shortcut."""
    terms, factors = {(1,): E - 1}, [X]
    plan = plan_lattice(terms, factors, R.names, ("eps", "a", "b"), ("a", "b"))
    assert "eps" not in plan.ones
    assert vanishes_on_lattice(terms, factors, plan)[0] is False


def test_forked_children_share_the_lattice_and_find_the_same_point():
    terms, factors = zero_identity(7, top=9)
    plan = plan_lattice(terms, factors, R.names, ("eps",), ("a", "b"))   # eps only: a and b both on the lattice
    assert plan.ones == ("eps",) and plan.points >= 64
    assert vanishes_on_lattice(terms, factors, plan, jobs=2) == (True, None)
    bad = {(1, 0): terms[(1, 0)] + X * Y ** 2 * E ** 2 * A ** 2, (0, 1): terms[(0, 1)]}
    plan = plan_lattice(bad, factors, R.names, ("eps",), ("a", "b"))
    assert vanishes_on_lattice(bad, factors, plan, jobs=2)[0] is False


def test_the_lattice_respects_the_budget():
    terms, factors = zero_identity(3, top=9)
    plan = plan_lattice(terms, factors, R.names, ("eps",), ("a", "b"))
    for jobs in (1, 2):
        with Budget(0.0).active(), pytest.raises(BudgetExhausted):
            vanishes_on_lattice(terms, factors, plan, jobs=jobs)


def test_both_routes_of_a_row_check_agree_on_the_euler_top():
    f = kahan_map("euler-top")
    basis = [Frac.parse(f.ring, t) for t in ("x1**2", "x2**2", "x3**2")]
    sol = prove_by_evenness(Certificate("t", "t", "-", "-"), f, basis[:2], basis[2], ("c1", "c2"))
    horner_route = row_holds(f, basis[:2], basis[2], 1, sol, route="horner")
    lattice_route = row_holds(f, basis[:2], basis[2], 1, sol, route="lattice")
    assert horner_route.holds and lattice_route.holds
    assert "expanded" in horner_route.route and "principal lattice" in lattice_route.route
    bad = [sol[0] + Frac.parse(f.ring, "eps**2*a1"), sol[1]]
    assert not row_holds(f, basis[:2], basis[2], 1, bad, route="lattice")
    assert not row_holds(f, basis[:2], basis[2], 1, bad, route="horner")


def test_exponents_past_int64_do_not_fake_a_grading():
    """R = y - y (x z)^(2^64) is not zero. With int64 exponent arithmetic the summand weight 4 * 2^62 wrapped to 0
    (so every grading seemed to hold) and the exponent sum 2^63 of F wrapped negative (so the size guard passed):
    x = z = 1 was allowed and R(x = z = 1) = 0 was read as R = 0. Exact arithmetic finds the one grading that holds
    (x and z of opposite weights): one of them alone is set to 1, and the identity is refuted."""
    ring = get_ring(("x", "y", "z"))
    x, y, z = ring.gens()
    terms, factors = {(0,): y, (4,): -y}, [x ** 2 ** 62 * z ** 2 ** 62]
    assert not horner(terms, factors).is_zero()
    for lattice in ((), ("z",)):
        plan = plan_lattice(terms, factors, ring.names, ("x", "z"), lattice)
        assert len(plan.ones) <= 1
        holds, point = vanishes_on_lattice(terms, factors, plan)
        assert not holds and point is not None


def test_degree_bounds_per_parameter_cut_the_lattice_and_still_find_the_last_point():
    """R = x a(a-1)(a-2) b(b-1)(b-2): degree 3 in a and in b, 6 in all; zero on the lower set {a, b <= 3, a + b <= 6}
    except at (3, 3), its 16 points against 28 on the principal lattice of degree 6."""
    t = X
    for c in range(3):
        t = t * (A - c) * (B - c)
    plan = plan_lattice({(0,): t}, [Y], R.names, ("eps",), ("a", "b"))
    assert (plan.degree, plan.degrees, plan.points) == (6, (3, 3), 16)
    assert vanishes_on_lattice({(0,): t}, [Y], plan) == (False, {"a": 3, "b": 3})
    assert vanishes_on_lattice({(0,): t - t}, [Y], plan) == (True, None)
