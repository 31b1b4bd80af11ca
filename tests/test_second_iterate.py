"""hk.second_iterate: the plain composition f o f and the gcd interpolated in the parameters (sec. 6.2)."""
from __future__ import annotations

import random

import flint
import pytest

from hkproof.algebra.linalg import solve_overdetermined
from hkproof.dynamics.catalogue import kahan_map
from hkproof.errors import HKProofError, SingularSystemError
from hkproof.hk.second_iterate import interpolated_gcd, plain_composition
from hkproof.hk.symmetries import SignedPermutation
from hkproof.hk.translation import ParameterTranslation
from hkproof.dynamics.field import QuadraticField


def _points(n: int, seed: int = 1) -> list[tuple[int, int, int]]:
    rng = random.Random(seed)
    return [(rng.randint(1, 50), rng.randint(1, 50), rng.randint(-60, -1)) for _ in range(n)]


def test_interpolated_gcd_recovers_delta_of_f_for_the_euler_top():
    """gcd(Delta_h(N, Delta), Delta_h(N, Delta)) is Delta_h(N, Delta) itself: every coefficient of x^e is a form of
    degree |e| in a (a -> mu a, eps -> eps/mu), so 60 generic points fix it."""
    f = kahan_map("euler-top")
    nums, delta = f.explicit
    exact = plain_composition(f, {"d": delta})[0]["d"]
    assert interpolated_gcd(f, delta, delta, _points(60), sum) == exact


def test_interpolated_gcd_with_the_cyclic_symmetry_needs_one_gcd_per_orbit():
    """The Euler top commutes with the index shift (x, a) (checked); Delta_h(N, Delta) is invariant, so 20 points
    and their orbits (60 points) fix it as 60 points do. A relabeling in the wrong direction (a 3-cycle against the
    other, not a symmetry) gives samples that no forms fit, and is refused."""
    f = kahan_map("euler-top")
    _, delta = f.explicit
    shift = SignedPermutation(tuple((f"x{k}", f"x{k % 3 + 1}", 1) for k in (1, 2, 3)),
                              tuple((f"a{k}", f"a{k % 3 + 1}") for k in (1, 2, 3)))
    assert shift.commutes(f)
    exact = plain_composition(f, {"d": delta})[0]["d"]
    assert interpolated_gcd(f, delta, delta, _points(20), sum, shift) == exact
    wrong = SignedPermutation(tuple((f"x{k}", f"x{k % 3 + 1}", 1) for k in (1, 2, 3)),
                              tuple((f"a{k % 3 + 1}", f"a{k}") for k in (1, 2, 3)))
    with pytest.raises(HKProofError, match="unlucky"):
        interpolated_gcd(f, delta, delta, _points(20), sum, wrong)


def test_interpolated_gcd_on_the_slice_of_a_parameter_translation():
    """The Euler top in inertia differences, x1' = (a2 - a3) x2 x3 (cyclic), is invariant under a -> a + c: samples
    moved to the slice a3 = 0 fix every coefficient with forms in (a1, a2), so 4 gcds and their orbits (12 points)
    give Delta_h(N, Delta) where 20 gcds are needed without the translation; a translation that does not shift
    every parameter is refused, and too few points stay refused."""
    field = QuadraticField("euler-top-differences", ("x1", "x2", "x3"), ("a1", "a2", "a3"),
                           ("(a2 - a3)*x2*x3", "(a3 - a1)*x3*x1", "(a1 - a2)*x1*x2"), "test")
    f = kahan_map(field)
    _, delta = f.explicit
    shift = SignedPermutation(tuple((f"x{k}", f"x{k % 3 + 1}", 1) for k in (1, 2, 3)),
                              tuple((f"a{k}", f"a{k % 3 + 1}") for k in (1, 2, 3)))
    translation = ParameterTranslation(("a1", "a2", "a3"), "a3")
    assert shift.commutes(f) and translation.field_is_invariant(field)
    exact = plain_composition(f, {"d": delta})[0]["d"]
    assert interpolated_gcd(f, delta, delta, _points(4), sum, shift, translation) == exact
    with pytest.raises(SingularSystemError):
        interpolated_gcd(f, delta, delta, _points(4), sum, shift)
    with pytest.raises(SingularSystemError):
        interpolated_gcd(f, delta, delta, _points(1), sum, shift, translation)
    with pytest.raises(HKProofError, match="must shift exactly"):
        interpolated_gcd(f, delta, delta, _points(3), sum, shift, ParameterTranslation(("a1", "a2"), "a2"))


def test_interpolated_gcd_refuses_unlucky_and_too_few_points():
    f = kahan_map("euler-top")
    _, delta = f.explicit
    with pytest.raises(HKProofError, match="drops"):
        interpolated_gcd(f, delta, delta, [(1, 0, 2)] + _points(59), sum)
    with pytest.raises(SingularSystemError):
        interpolated_gcd(f, delta, delta, _points(12), sum)


def test_solve_overdetermined_is_exact_and_refuses_a_rank_deficient_system():
    a = flint.fmpq_mat([[1, 0], [0, 1], [1, 1]])
    assert solve_overdetermined(a, [2, 3, 5]) == [2, 3]
    with pytest.raises(SingularSystemError):
        solve_overdetermined(flint.fmpq_mat([[1, 1], [2, 2], [3, 3]]), [1, 2, 3])


def test_the_clebsch_composition_is_the_lift_of_its_restriction_to_w3_0():
    """Table "f2" is read on the slice w3 = 0 (theorems.clebsch_f2): a translation-invariant P_h(N, Delta) is the
    lift of its restriction. Checked on m1 p1 and on the m1-numerator's top part m1 (cheap), and a polynomial that
    is not invariant (w3 m1) is not the lift of its restriction."""
    from hkproof.algebra.fraction import Frac
    from hkproof.theorems._clebsch import TRANSLATION

    f = kahan_map("clebsch")
    small = TRANSLATION.slice_map(f)
    r = f.ring
    for text in ("m1*p1", "m1", "w1*p2**2 + m3"):
        p = Frac.parse(r, text).num
        full = plain_composition(f, {"p": p})[0]["p"]
        assert TRANSLATION.is_invariant(Frac(r, full)) == TRANSLATION.is_invariant(Frac(r, p))
        p0 = TRANSLATION.restrict(Frac(r, p)).num
        sliced = plain_composition(small, {"p": p0})[0]["p"]
        assert (TRANSLATION.lift(Frac(small.ring, sliced), r) == Frac(r, full)) is TRANSLATION.is_invariant(
            Frac(r, p))


def test_every_claim_reading_the_plain_composition_declares_it_shared():
    """Claim.shares: a claim whose prover calls plain_second_iterate (an lru-cached f o f) must name it, or a run with
    two workers may compute f o f in both (dc-f2-reduced did not: 17.6 s on the cold worker against 8.6 s)."""
    import inspect

    from hkproof.orchestration.registry import REGISTRY, load_all
    from hkproof.theorems.clebsch_f2 import PLAIN_F2
    load_all()
    readers = {c.id for c in REGISTRY.values() if "plain_second_iterate(" in inspect.getsource(c.prover)}
    assert readers == {"dc-f2-plain", "dc-f2-reduced"}
    assert {c.id for c in REGISTRY.values() if c.shares == PLAIN_F2} == readers
