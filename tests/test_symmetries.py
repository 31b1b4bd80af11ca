"""Symmetries of a quadratic field (hk.symmetries) and the groups of step 5d they carry
(pipelines.discover.groups.carried_by_symmetry). Each symmetry found is checked on the Kahan map itself;
maps that are not symmetries are refused."""
from __future__ import annotations

import pytest
import sympy

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import get_system, kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.hk.symmetries import SignedPermutation, field_symmetries
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.groups import Group, IntegralBasis, carried_by_symmetry


def _equivariant_by_sympy(field: QuadraticField, sigma: SignedPermutation) -> bool:
    """sigma(F_v) = s_v F_pi(v), checked in sympy from the printed field (independent of FLINT)."""
    subs = {sympy.Symbol(v): s * sympy.Symbol(w) for v, w, s in sigma.variables}
    subs.update({sympy.Symbol(a): sympy.Symbol(b) for a, b in sigma.parameters})
    rhs = {v: sympy.sympify(t) for v, t in zip(field.variables, field.rhs_text, strict=True)}
    return all(sympy.expand(rhs[v].xreplace(subs) - s * rhs[w]) == 0 for v, w, s in sigma.variables)


@pytest.mark.parametrize("system, count", [("euler-top", 23), ("clebsch", 47), ("so4-euler-top", 191),
                                           ("so4-euler-top-flow2", 191), ("volterra-4", 7)])
def test_the_symmetries_found_are_symmetries_of_the_field_by_sympy(system, count):
    """The whole group is found (signs x permutations: 4 x 6 - 1 for the Euler top, 8 x 24 - 1 for so(4)); each
    element is an equivariance of the printed field, recomputed in sympy."""
    field = get_system(system)
    found = field_symmetries(field)
    assert len(found) == count == len({str(s) for s in found})
    assert all(_equivariant_by_sympy(field, s) for s in found[::max(1, len(found) // 12)])


def test_each_symmetry_of_the_euler_top_commutes_with_its_kahan_map():
    kmap = kahan_map("euler-top")
    assert all(s.commutes(kmap) for s in field_symmetries(kmap.field))


def test_a_signed_permutation_that_is_no_symmetry_is_refused():
    """so(4): the index cycle 2 -> 3 -> 4 -> 2 on m without permuting the parameters is no symmetry of the map (nor
    of the field); with the parameters permuted too, it is. A field with one coefficient changed loses it."""
    kmap = kahan_map("so4-euler-top")
    sigma = next(s for s in field_symmetries(kmap.field) if s.parameters == (("a2", "a3"), ("a3", "a4"), ("a4", "a2")))
    assert sigma.commutes(kmap)
    assert not SignedPermutation(sigma.variables).commutes(kmap)
    field = kmap.field
    broken = QuadraticField("broken", field.variables, field.parameters,
                            (field.rhs_text[0].replace("(a1 - a2)", "(a1 - 2*a2)"), *field.rhs_text[1:]))
    assert str(sigma) not in {str(s) for s in field_symmetries(broken)}


def test_a_group_of_so4_bases_is_carried_by_one_symmetry():
    """The three bases (m13^2, m24^2, 1, C, m13 m24), (m12^2, m34^2, 1, C, m12 m34), (m14^2, m23^2, 1, C, m14 m23)
    with C the Casimir: one symmetry carries the first to the others (a chain), and the replaced bases are its exact
    images, each function proportional to the one it replaces."""
    ctx = SearchContext.for_maps(kahan_map("so4-euler-top"))
    ring = ctx.kmap.ring
    casimir = Frac.parse(ring, "m12**2 + m13**2 + m14**2 + m23**2 + m24**2 + m34**2")

    def basis(i: str, j: str) -> IntegralBasis:
        names = [f"{i}**2", f"{j}**2", "1", "I1", f"{i}*{j}"]
        return IntegralBasis([Frac.parse(ring, n) for n in names[:3]] + [casimir, Frac.parse(ring, names[4])], names,
                             True)
    group = Group([(0, 4), (1, 4), (2, 4)], [basis("m13", "m24"), basis("m12", "m34"), basis("m14", "m23")])
    carried = carried_by_symmetry(ctx, group)
    assert carried.symmetry is not None and len(carried.images) == 2
    assert carried.symmetry.commutes(ctx.kmap)
    phase = set(ctx.kmap.variables)
    for src, dst in carried.images:
        images = [carried.symmetry.apply(h) for h in carried.order(carried.members[src])]
        assert images == carried.order(carried.members[dst])
        original = group.order(group.members[dst])
        assert not ((images[-1] / original[-1]).variables() & phase)            # the normalized one to itself
        assert all(any(not ((a / b).variables() & phase) for b in original) for a in images)
    assert carried.width == group.width


def test_a_group_no_symmetry_carries_is_left_alone():
    ctx = SearchContext.for_maps(kahan_map("so4-euler-top"))
    ring = ctx.kmap.ring
    one = IntegralBasis([Frac.parse(ring, t) for t in ("m13**2", "m24**2", "1", "m13*m24")],
                        ["m13**2", "m24**2", "1", "m13*m24"], True)
    other = IntegralBasis([Frac.parse(ring, t) for t in ("m12**2", "m13**2", "1", "m12*m34")],
                          ["m12**2", "m13**2", "1", "m12*m34"], True)
    group = Group([(0, 3), (1, 3)], [one, other])
    assert carried_by_symmetry(ctx, group) is group
