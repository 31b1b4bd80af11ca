"""hk/linear_relations.py: printed relations and chains of relations as rows (sec. 6.7, eqs. "rel18_*")."""
from __future__ import annotations

import pytest

from hkproof.algebra import Frac
from hkproof.algebra.ring import get_ring
from hkproof.errors import ParseError
from hkproof.hk.linear_relations import parse_relation, parse_relation_chain, relation_rank, same_relation

R = get_ring(("x", "w"))


def test_chain_gives_consecutive_relations_with_known_moved_right():
    d = Frac.parse(R, "x**2")
    rels = parse_relation_chain(R, "a = w*b = c + d", ["a", "b", "c"], {"d": d})
    assert len(rels) == 2
    assert [str(c) for c in rels[0].coefficients] == ["1", "-w", "0"] and rels[0].rhs.is_zero()
    assert [str(c) for c in rels[1].coefficients] == ["0", "w", "-1"] and rels[1].rhs == d


def test_same_relation_and_rank():
    (a,) = parse_relation_chain(R, "2*a = w*b", ["a", "b"])
    (b,) = parse_relation_chain(R, "4*a - 2*w*b = 0", ["a", "b"])
    (c,) = parse_relation_chain(R, "4*a - 2*w*b = 1", ["a", "b"])
    assert same_relation(a, b) and not same_relation(a, c)
    assert relation_rank([a, b, c]) == 2


def test_nonlinear_chain_is_refused():
    with pytest.raises(ParseError):
        parse_relation_chain(R, "a = b = a*b", ["a", "b"])


@pytest.mark.parametrize("text", ["a/b = 1", "x/(a + 1) = b", "a**2 = w*b", "w*a*b = 0"])
def test_unknowns_in_a_denominator_or_a_product_are_refused(text):
    with pytest.raises(ParseError, match="not linear"):
        parse_relation(R, text, ["a", "b"])


def test_coefficients_with_a_denominator_and_absent_unknowns():
    rel = parse_relation(R, "a/(w + 1) + x*b/w = x**2/(w + 1)", ["a", "b", "c"])
    assert [str(c) for c in rel.coefficients] == ["(1)/(w + 1)", "(x)/(w)", "0"]
    assert rel.rhs == Frac.parse(R, "x**2/(w + 1)")
