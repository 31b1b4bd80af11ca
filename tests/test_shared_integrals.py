"""hk.integrals.shared_integrals: which integrals of one Kahan map another map also preserves (sec. 7)."""
from __future__ import annotations

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.integrals import shared_integrals
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"  # Prop. "dET first HK basis"
WITNESS = {"x1": 1, "x2": 2, "x3": -1, "eps": "1/5", "a1": 1, "a2": 2, "a3": -3}


def _run(other: KahanMap, limit: int = 2000) -> tuple[list[str], Certificate]:
    f = kahan_map("euler-top")
    cert = Certificate("t", "t", "-", "-")
    integrals = {"c1": Frac.parse(f.ring, C1), "x1^2": Frac.parse(f.ring, "x1**2")}
    return shared_integrals(cert, integrals, other, "test", WITNESS, "Q(x, eps, a)", limit), cert


def test_the_euler_top_preserves_c1_not_x1_squared():
    shared, cert = _run(kahan_map("euler-top"))
    assert shared == ["c1"]
    assert [s.status for s in cert.steps] == [Status.VERIFIED, Status.VERIFIED]


def test_a_perturbed_field_preserves_neither():
    other = KahanMap(QuadraticField("et-perturbed", ("x1", "x2", "x3"), ("a1", "a2", "a3"),
                                    ("a1*x2*x3", "a2*x3*x1", "a3*x1*x2 + x1**2"), "perturbed Euler top"))
    assert _run(other)[0] == []


def test_above_the_symbolic_limit_a_point_agreement_is_evidence_only():
    shared, cert = _run(kahan_map("euler-top"), limit=0)
    assert shared == ["c1"] and cert.steps[-1].status is Status.EVIDENCE_EXACT


def test_max_jacobian_rank_skips_poles_and_counts_independent_integrals():
    from hkproof.hk.independence import max_jacobian_rank
    f = kahan_map("euler-top")
    c1 = Frac.parse(f.ring, C1)
    d1 = Frac.parse(f.ring, "a2*(1 - eps**2*a3*a1*x2**2)/(a2*x1**2 - a1*x2**2)")
    pole = {"x1": 1, "x2": 1, "x3": 1, "eps": 1, "a1": 1, "a2": 1, "a3": 2}  # a1 x2^2 - a2 x1^2 = 0
    good = {"x1": 1, "x2": 2, "x3": 3, "eps": "1/3", "a1": 1, "a2": 5, "a3": -2}
    assert max_jacobian_rank([c1, d1], f.variables, [pole, good]) == 2
    assert max_jacobian_rank([c1, c1 * c1], f.variables, [pole, good]) == 1
    assert max_jacobian_rank([], f.variables, [good]) == 0
