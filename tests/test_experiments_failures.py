"""Where each method fails, hkproof says so instead of answering wrongly."""
from __future__ import annotations

import random
from fractions import Fraction

import flint
import mpmath
import numpy as np
import pytest

from hkproof.algebra.linalg import rank_q
from hkproof.dynamics import kahan_map
from hkproof.experiments import ExactQ, Float64, Modular, MPMath, ProfileProblem, make_scene, parse_basis
from hkproof.experiments.profiles_mod_p import ModP, UnluckyPrimeError
from hkproof.algebra.sampling import random_rationals
from hkproof.experiments.points import near_singular_point
from hkproof.experiments.profiles import AMBIGUOUS, SINGULAR
from hkproof.experiments.pslq import agreement, pslq_relations
from hkproof.experiments.relations import find_relations

ET_VALUES = {"eps": "1/3", "a1": 1, "a2": 2, "a3": -3}


def _problem(system, values, basis):
    f = kahan_map(system)
    return ProfileProblem(make_scene(f, values), parse_basis(f.ring, basis))


def test_float_rank_near_delta_zero_is_ambiguous_not_wrong():
    """Near Delta = 0 a plain numerical rank goes wrong; hkproof's float answer is right or 'ambiguous'."""
    problem = _problem("euler-top", ET_VALUES, "x1**2, x2**2, x3**2, 1")
    rng = random.Random(3)
    naive_wrong = flagged = 0
    for _ in range(8):
        x = near_singular_point(problem.scene, rng, Fraction(1, 10**12))
        exact = problem.profile(x, ExactQ(), with_kernel=False)
        fl = problem.profile(x, Float64(), with_kernel=False)
        assert exact.dimension == 2
        assert fl.verdict in (AMBIGUOUS, SINGULAR) or fl.dimension == 2
        flagged += fl.verdict in (AMBIGUOUS, SINGULAR)
        rows = Float64().profile(problem.scene, problem.compiled, [flint.fmpq(v.numerator, v.denominator)
                                                                   for v in x]).rows
        naive_wrong += 4 - np.linalg.matrix_rank(np.array(rows)) != 2
    assert flagged >= 4 and naive_wrong >= 1


def test_an_unlucky_prime_is_detected_and_replaced():
    """A small prime can drop a rank (a non-basis would look like d = 1); a second prime exposes it."""
    problem = _problem("euler-top", ET_VALUES, "x1**2, x2**2, x3")
    x = [flint.fmpq(1, 2), flint.fmpq(2, 3), flint.fmpq(-3, 4)]
    exact = ExactQ().profile(problem.scene, problem.compiled, x).ranks
    unlucky = None
    for p in range(11, 5000):
        if flint.fmpz(p).is_prime():
            try:
                if ModP(p).profile(problem.scene, problem.compiled, x).ranks != exact:
                    unlucky = p
                    break
            except UnluckyPrimeError:
                continue
    assert unlucky is not None, "no unlucky prime below 5000 for this point"
    profile = problem.profile(x, Modular(primes=[unlucky]))
    assert profile.dimension == 0 and profile.dims == [2, 1, 0]
    assert unlucky in [u["prime"] for u in profile.certainty["unlucky_primes"]]
    assert unlucky not in profile.certainty["primes"]


def test_a_prime_dividing_det_m_on_the_orbit_is_replaced():
    problem = _problem("euler-top", ET_VALUES, "x1**2, x2**2, x3**2, 1")
    x = [flint.fmpq(1, 2), flint.fmpq(2, 3), flint.fmpq(-3, 4)]
    bad = next(p for p in range(11, 5000) if flint.fmpz(p).is_prime() and _raises(problem, x, p))
    profile = problem.profile(x, Modular(primes=[bad]))
    assert profile.dimension == 2 and "det M" in profile.certainty["unlucky_primes"][0]["reason"]


def _raises(problem, x, p) -> bool:
    try:
        ModP(p).profile(problem.scene, problem.compiled, x)
    except UnluckyPrimeError:
        return True
    return False


def test_pslq_below_the_precision_it_needs_misses_relations_but_reports_none_wrong():
    f = kahan_map("clebsch")
    values = {"eps": "1/10", "w1": "1/10", "w2": "1/5", "w3": "3/10"}
    exact = find_relations(f, ["p1**2, p2**2, p3**2, 1"]).relations
    at = {k: Fraction(v) for k, v in values.items()}
    low = pslq_relations(f, ["p1**2, p2**2, p3**2, 1"], values, digits=8)
    right, recovered = agreement(low, exact, at)
    assert right == len(low.relations) and recovered < 2


def test_pslq_at_a_single_rational_point_finds_a_spurious_relation():
    """Kernel coordinates at a rational point are rationals: PSLQ there finds relations that do not persist,
    which is why hkproof samples points with every digit random and keeps only recurring relations."""
    f = kahan_map("clebsch")
    values = {"eps": "1/10", "w1": "1/10", "w2": "1/5", "w3": "3/10"}
    problem = _problem("clebsch", values, "p1**2, p2**2, p3**2, 1")
    exact = [r.row_at({k: Fraction(v) for k, v in values.items()})
             for r in find_relations(f, ["p1**2, p2**2, p3**2, 1"]).relations]
    rng = random.Random(0)
    spurious = 0
    for _ in range(4):
        x = random_rationals(rng, len(f.variables))
        c = ExactQ().kernel(ExactQ().profile(problem.scene, problem.compiled, x), 1)[0]
        with mpmath.workdps(30):
            rel = mpmath.pslq([mpmath.mpf(int(v.p)) / int(v.q) for v in (c[0], c[1])] + [mpmath.mpf(1)],
                              maxcoeff=10**6, maxsteps=10**5)
        full = [rel[0], rel[1], 0, rel[2]]
        spurious += rank_q(exact + [full]) > rank_q(exact)
    assert spurious >= 1


def test_a_tiny_true_singular_value_is_not_taken_for_zero():
    """Near Delta = 0, f^2(x) comes back close to x: X has a singular value ~1e-27 that is not zero.
    At 30 digits alone it looks like noise (a wrong d); the check at 60 digits makes the answer 'ambiguous'."""
    problem = _problem("clebsch", {"eps": "1/10", "w1": "1/10", "w2": "1/5", "w3": "3/10"}, "p1**2, p2**2, p3**2, 1")
    rng = random.Random(7)
    unchecked_wrong = 0
    for _ in range(3):
        x = near_singular_point(problem.scene, rng, Fraction(1, 10**9))
        exact = problem.profile(x, ExactQ(), with_kernel=False)
        unchecked = problem.profile(x, MPMath(30, confirm="never"), with_kernel=False)
        checked = problem.profile(x, MPMath(30), with_kernel=False)
        unchecked_wrong += unchecked.dims != exact.dims and unchecked.verdict not in (AMBIGUOUS, SINGULAR)
        assert checked.dims == exact.dims or checked.verdict in (AMBIGUOUS, SINGULAR)
    assert unchecked_wrong >= 1


@pytest.mark.slow
def test_float_paths_are_never_wrong_on_hard_points():
    """Large eps, long orbits and points near Delta = 0: right or 'ambiguous', never a wrong profile."""
    f = kahan_map("clebsch")
    rng = random.Random(5)
    cases = [({"eps": "1", "w1": "1/10", "w2": "1/5", "w3": "3/10"},
              "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, m1*p1, m2*p2, m3*p3, 1", False),
             ({"eps": "1/10", "w1": "1/10", "w2": "1/5", "w3": "3/10"}, "p1**2, p2**2, p3**2, 1", True)]
    for values, basis, near in cases:
        problem = _problem("clebsch", values, basis)
        for _ in range(8):
            x = near_singular_point(problem.scene, rng, Fraction(1, 10**9)) if near else random_rationals(rng, len(f.variables))
            exact = problem.profile(x, ExactQ(), with_kernel=False).dims
            for arithmetic in (Float64(), MPMath(30), MPMath(60)):
                p = problem.profile(x, arithmetic, with_kernel=False)
                assert p.dims == exact or p.verdict in (AMBIGUOUS, SINGULAR), (arithmetic.name, x)


def test_exact_rows_in_integers_agree_with_rational_products():
    """ExactQ evaluates a basis over the common denominator of the point (IntegerPoly); the generic loop of rational
    products gives the same rows on a basis with rational coefficients, a constant and a rational function, and a
    vanishing denominator is a ZeroDivisionError as before."""
    from hkproof.experiments.arithmetics import FieldArithmetic
    problem = _problem("euler-top", ET_VALUES, "x1**2/3 - 5*x2/7, x1*x2*x3/(x3 + 2), -2/9, x3**4")
    exact = ExactQ()
    prep = exact.prepare(problem.scene, problem.compiled)
    rng = random.Random(5)
    for _ in range(20):
        x = [flint.fmpq(rng.randrange(-50, 50), rng.randrange(1, 40)) for _ in range(3)]
        if x[2] == -2:
            continue
        assert exact.basis_row(prep, x) == FieldArithmetic.basis_row(exact, prep, x)
    with pytest.raises(ZeroDivisionError):
        exact.basis_row(prep, [flint.fmpq(1), flint.fmpq(1, 2), flint.fmpq(-2)])
    with pytest.raises(ZeroDivisionError):
        FieldArithmetic.basis_row(exact, prep, [flint.fmpq(1), flint.fmpq(1, 2), flint.fmpq(-2)])
