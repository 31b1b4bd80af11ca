"""The Clebsch flows (end of sec. 6): general map, second-flow theorem, Phi0 for every flow, conjecture evidence."""
from __future__ import annotations

import contextlib

import pytest
import sympy

from hkproof.orchestration.registry import get_claim, proven
from hkproof.proof.status import Status
from hkproof.theorems.clebsch_flows.general import GENERAL_CLAIM, SECOND, THETA_RELATION
from tests.conftest import assert_group_certified


def test_second_flow_verified_with_correction():
    cert = proven("flow-second-theorem")
    assert cert.status is Status.VERIFIED, cert.render()
    assert any("w_j w_k E_i (not w_j w_k E_j)" in c for c in cert.corrections)


@pytest.mark.parametrize("key,text", [
    ("L", SECOND["L"].replace("1 + eps**2*w1*", "1 + 2*eps**2*w1*")),          # L with a changed coefficient
    ("rel4", "e1 - e2 - (w1 - w2)*e6 = 2*eps**2*w3**2*(w1 - w2)"),              # a relation with a wrong coefficient
    ("rel6", "e2 - e3 - (w2 - w3)*e4 = eps**2*w2**2*(w2 - w3)"),                # sixth relation not a consequence
    ("b_of_L0", "w_j*w_k*E_k"),                                                 # the corrected index must be E_i
])
def test_second_flow_perturbed_refuted(key, text):
    cert = get_claim("flow-second-theorem").prove({key: text})
    assert cert.status is not Status.VERIFIED


@pytest.mark.parametrize("key,text", [("flow2_b", "[-w2*w3, -w3*w1, -w1*w3]"), ("flow1_c", "[1, 1, 2]")])
def test_general_map_perturbed_refuted(key, text):
    assert get_claim("flow-general-map").prove({key: text}).status is not Status.VERIFIED


@pytest.mark.slow
def test_conjecture_for_every_flow_verified():
    cert = get_claim("flow-conjecture").prove()
    assert cert.status is Status.VERIFIED, cert.render()
    for case in ("z != 0: ", "z = 0: "):
        assert sum(s.name.startswith(case) for s in cert.steps) == 3, cert.render()


@pytest.mark.slow
def test_conjecture_with_a_wrong_dimension_refuted():
    assert get_claim("flow-conjecture").prove({"dim": "5"}).status is Status.REFUTED


def test_general_phi0_verified():
    cert = get_claim("flow-general-phi0").prove()
    assert cert.status is Status.VERIFIED, cert.render()


@pytest.mark.parametrize("key,text", [
    ("D", GENERAL_CLAIM["D"].replace("z + eps**2", "z + 2*eps**2")),
    ("rel4", "e1 - e2 - (w1 - w2)*e6 = eps**2*c3*(w1 - w2)"),
])
def test_general_phi0_perturbed_refuted(key, text):
    assert get_claim("flow-general-phi0").prove({key: text}).status is not Status.VERIFIED


@pytest.mark.slow      # 30-40 s; the default suite proves flow-theta-all through test_the_script_certifies_the_group
def test_theta_every_flow_with_w_symbolic():
    cert = get_claim("flow-theta-all").prove()
    assert cert.status is Status.VERIFIED, cert.render()
    assert any("sigma" in step.name for step in cert.steps)         # the transport of flow-second-theta


def test_theta_perturbed_relation_refuted():
    bad = THETA_RELATION.replace("(w2 - w3)*c1*(eps**2*L - c1)", "(w2 - w3)*c1*(eps**2*L - 2*c1)")
    assert get_claim("flow-theta-all").prove({"relation": bad}).status is not Status.VERIFIED


def test_the_transport_of_a_solution_needs_each_equation_carried():
    """flow-theta-all reads the transported Theta solution on the source: sigma0 (eps -> y eps) carries the first
    flow's system to the (y, 0) map's, so the step holds; a substitution that breaks the sign of eps (eps -> eps + y)
    or a target row that is not the image (H4 doubled) is refused, and so is a proportionality with a wrong entry."""
    from hkproof.algebra.fraction import Frac
    from hkproof.algebra.ring import get_ring
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.hk.transport import Substitution
    from hkproof.proof.certificate import Certificate, ProofStopped
    from hkproof.theorems._clebsch import recall
    from hkproof.theorems.clebsch_flows import general
    from hkproof.theorems.clebsch_flows.data import yz_map_at_z0
    first, g0 = kahan_map(general.FIRST), yz_map_at_z0()
    sol = [recall(proven("dc-theta"), k, first.ring) for k in general.THETA_NAMES]
    good = general.reduction_substitutions(proven("flow-reduction").formulas)[1]
    bad = Substitution(first.ring, g0.ring, {"eps": Frac.parse(g0.ring, "eps + y")})
    basis, h4 = general._theta_basis(g0)

    def status(sigma, target_h4):
        cert = Certificate("t", "t", "-", "-")
        with contextlib.suppress(ProofStopped):
            general._transported_solution(cert, sigma, (*general._theta_basis(first), []), g0,
                                          (basis, target_h4, []), sol, "z = 0")
        return cert.status
    assert status(good, h4) is Status.VERIFIED
    assert status(bad, h4) is not Status.VERIFIED
    assert status(good, h4 * 2) is not Status.VERIFIED
    r = get_ring(("x", "y"))
    x, y = Frac.parse(r, "x"), Frac.parse(r, "y")
    assert general._proportional([2 * x * y, 2 * y], [x * y, y])
    assert general._proportional([Frac(r, 0), y], [Frac(r, 0), x * y / x])
    assert not general._proportional([2 * x, 3 * y], [x, y]) and not general._proportional([Frac(r, 0), y], [x, y])


def test_the_general_flow_is_invariant_under_the_combined_shift():
    from hkproof.theorems.clebsch_flows.data import yz_map
    from hkproof.theorems.clebsch_flows.general import YZ_SHIFT
    assert all(YZ_SHIFT.is_invariant(c) for c in yz_map().components())
    assert "y -> y + (-z) c" in str(YZ_SHIFT)


def test_second_theta_perturbed_relation_refuted():
    bad = THETA_RELATION.replace("(w3 - w1)*c2*(eps**2*L - c2)", "(w3 - w1)*c2*(eps**2*L + c2)")
    assert get_claim("flow-second-theta").prove({"relation": bad}).status is not Status.VERIFIED


def test_flow_reduction_verified():
    cert = proven("flow-reduction")
    assert cert.status is Status.VERIFIED, cert.render()


@pytest.mark.parametrize("key,text", [
    ("w1_prime", "w1 + 2*y/z"),                # a wrong shift of one w
    ("eps_prime", "-z*eps"),                   # the inverse map, not the map
    ("eps_prime", "z**2*eps"),                 # a wrong rescaling of the step
    ("eps_prime_z0", "2*y*eps"),               # z = 0: a wrong rescaling
])
def test_flow_reduction_perturbed_refuted(key, text):
    assert get_claim("flow-reduction").prove({key: text}).status is not Status.VERIFIED


def test_substitution_refuses_bad_input():
    from hkproof.algebra.fraction import Frac
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.errors import HKProofError
    from hkproof.hk.transport import Substitution
    from hkproof.theorems.clebsch_flows.data import yz_map
    g, f2 = yz_map(), kahan_map("clebsch-flow2")
    with pytest.raises(HKProofError):
        Substitution(f2.ring, g.ring, {"nope": Frac(g.ring, 1)})            # not a variable of the source
    with pytest.raises(HKProofError):
        Substitution(f2.ring, g.ring, {"eps": Frac(f2.ring, 1)})            # image outside the target ring


@pytest.mark.parametrize("i", [1, -1])
def test_row_check_by_horner_agrees_with_substitution(i):
    """hk.row_check on the first flow's Phi0 kernel c_k = 1/J + eps^2 w_k (target 1: the Delta^2 branch)."""
    from hkproof.algebra.fraction import Frac
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.hk.reduced import check_solution
    from hkproof.hk.row_check import row_holds
    f = kahan_map("clebsch")
    r = f.ring
    basis = [Frac.parse(r, f"p{k}**2") for k in (1, 2, 3)]
    inv_j = Frac.parse(r, "(1 - eps**2*(w1*p1**2 + w2*p2**2 + w3*p3**2))/(p1**2 + p2**2 + p3**2)")
    good = [inv_j + Frac.parse(r, f"eps**2*w{k}") for k in (1, 2, 3)]
    bad = [good[0] + Frac.parse(r, "eps**4"), *good[1:]]
    one = Frac(r, 1)
    assert row_holds(f, basis, one, i, good) and check_solution(f, basis, one, [i], [], good)
    assert not row_holds(f, basis, one, i, bad) and not check_solution(f, basis, one, [i], [], bad)


def test_second_flow_relations_found_is_evidence():
    cert = get_claim("flow-second-relations-found").prove()
    assert cert.status is Status.EVIDENCE_EXACT, cert.render()


@pytest.mark.parametrize("key,text", [
    ("rel2_3", "a2*w2*(w1 - w3) - a3*w3*(w1 - w2) - a5*w1*w3*(w1 - w3) + a6*w1*w2*(w1 + w2) = 0"),
    ("rel2_9", "a1*w3 + a3*(w1 - w3) - a4*w2*w3 = 0"),
    ("rows01_theta", "17"),
    ("rel18_8", "(a3 - a1 - (w3 - w1)*a5)/(w2 - w3) = (b3 - b1 - (w3 - w1)*b5)/(w3 - w2)"),
])
def test_second_flow_relations_perturbed(key, text):
    cert = get_claim("flow-second-relations-found").prove({key: text})
    assert cert.status < Status.EVIDENCE_EXACT


@pytest.mark.parametrize("key,text", [
    ("phirel_11", "-La2*eps**2 + La3*eps**2 + a2*w1 - a3*w1 - a5*w1*(w1 - w3) + a6*w1*(w1 + w2) = 0"),
    ("rows0", "18"),
])
def test_second_flow_l_relations_perturbed(key, text):
    assert get_claim("flow-second-l-relations-found").prove({key: text}).status < Status.EVIDENCE_EXACT


@pytest.mark.slow
def test_second_flow_bases_345_with_w_symbolic():
    cert = get_claim("flow-second-bases-345").prove()
    assert cert.status is Status.VERIFIED, cert.render()
    assert {"a1", "b6", "c3"} <= set(cert.formulas)
    assert {"w1", "w2", "w3", "eps"} <= cert.values["a1"].variables()


@pytest.mark.slow
@pytest.mark.parametrize("old,new", [("a6*w1*(w1 - w2)", "a6*w1*(w1 + w2)"),      # changes the rank
                                     ("-La2*eps**2", "-2*La2*eps**2")])           # keeps the rank
def test_second_flow_bases_345_perturbed(old, new):
    from hkproof.theorems.clebsch_flows.second_flow_bases import SECOND_PHI_RELATIONS
    bad = SECOND_PHI_RELATIONS["phirel_11"].replace(old, new)
    assert bad != SECOND_PHI_RELATIONS["phirel_11"]
    assert get_claim("flow-second-bases-345").prove({"phirel_11": bad}).status < Status.VERIFIED


def test_substitution_injectivity_is_checked():
    """w1, w2 -> the same image is not injective; the flow reduction's substitution is."""
    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.theorems.clebsch_flows.data import REDUCTION, substitution, yz_map
    from hkproof.theorems.clebsch_flows.general import RANK_POINT
    f2, g = kahan_map("clebsch-flow2"), yz_map()
    point = {k: v for k, v in RANK_POINT.items() if k in g.ring.names}
    moved = ("eps", "w1", "w2", "w3")
    assert substitution(f2, g, REDUCTION).is_injective_at(moved, point)
    collapsed = {**REDUCTION, "w2": REDUCTION["w1"]}
    assert not substitution(f2, g, collapsed).is_injective_at(moved, point)


@pytest.mark.slow
def test_second_flow_kernel_coordinates_by_an_independent_route():
    """alpha, beta, gamma of flow-second-bases-345 (w symbolic) at a random rational point annihilate the rows
    i = 0 ... 4 along an orbit that sympy computes from the printed field (no hkproof map, no composition)."""
    from fractions import Fraction

    from hkproof.dynamics.catalogue import kahan_map
    from hkproof.orchestration.registry import proven
    from tests.sympy_bridge import kahan_orbit
    f = kahan_map("clebsch-flow2")
    cert = proven("flow-second-bases-345")
    values = {"eps": Fraction(1, 5), "w1": Fraction(3, 2), "w2": -2, "w3": Fraction(7, 3), "m1": 1, "m2": -2,
              "m3": Fraction(1, 3), "p1": 2, "p2": Fraction(-1, 2), "p3": 3}
    orbit = kahan_orbit([str(c) for c in f.field.rhs], f.variables, values, 4)
    _kernel_rows_hold(cert, values, orbit)


def _kernel_rows_hold(cert, at, orbit) -> None:
    """alpha, beta, gamma of `cert`, evaluated at the parameters `at`, annihilate the rows of Phi1, Phi2, Phi3 at
    every point of `orbit` (sympy arithmetic on the printed monomials)."""
    common = ("p1**2", "p2**2", "p3**2", "m1**2", "m2**2", "m3**2")
    for block, (letter, target) in enumerate(zip("abc", ("m1*p1", "m2*p2", "m3*p3"))):
        coords = [cert.values[f"{letter}{j}"].evaluate(at) for j in range(1, 7)]
        for point in orbit:
            env = {k: sympy.Rational(v) for k, v in point.items()}
            row = [sympy.sympify(t).subs(env) for t in common]
            lhs = sum(sympy.Rational(int(c.p), int(c.q)) * v for c, v in zip(coords, row))
            assert lhs == sympy.sympify(target).subs(env), (block, point)


@pytest.mark.slow
def test_transported_kernel_coordinates_by_an_independent_route():
    """flow-conjecture's transport, z != 0: alpha, beta, gamma of the second flow taken at eps' = z eps and
    w' = w + y/z annihilate the rows i = 0 ... 3 along an orbit that sympy computes from the printed general field
    with b_k = y w_k - z w_i w_j (no hkproof map, no substitution code)."""
    from fractions import Fraction

    from hkproof.dynamics.catalogue import get_system
    from hkproof.orchestration.registry import proven
    from tests.sympy_bridge import kahan_orbit
    general = get_system("clebsch-general")
    cert = proven("flow-second-bases-345")
    eps, y, z = Fraction(1, 4), Fraction(2, 3), Fraction(-3, 2)
    w = {"w1": Fraction(1, 2), "w2": 3, "w3": Fraction(-5, 4)}
    x = {"m1": 2, "m2": Fraction(-1, 3), "m3": 1, "p1": -1, "p2": Fraction(5, 2), "p3": 2}
    b = {f"b{k + 1}": y * w[f"w{k + 1}"] - z * w[f"w{i + 1}"] * w[f"w{j + 1}"]
         for k, i, j in ((0, 1, 2), (1, 2, 0), (2, 0, 1))}
    orbit = kahan_orbit([str(c) for c in general.rhs], general.variables, {**x, **w, **b, "eps": eps}, 3)
    moved = {**x, "eps": z * eps, **{k: v + y / z for k, v in w.items()}}
    _kernel_rows_hold(cert, moved, orbit)


def test_the_script_certifies_the_group(monkeypatch, capsys):
    assert_group_certified("clebsch-flows", monkeypatch, capsys)
