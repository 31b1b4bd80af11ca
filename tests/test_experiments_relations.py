"""Recipe (E): the relations of sections 5 and 6 recovered exactly, with eps and the parameters symbolic."""
from __future__ import annotations

import json
from typing import Sequence

import pytest

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import rank_over_fraction_field
from hkproof.cli import main
from hkproof.dynamics import kahan_map
from hkproof.experiments.pslq import agreement, pslq_relations
from hkproof.errors import HKProofError
from hkproof.experiments.relations import find_relations

PSI = "p1**2, p2**2, p3**2, m1*p1, m2*p2, m3*p3"
FLOW2 = "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, 1"


def spans(system: str, search, expected: Sequence[Sequence[str]]) -> bool:
    """Every expected row (coefficients of the columns, then the constant) lies in the span of the found ones."""
    ring = kahan_map(system).ring
    found = [list(r.coefficients) + [-r.rhs] for r in search.relations]
    rows = [[Frac.parse(ring, c) for c in row] for row in expected]
    return rank_over_fraction_field(found + rows) == rank_over_fraction_field(found) == search.dimension


def test_euler_top_relations_of_section_5():
    """alpha1 c1 + alpha2 c2 = alpha3 and alpha1 d1 + alpha2 d2 = eps^2 alpha1 alpha2 alpha3."""
    c = find_relations(kahan_map("euler-top"), ["x1**2, x2**2, x3**2"])
    assert c.dimension == 1 and spans("euler-top", c, [["a1", "a2", "-a3"]])
    d = find_relations(kahan_map("euler-top"), ["x1**2, x2**2, 1"])
    assert d.dimension == 1 and spans("euler-top", d, [["a1", "a2", "-eps**2*a1*a2*a3"]])


def test_clebsch_first_basis_relations():
    """c1 - c2 = eps^2 (w1 - w2) and c2 - c3 = eps^2 (w2 - w3) (proof of Th. "dC basis 1")."""
    search = find_relations(kahan_map("clebsch"), ["p1**2, p2**2, p3**2, 1"])
    assert search.dimension == 2
    assert spans("clebsch", search, [["1", "-1", "0", "-eps**2*(w1 - w2)"], ["0", "1", "-1", "-eps**2*(w2 - w3)"]])
    assert all(r.checked == 3 for r in search.relations)


def test_psi_relations():
    """d1 = d2 = d3 (eq. "dC basis_2 rels 1") and eq. "dC basis 2 lin rel", shown as in the paper."""
    search = find_relations(kahan_map("clebsch"), [PSI], names=["d1", "d2", "d3", "d7", "d8", "d9"])
    assert search.dimension == 3
    # columns d1, d2, d3, d7, d8 and the constant, which is -d9
    assert spans("clebsch", search, [["1", "-1", "0", "0", "0", "0"], ["0", "1", "-1", "0", "0", "0"],
                                     ["0", "0", "0", "w2 - w3", "w3 - w1", "-(w1 - w2)"]])
    assert "d7*(w2 - w3) + d8*(-w1 + w3) + d9*(w1 - w2) = 0" in [r.text() for r in search.relations]


def test_second_flow_five_relations():
    """Eqs. "dCS2 linrel 1" to "dCS2 linrel 5" for the basis Phi_0 of the second flow."""
    search = find_relations(kahan_map("clebsch-flow2"), [FLOW2])
    assert search.dimension == 5
    assert spans("clebsch-flow2", search, [
        ["w1", "0", "0", "-w2*w3", "0", "0", "0"],
        ["0", "w2", "0", "0", "-w3*w1", "0", "0"],
        ["0", "0", "w3", "0", "0", "-w1*w2", "0"],
        ["1", "-1", "0", "0", "0", "-(w1 - w2)", "-eps**2*w3**2*(w1 - w2)"],
        ["-1", "0", "1", "0", "-(w3 - w1)", "0", "-eps**2*w2**2*(w3 - w1)"]])


@pytest.mark.slow
def test_rel18_nine_relations_among_three_bases():
    """Eqs. "rel18_1" to "rel18_8": nine relations among alpha, beta, gamma (stretch goal)."""
    common = "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, "
    search = find_relations(kahan_map("clebsch"), [common + "m1*p1", common + "m2*p2", common + "m3*p3"])
    assert search.dimension == 9 and len(search.relations) == 9
    z = ["0"] * 6

    def row(a, b, g, const="0"):
        return a + b + g + [const]
    expected = [
        row(["0"] * 4 + ["w1 - w3", "-(w1 - w2)"], z, z),                       # rel18_1
        row(z, ["0"] * 3 + ["w2 - w3", "0", "-(w2 - w1)"], z),                  # rel18_2
        row(z, z, ["0"] * 3 + ["w3 - w2", "-(w3 - w1)", "0"]),                  # rel18_3
        row(["0"] * 3 + ["1", "0", "0"], ["0"] * 4 + ["-1", "0"], z),           # rel18_4 (alpha4 = beta5)
        row(["0"] * 3 + ["1", "0", "0"], z, ["0"] * 5 + ["-1"]),                # rel18_4 (alpha4 = gamma6)
        # rel18_6: (a2 - a3 - w23 a4)/w23 = (b2 - b3 - w23 b4)/w31 = (g2 - g3 - w23 g4)/w12
        row(["0", "(w3 - w1)", "-(w3 - w1)", "-(w2 - w3)*(w3 - w1)", "0", "0"],
            ["0", "-(w2 - w3)", "(w2 - w3)", "(w2 - w3)**2", "0", "0"], z),
        row(["0", "(w1 - w2)", "-(w1 - w2)", "-(w2 - w3)*(w1 - w2)", "0", "0"], z,
            ["0", "-(w2 - w3)", "(w2 - w3)", "(w2 - w3)**2", "0", "0"]),
        # rel18_8: (a3 - a1 - w31 a5)/w23 = (b3 - b1 - w31 b5)/w31 = (g3 - g1 - w31 g5)/w12
        row(["-(w3 - w1)", "0", "(w3 - w1)", "0", "-(w3 - w1)**2", "0"],
            ["(w2 - w3)", "0", "-(w2 - w3)", "0", "(w2 - w3)*(w3 - w1)", "0"], z),
        row(["-(w1 - w2)", "0", "(w1 - w2)", "0", "-(w3 - w1)*(w1 - w2)", "0"], z,
            ["(w2 - w3)", "0", "-(w2 - w3)", "0", "(w2 - w3)*(w3 - w1)", "0"]),
    ]
    assert spans("clebsch", search, expected)


def test_pslq_agrees_with_exact_at_enough_digits():
    values = {"eps": "1/10", "w1": "1/10", "w2": "1/5", "w3": "3/10"}
    f = kahan_map("clebsch")
    exact = find_relations(f, ["p1**2, p2**2, p3**2, 1"])
    found = pslq_relations(f, ["p1**2, p2**2, p3**2, 1"], values, digits=30)
    assert agreement(found, exact.relations, values) == (2, 2)


def test_cli_relations_json(capsys):
    code = main(["relations", "clebsch", "--basis", "p1**2, p2**2, p3**2, 1", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["dimension"] == 2 and len(out["relations"]) == 2
    assert "c1 - c2 = eps**2*(w1 - w2)" in [r["relation"] for r in out["relations"]]


def test_a_found_relation_is_a_row_of_the_reduced_systems():
    """One Relation type: a relation found by recipe (E) is, as found, a row of Prop. "prop: even" (Th. "dC basis 1",
    second route: (c1 p1^2 + c2 p2^2 + c3 p3^2) o f^i = 1, i = 0, 1, and one relation)."""
    from hkproof.algebra.fraction import Frac
    from hkproof.hk.reduced import Relation, prove_by_evenness
    from hkproof.proof.certificate import Certificate
    from hkproof.proof.status import Status
    f = kahan_map("clebsch")
    rel = find_relations(f, ["p1**2, p2**2, p3**2, 1"]).relations[0]
    assert isinstance(rel, Relation) and len(rel.names) == 3
    basis = [Frac.parse(f.ring, t) for t in ("p1**2", "p2**2", "p3**2")]
    cert = Certificate("t", "t", "-", "-")
    c = prove_by_evenness(cert, f, basis, Frac(f.ring, 1), ("c1", "c2", "c3"), (0, 1), [rel])
    assert all(step.status is Status.VERIFIED for step in cert.steps)
    assert c[0] == Frac.parse(f.ring, "(1 + eps**2*(w1 - w2)*p2**2 + eps**2*(w1 - w3)*p3**2)/(p1**2 + p2**2 + p3**2)")


def test_support_screen_agrees_with_the_direct_kernel_test():
    """`_sparsest`'s screen (a determinant of a random projection of the annihilator's columns mod p, then ranks mod p
    and over Q) answers exactly what the direct
    test answers: does the span of the relation vectors contain a non-zero vector supported in S?"""
    import itertools
    import random

    import flint

    from hkproof.algebra.linalg import nullspace_q
    from hkproof.experiments.relations import _carrying_supports
    rng = random.Random(3)
    for trial in range(12):
        width, count = 7, rng.randint(1, 5)
        # vectors with planted sparse members, so that both answers occur
        values = [[flint.fmpq(rng.randint(-3, 3)) if rng.random() < 0.5 or trial % 2 else flint.fmpq(0)
                   for _ in range(width)] for _ in range(count)]
        if flint.fmpq_mat(values).rank() < count:
            continue
        carrying = _carrying_supports(values, width)
        for size in (1, 2, 3, 4):
            found = carrying(size)
            for support in itertools.combinations(range(width), size):
                outside = [j for j in range(width) if j not in support]
                direct = bool(nullspace_q([[v[j] for v in values] for j in outside]))
                assert (support in found) == direct, (values, support)


def test_kernel_vectors_share_one_orbit_and_agree_with_kernel_vector():
    from hkproof.experiments.profiles import ProfileProblem, kernel_vector, kernel_vectors
    from hkproof.experiments.scene import make_scene
    f = kahan_map("euler-top")
    scene = make_scene(f, {"eps": "1/3", "a1": 2, "a2": -3, "a3": 5})
    problems = [ProfileProblem(scene, [Frac.parse(f.ring, t) for t in b.split(", ")])
                for b in ("x1**2, x2**2, x3**2", "x1**2, x2**2, 1")]
    point = [1, 2, -1]
    assert kernel_vectors(problems, point) == [kernel_vector(p, point) for p in problems]
    other = ProfileProblem(make_scene(f, {"eps": 1, "a1": 1, "a2": 2, "a3": 3}), problems[0].basis)
    with pytest.raises(HKProofError, match="in one scene"):
        kernel_vectors([problems[0], other], point)


def test_a_basis_times_an_integral_is_sampled_from_the_plain_one():
    """(x1^2, x2^2, h x3^2) with h an integral of the Euler top's Kahan map has the kernel coordinates of
    (x1^2, x2^2, x3^2) times h: recipe (E) told that h is an integral samples it without profiling it and finds the
    same relation space as profiling both; a function that does not match leaves the basis profiled."""
    import random

    from hkproof.algebra.fraction import Frac
    from hkproof.experiments.relations import CoordinateSampler

    f = kahan_map("euler-top")
    h = Frac.parse(f.ring, "(1 - eps**2*a2*a3*x1**2)/(1 - eps**2*a3*a1*x2**2)")
    nums, delta = f.explicit
    assert h.pullback(nums, delta, f.variables) == h
    plain = [Frac.parse(f.ring, t) for t in ("x1**2", "x2**2", "x3**2")]
    bases = [plain, plain[:2] + [h * plain[2]]]
    assert CoordinateSampler(f, bases, random.Random(0), [h]).derived == {1: (0, h)}
    assert CoordinateSampler(f, bases, random.Random(0), [h * h]).derived == {}
    derived = find_relations(f, bases, integrals=[h])
    profiled = find_relations(f, bases)
    assert derived.dimension == profiled.dimension == 1      # a1 c1 + a2 c2 = a3; h c_k adds none
    rows = [[str(c) for c in r.coefficients] + [str(-r.rhs)] for r in profiled.relations]
    assert spans("euler-top", derived, rows)
