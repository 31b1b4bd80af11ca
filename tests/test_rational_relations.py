"""Rational relations T P(U) = Q(U) among integrals at fixed parameters: found again, checked at fresh points,
and refused or empty where there is nothing to find."""
from __future__ import annotations

import json
import random

import flint
import pytest

from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.experiments.rational_relations import DependenceSearchError, find_rational_relations, monomials
from hkproof.algebra.sampling import random_rational
from hkproof.orchestration.registry import proven
from hkproof.theorems._clebsch import X, named, recall

AT = {"w1": 2, "w2": -3, "w3": 5, "eps": flint.fmpq(1, 3)}


def _clebsch_integrals():
    r = kahan_map("clebsch").ring
    abcd = proven("dc345-abcd")
    return recall(proven("dc-basis1-relations"), "J", r), {k: recall(abcd, k, r) for k in "ABCD"}


def test_monomials_with_a_cap():
    assert len(monomials(["A", "D"], 2)) == 6
    assert (0, 2) not in monomials(["A", "D"], 2, {"D": 1})


def test_j_in_terms_of_abcd_is_found_again():
    J, abcd = _clebsch_integrals()
    search = find_rational_relations(J, abcd, AT, X, target_name="J")
    assert search.dimension == 2
    # every relation found holds at a fresh point, exactly
    rng = random.Random(99)
    point = {v: random_rational(rng) for v in X}
    fixed = {**{k: flint.fmpq(v) for k, v in AT.items()}, **point}
    j, *u = (h.evaluate(fixed) for h in (J, *abcd.values()))
    for rel in search.relations:
        def poly(coefficients):
            out = flint.fmpq(0)
            for m, c in coefficients.items():
                term = c
                for x, e in zip(u, m):
                    term *= x ** e
                out += term
            return out
        assert j * poly(rel.denominator) == poly(rel.numerator)
    # the proven relation of dc-theta-dependence (P, Q linear in A, B, D) lies in the space found
    w1, w2, w3, e = (flint.fmpq(AT[k]) for k in ("w1", "w2", "w3", "eps"))
    mons = monomials(list(abcd), 1)
    p = {(1, 0, 0, 0): -e**2 * w1 / (w1 - w2), (0, 1, 0, 0): e**2 * w2 / (w1 - w2), (0, 0, 0, 1): e**2 * w3}
    q = {(1, 0, 0, 0): 1 / (w1 - w2), (0, 1, 0, 0): -1 / (w1 - w2), (0, 0, 0, 1): flint.fmpq(-1)}
    rows = [[rel.denominator.get(m, 0) for m in mons] + [rel.numerator.get(m, 0) for m in mons]
            for rel in search.relations]
    known = [p.get(m, 0) for m in mons] + [q.get(m, 0) for m in mons]
    assert flint.fmpq_mat(rows + [known]).rank() == 2


def test_nothing_to_find_gives_an_empty_space():
    J, abcd = _clebsch_integrals()
    h1 = named(kahan_map("clebsch"), "H1")   # not an integral of the map: no relation with integrals
    search = find_rational_relations(h1, abcd, AT, X, degrees=(1, 2))
    assert search.dimension == 0
    # the quadric eq. "ABCD dependence" (P = 0) is reported apart: a relation among A, B, C, D alone
    assert len(search.among_knowns) == 1 and " = 0" in search.among_knowns[0].text()


def test_every_parameter_must_be_fixed():
    J, abcd = _clebsch_integrals()
    with pytest.raises(DependenceSearchError, match="w3"):
        find_rational_relations(J, abcd, {"w1": 2, "w2": -3, "eps": 1}, X)


def test_cli(capsys):
    code = main(["depend", "euler-top", "--target", "h=(x1**2 + x2**2)/x3**2", "--on", "u=x1**2/x3**2",
                 "--on", "v=x2**2/x3**2", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["dimension"] == 1 and out["relations"][0]["relation"] == "h = (u + v)/(1)"
    assert main(["depend", "euler-top", "--target", "h=x1", "--on", "u=x2**2"]) == 1   # nothing found
    assert main(["depend", "euler-top", "--target", "h=x1", "--on", "no-such-claim:u"]) != 0


def test_bad_input_is_an_error_not_a_traceback():
    assert main(["depend", "euler-top", "--target", "h=x1", "--on", "u=x2", "--degrees", "-1", "2"]) == 2
    assert main(["depend", "euler-top", "--target", "h=x1+", "--on", "u=x2"]) == 2
    assert main(["depend", "euler-top", "--target", "h=x1", "--on", "u=x2", "--cap", "u=two"]) == 2
