"""Algorithm (N) (Theorem "Lem: dim K"): kernel profiles in four arithmetics, and the paper's HK-bases."""
from __future__ import annotations

import json
from concurrent.futures import ThreadPoolExecutor
from fractions import Fraction

import flint
import pytest

from hkproof.algebra.fraction import Frac
from hkproof.cli import main
from hkproof.dynamics import kahan_map
from hkproof.errors import DependentBasisError
from hkproof.experiments import (ExactQ, Float64, KernelProfile, Modular, MPMath, ProfileProblem, ScanResult,
                                 fundamental_finite, make_scene, parse_basis, scan)
from hkproof.experiments.profiles import AMBIGUOUS, HK_BASIS, IRREGULAR, NO_BASIS, BasisFamily, kernel_vector

CLEBSCH = {"eps": "1/10", "w1": "1/10", "w2": "1/5", "w3": "3/10"}
MAX_BASIS = "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, m1*p1, m2*p2, m3*p3, 1"
ONE_DIM = ["p1**2, p2**2, p3**2, 1",
           "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, m1*p1",
           "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, m2*p2",
           "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, m3*p3"]


def test_fundamental_finite_reads_the_ranks():
    assert fundamental_finite([1, 2, 2, 2]) == (HK_BASIS, 2)
    assert fundamental_finite([1, 2, 3, 4]) == (NO_BASIS, 0)
    assert fundamental_finite([1, 1, 2, 3]) == (IRREGULAR, None)
    assert fundamental_finite([1, None, 2, 2]) == (AMBIGUOUS, None)


def test_parse_basis_keeps_commas_inside_parentheses():
    ring = kahan_map("euler-top").ring
    basis = parse_basis(ring, "x1**2, (x2 + x3)*(x2 - x3), 1")
    assert [str(b) for b in basis][2] == "1" and len(basis) == 3


def test_euler_top_full_basis_has_dimension_two():
    """Th. "dET full basis", and its one-dimensional sub-bases (Props. "dET first/second HK basis")."""
    assert scan("euler-top", "x1**2, x2**2, x3**2, 1", points=3).dimension == 2
    assert scan("euler-top", "x1**2, x2**2, x3**2", points=3).dimension == 1
    assert scan("euler-top", "x1**2, x2**2, 1", points=3).dimension == 1
    assert scan("euler-top", "x1**2, x2**2, x3", points=3).dimension == 0


def test_clebsch_bases_of_section_6():
    """Th. "dClebsch max basis" (d = 4) and Th. "dClebsch 1dim bases" (d = 1), exactly at two points each."""
    assert scan("clebsch", MAX_BASIS, points=2, values=CLEBSCH).dimension == 4
    for basis in ONE_DIM:
        assert scan("clebsch", basis, points=2, values=CLEBSCH).dimension == 1
    assert scan("clebsch", "p1**2, p2**2, m1**2, 1", points=2, values=CLEBSCH).dimension == 0


@pytest.mark.parametrize("arithmetic", [ExactQ(), Modular(), Float64(), MPMath(30)], ids=lambda a: a.name)
def test_four_arithmetics_agree_on_an_easy_point(arithmetic):
    f = kahan_map("clebsch")
    problem = ProfileProblem(make_scene(f, CLEBSCH), parse_basis(f.ring, MAX_BASIS))
    point = [Fraction(1, 2), Fraction(-1, 3), Fraction(2, 5), Fraction(3, 4), Fraction(-2, 7), Fraction(1, 3)]
    profile = problem.profile(point, arithmetic)
    assert profile.verdict == HK_BASIS and profile.dims == [9, 8, 7, 6, 5, 4, 4, 4, 4, 4]
    assert len(profile.kernel) == 4


def test_kernel_is_normalized_as_the_paper_and_matches_prop_det_first_basis():
    """K_Phi0(x) = [c1 : c2 : -1] with c1, c2 of eq. "dET c1 c2"."""
    f = kahan_map("euler-top")
    values = {"eps": Fraction(1, 3), "a1": 2, "a2": -3, "a3": 5}
    problem = ProfileProblem(make_scene(f, values), parse_basis(f.ring, "x1**2, x2**2, x3**2"))
    x = [Fraction(1, 2), Fraction(2, 3), Fraction(-3, 4)]
    c = kernel_vector(problem, x)
    at = {"x1": x[0], "x2": x[1], "x3": x[2], **values}
    c1 = Frac.parse(f.ring, "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)").evaluate(at)
    c2 = Frac.parse(f.ring, "(a1*x3**2 - a3*x1**2)/(a1*x2**2 - a2*x1**2)").evaluate(at)
    assert c == [c1, c2, -1]


def test_clebsch_first_basis_kernel_is_one_over_j_plus_eps2_omega():
    """Th. "dC basis 1": K_Phi0 = [1/J + eps^2 w1 : 1/J + eps^2 w2 : 1/J + eps^2 w3 : -1]."""
    f = kahan_map("clebsch")
    problem = ProfileProblem(make_scene(f, CLEBSCH), parse_basis(f.ring, ONE_DIM[0]))
    x = [Fraction(1, 2), Fraction(-1, 3), Fraction(2, 5), Fraction(3, 4), Fraction(-2, 7), Fraction(1, 3)]
    c = kernel_vector(problem, x)
    at = dict(zip(f.variables, x)) | {k: Fraction(v) for k, v in CLEBSCH.items()}
    inv_j = Frac.parse(f.ring, "(1 - eps**2*(w1*p1**2 + w2*p2**2 + w3*p3**2))/(p1**2 + p2**2 + p3**2)").evaluate(at)
    assert c == [inv_j + Frac.parse(f.ring, f"eps**2*{w}").evaluate(at) for w in ("w1", "w2", "w3")] + [-1]


def test_a_family_of_bases_shares_its_functions_and_centres_its_window():
    """Phi1, Phi2, Phi3 of Th. "dC bases 345" share six functions: 9 distinct ones are evaluated, on the window
    f^-3(x), ..., f^3(x); each kernel is that of the basis alone and satisfies the rows of the forward orbit."""
    f = kahan_map("clebsch")
    scene = make_scene(f, CLEBSCH)
    problems = [ProfileProblem(scene, parse_basis(f.ring, b)) for b in ONE_DIM[1:]]
    family = BasisFamily(problems)
    assert len(family.functions) == 9 and (family.back, family.forward) == (3, 3)
    x = [Fraction(1, 2), Fraction(-1, 3), Fraction(2, 5), Fraction(3, 4), Fraction(-2, 7), Fraction(1, 3)]
    vectors = family.kernel_vectors(x)
    assert vectors == [kernel_vector(p, x) for p in problems]
    arithmetic = ExactQ()
    for problem, c in zip(problems, vectors):
        prep = arithmetic.prepare(scene, problem.compiled)
        for y in arithmetic.orbit(prep, [flint.fmpq(v.numerator, v.denominator) for v in x], 6):
            assert sum(a * b for a, b in zip(c, arithmetic.basis_row(prep, y))) == 0


def test_orbits_through_delta_zero_are_skipped_and_counted():
    """Delta = 1 - eps^2 a2 a3 x1^2 at (x1, 0, 0): zero for x1 = 2, eps = 1/2, a2 = a3 = 1."""
    values = {"eps": "1/2", "a1": 1, "a2": 1, "a3": 1}
    result = scan("euler-top", "x1**2, x2**2, 1", points=[[2, 0, 0], [1, 2, 3]], values=values)
    assert result.count("singular") == 1 and result.dimension == 1
    for arithmetic in ("modular", "float", "mpmath"):
        other = scan("euler-top", "x1**2, x2**2, 1", points=[[2, 0, 0]], values=values, arithmetic=arithmetic)
        assert other.count("singular") == 1 and other.dimension is None


def test_scan_accepts_any_executor():
    serial = scan("euler-top", "x1**2, x2**2, 1", points=6, seed=4)
    with ThreadPoolExecutor(2) as pool:
        threaded = scan("euler-top", "x1**2, x2**2, 1", points=6, seed=4, executor=pool, chunk=1)
    assert [p.to_dict()["kernel"] for p in threaded.profiles] == [p.to_dict()["kernel"] for p in serial.profiles]


def test_dependent_functions_are_refused():
    """x1**2 and 4*x1**2 are dependent: Def. "Hirota mech" asks for independent functions."""
    with pytest.raises(DependentBasisError):
        scan("euler-top", "x1**2, 4*x1**2, 1", points=2)


def test_dimension_is_none_when_points_disagree():
    profiles = [KernelProfile(["1"], HK_BASIS, 1), KernelProfile(["2"], NO_BASIS, 0)]
    assert ScanResult("s", ["x", "1"], "exact", {}, profiles).dimension is None
    assert ScanResult("s", ["x", "1"], "exact", {}, profiles[:1]).dimension == 1


def test_cli_scan_json(capsys):
    code = main(["scan", "euler-top", "--basis", "x1**2, x2**2, x3**2, 1", "--points", "2", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert code == 0 and out["dimension"] == 2 and len(out["points"]) == 2
    assert out["points"][0]["dims"] == [3, 2, 2, 2]


def test_cli_scan_text_says_no_basis(capsys):
    main(["scan", "clebsch", "--basis", "p1**2, m2**2, 1", "--points", "2", "--arithmetic", "modular"])
    assert "dimension 0 (Phi is no HK-basis)" in capsys.readouterr().out


def test_exact_profiles_at_points_of_several_scenes():
    """exact_profiles: Th. "dET full basis" (d = 2) at two scenes; Phi0 of the Euler top has d = 1."""
    from hkproof.experiments.profiles import exact_profiles
    f = kahan_map("euler-top")
    full = [Frac.parse(f.ring, t) for t in ("x1**2", "x2**2", "x3**2", "1")]
    points = [({"eps": "1/7", "a1": 1, "a2": 2, "a3": -3}, (1, 2, 3)),
              ({"eps": "1/3", "a1": "1/2", "a2": 5, "a3": -1}, (2, -1, "1/2"))]
    profiles = exact_profiles(f, full, points)
    assert [p.dimension for p in profiles] == [2, 2]
    assert [p.dimension for p in exact_profiles(f, full[:3], points)] == [1, 1]
