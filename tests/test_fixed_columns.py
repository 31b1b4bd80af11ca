"""The bivectors fixed by the flow of a linear symmetry (hkproof.hk.fixed_columns, issue 38): each basis vector is
checked against an independent sympy Lie derivative, their number equals the weight-0 columns of the torus, and a
class searched on them has the rank the torus' weight 0 has."""
from __future__ import annotations

import itertools

import random

import flint
import numpy as np
import pytest
import sympy

from hkproof.algebra.modular import rank_mod_p
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.fixed_columns import commutes_with_signs, fixed_columns
from hkproof.hk.poisson import pairs
from hkproof.hk.poisson_system import blocks, sign_symmetries
from hkproof.hk.torus import commuting_linear_fields, eigen_coordinates, generic_generator, semi_invariance_character
from hkproof.pipelines.poisson import _prime_and_torus, _Scene, with_integrals
from hkproof.pipelines.poisson_candidates import Denominator
from hkproof.proof.status import Status
from tests.test_poisson import sympy_check


def _rotation() -> flint.fmpq_mat:
    [a] = commuting_linear_fields(kahan_map("gaudin-2").field)
    return a


def _lie_derivative(a: flint.fmpq_mat, q: sympy.Matrix, xs: list[sympy.Symbol]) -> sympy.Matrix:
    """(L_X Q)^ij = X(Q^ij) - A_ik Q^kj - A_jk Q^ik, X = A x, with sympy alone."""
    n = len(xs)
    am = sympy.Matrix(n, n, [sympy.Rational(str(e)) for e in a.entries()])
    x = am * sympy.Matrix(xs)
    flow = q.applyfunc(lambda e: sum(x[l] * sympy.diff(e, xs[l]) for l in range(n)))
    return (flow - am * q - q * am.T).applyfunc(sympy.expand)


def test_each_fixed_vector_has_zero_lie_derivative_and_their_number_is_the_weight_zero_block() -> None:
    f = kahan_map("gaudin-2")
    a = _rotation()
    signs = sign_symmetries(f)
    assert commutes_with_signs(a, signs)
    xs = [sympy.Symbol(v) for v in f.variables]
    found = 0
    for block in blocks(f, 2, signs):
        basis = fixed_columns(f, block, a, flint.fmpq(0))
        found += len(basis)
        for vector in basis.vectors[:12]:
            q = sympy.zeros(6, 6)
            for c, k in vector:
                pair, m = block.columns[c]
                i, j = pairs(6)[pair]
                mono = sympy.Mul(*[x ** e for x, e in zip(xs, m)])
                q[i, j] += k * mono
                q[j, i] -= k * mono
            assert _lie_derivative(a, q, xs) == sympy.zeros(6, 6)
    torus = eigen_coordinates(a, 998244353)
    assert torus is not None
    weight_zero = sum(len(b.columns) for b in blocks(f, 2, [], torus) if b.character[-1] == 0)
    assert found == weight_zero


def test_coordinates_round_trip_and_refuse_a_vector_outside_the_span() -> None:
    f = kahan_map("gaudin-2")
    block = blocks(f, 3, sign_symmetries(f))[0]
    basis = fixed_columns(f, block, _rotation(), flint.fmpq(0))
    p = 1000003
    rng = random.Random(1)
    coords = [rng.randrange(p) for _ in range(len(basis))]
    vector = [0] * len(block.columns)
    for x, v in zip(coords, basis.vectors):
        for c, k in v:
            vector[c] = (vector[c] + x * k) % p
    assert basis.coordinates(vector, p) == coords
    moved = list(vector)
    moved[basis.vectors[0][-1][0]] = (moved[basis.vectors[0][-1][0]] + 1) % p
    assert basis.coordinates(moved, p) is None
    rows = np.array([[rng.randrange(p) for _ in block.columns] for _ in range(3)], dtype=np.int64)
    projected = basis.project(rows, p)
    assert [int(sum(int(r[c]) * x for c, x in enumerate(vector)) % p) for r in rows] == \
           [int(sum(int(r[b]) * x for b, x in enumerate(coords)) % p) for r in projected]


def test_the_character_of_a_semi_invariant_denominator() -> None:
    f = kahan_map("gaudin-2")
    a = _rotation()
    ring = f.ring
    s1, s2, s3 = (ring.gen(v) for v in ("s1", "s2", "s3"))
    assert semi_invariance_character(f, a, s1 ** 2 + s2 ** 2 + s3) == 0
    assert semi_invariance_character(f, a, s1) is None
    scaled = flint.fmpq_mat(6, 6, [1 if i == j else 0 for i in range(6) for j in range(6)])   # X = x: Euler's
    assert semi_invariance_character(f, scaled, s1 * s2 * s3) == 3


def test_the_fixed_coordinates_have_the_rank_of_the_torus_weight_zero() -> None:
    """D = 1 at degree 4: the rank mod p on the fixed coordinates equals the rank of the torus' weight-0 block (both
    full: the class is excluded), on 596 unknowns instead of the 1 570 columns of the sign block they lie in."""
    f = kahan_map("gaudin-2")
    rng = random.Random(0)
    a = generic_generator(commuting_linear_fields(f.field), rng)
    prime, torus = _prime_and_torus(rng, a)
    values = {"eps": flint.fmpq(3, 7), "b": flint.fmpq(5), "g": flint.fmpq(-2, 3)}
    one = Denominator("1", f.ring.constant(1))
    fixed = _Scene(f, prime, values, one, sign_symmetries(f), fixed=a)
    circle = _Scene(f, prime, values, one, [], torus=torus)
    [block] = fixed.blocks(4)
    [zero] = [b for b in circle.blocks(4) if b.character[-1] == 0]
    assert fixed.width(block) == len(zero.columns) < len(block.columns)
    rows, _ = fixed.system(block, rng, 40)
    ranks = rank_mod_p(rows.tolist(), prime), rank_mod_p(circle.system(zero, rng, 40)[0].tolist(), prime)
    assert ranks == (fixed.width(block), len(zero.columns))


@pytest.mark.slow       # about 10 minutes: the rebuild (3.5 min), the exact invariance (4 min), the Casimir search
def test_the_gaudin_magnets_invariant_bivector_of_rank_four_is_not_poisson() -> None:
    """The class F4^2 = (eps^2 b g s3 - 1)^2 at degree 6: its kernel (weight 0) is rebuilt on the fixed coordinates,
    proven invariant with eps, b and g symbolic, of rank 4, and NOT Poisson; sympy agrees at a random rational
    point (invariant, Jacobi fails), the note says that the class has no invariant Poisson structure (and a no-poisson
    theorem certifies it), and the four integrals are pairwise in involution with respect to it."""
    report = with_integrals(kahan_map("gaudin-2"), 6, only=["F4^2"])
    [s] = report.structures
    assert s.status is Status.VERIFIED and s.poisson is False and s.rank == 4
    ring = kahan_map("gaudin-2").ring
    s3, eps, b, g = (ring.gen(v) for v in ("s3", "eps", "b", "g"))
    assert s.bivector.denominator in ((eps ** 2 * b * g * s3 - 1) ** 2, -(eps ** 2 * b * g * s3 - 1) ** 2)
    assert sympy_check("gaudin-2", s.bivector) == (True, False)
    assert any("no invariant Poisson structure" in n for n in report.notes)
    [screened] = report.kernels                           # and the certificate of that: a no-poisson step
    assert screened.rebuilt and screened.no_poisson is not None and screened.no_poisson.status is Status.VERIFIED
    [(_, involution)] = report.involution                 # the four integrals in involution: a fact about Pi, no more
    assert involution.status is Status.VERIFIED and len(report.integrals) == 4


def test_jacobi_mod_p_of_a_screened_kernel_and_of_residue_bivectors() -> None:
    """--screen tests Jacobi mod p on a small kernel: Lotka-Volterra's xy passes (no theorem); a bivector that fails
    Jacobi over Z fails it mod p, one that holds holds; two Poisson members have dependent brackets (a member may be
    Poisson), two whose brackets are independent leave none."""
    from hkproof.algebra.ring import get_ring
    from hkproof.hk.poisson import Bivector, brackets_independent_mod, schouten
    report = with_integrals(kahan_map("lotka-volterra"), 2, integrals_degree=0, screen=True)
    assert [(k.name, k.dimension, k.jacobi_mod_p) for k in report.kernels] == [("1", 1, True)]
    assert "a member may satisfy Jacobi mod p" in report.text() and report.kernels[0].no_poisson is None
    names = ("x", "y", "z")
    ring = get_ring(names)
    x, y, z = (ring.gen(v) for v in names)
    one, zero = ring.constant(1), ring.constant(0)
    p = 1000003
    assert brackets_independent_mod([Bivector(ring, names, (y, zero, z), one)], p)            # v.curl v = z
    assert not brackets_independent_mod([Bivector(ring, names, (y * p, zero, z * p), one)], p)
    assert not brackets_independent_mod([Bivector(ring, names, (z, zero, zero), one)], p)
    assert not brackets_independent_mod([Bivector(ring, names, (z, zero, zero), one),
                                         Bivector(ring, names, (zero, zero, x), one)], p)     # both Poisson
    assert brackets_independent_mod([Bivector(ring, names, (y, zero, z), one),
                                     Bivector(ring, names, (zero, x * y, z * z), one)], p)
    # the values at points (from the jets of Q and D, no bracket expanded) give the coefficients' verdicts
    cases = [[Bivector(ring, names, (y, zero, z), one)], [Bivector(ring, names, (y * p, zero, z * p), one)],
             [Bivector(ring, names, (z, zero, zero), one), Bivector(ring, names, (zero, zero, x), one)],
             [Bivector(ring, names, (y, zero, z), one), Bivector(ring, names, (zero, x * y, z * z), one)],
             [Bivector(ring, names, (y * z, x, x * x), x + 2 * y), Bivector(ring, names, (x, zero, y), x + 2 * y)]]
    verdicts = []
    for members in cases:
        expanded = [{(k, m): int(c) % p for k, q in enumerate(schouten(a, b)) for m, c in q.to_dict().items()}
                    for a, b in itertools.combinations_with_replacement(members, 2)]
        keys = sorted({key for row in expanded for key in row})
        coefficients = bool(keys) and flint.nmod_mat([[row.get(k, 0) for k in keys] for row in expanded], p).rank() \
            == len(expanded)
        verdicts.append(brackets_independent_mod(members, p))
        assert verdicts[-1] == coefficients
    assert True in verdicts and False in verdicts


def test_bracket_relations_give_the_poisson_members_mod_p():
    """The relations among the brackets, as symmetric forms: c c^T lies in their span exactly for the members that
    satisfy Jacobi mod p (two constant bivectors, Poisson and compatible: the whole pencil), not for one that fails."""
    from hkproof.algebra.ring import get_ring
    from hkproof.hk.poisson import Bivector, bracket_relations_mod
    names = ("x", "y", "z")
    ring = get_ring(names)
    x, y, z = (ring.gen(v) for v in names)
    one, zero = ring.constant(1), ring.constant(0)
    p = 1000003
    members = [Bivector(ring, names, (one, zero, zero), one), Bivector(ring, names, (zero, zero, one), one),
               Bivector(ring, names, (y, zero, z), one)]                                       # the last: v.curl v = z
    forms = bracket_relations_mod(members, p)

    def in_span(c: list[int]) -> bool:
        vec = [[w[a][b] for a in range(3) for b in range(a, 3)] for w in forms]
        target = [c[a] * c[b] % p for a in range(3) for b in range(a, 3)]
        return flint.nmod_mat(vec + [target], p).rank() == flint.nmod_mat(vec, p).rank()
    assert len(forms) == 4                      # [v1, v1], [v2, v2], [v1, v2] and [v1, v3] vanish
    assert in_span([1, 0, 0]) and in_span([0, 1, 0]) and in_span([1, 5, 0])
    assert not in_span([0, 0, 1]) and not in_span([1, 0, 1])
    assert bracket_relations_mod(members[2:], p) == []
