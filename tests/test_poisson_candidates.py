"""The candidate denominators of `poisson` (issue 38): the irreducible factors in the phase variables of the
integrals' denominators, the Darboux polynomials and the given D, and their products of two; each class searched."""
from __future__ import annotations

import json
import subprocess
import sys

from hkproof.algebra.ring import get_ring
from hkproof.dynamics.catalogue import kahan_map
from hkproof.pipelines.poisson import with_integrals
from hkproof.pipelines.poisson_candidates import candidate_denominators
from hkproof.proof.status import Status


def test_factors_up_to_units_and_products_of_two() -> None:
    ring = get_ring(("x", "y", "eps", "a"))
    x, y, eps, a = (ring.gen(v) for v in ("x", "y", "eps", "a"))
    sources = [("den(I1)", -3 * (a + 1) * x**2 * (1 - eps * y)),       # (a + 1) is a unit of Q(eps, a): dropped
               ("P1", 2 * x * (eps * y - 1)),                         # the same factors up to rational factors
               ("P2", y + 1)]
    found = candidate_denominators(ring.constant(1), ("x", "y"), sources)
    names = [d.name for d in found]
    assert names == ["1", "F1", "F2", "F3", "F1^2", "F1*F2", "F1*F3", "F2^2", "F2*F3", "F3^2"]
    polys = {d.name: d.poly for d in found}
    assert sorted(str(polys[n]) for n in ("F1", "F2", "F3")) == sorted(str(p) for p in (x, eps * y - 1, y + 1))
    assert polys["F1*F2"] == polys["F1"] * polys["F2"]
    assert "den(I1)" in found[1].origin and "P1" in found[1].origin
    assert candidate_denominators(ring.constant(1), ("x", "y"), [("den(I1)", (a + 2) * eps)]) == found[:1]


def test_every_class_of_the_euler_top_is_searched() -> None:
    """x2^2 a1 - x1^2 a2 (den of I1, a Darboux polynomial) and the other factors of measure's Darboux polynomials:
    every class with a factor in D is excluded at degree 3, D = 1 has the three structures."""
    report = with_integrals(kahan_map("euler-top"), 3)
    assert len(report.structures) == 3
    assert {e.name for e in report.excluded} == {"F1", "F2", "F3", "F1^2", "F1*F2", "F1*F3", "F2^2", "F2*F3", "F3^2"}
    assert all(e.certificate.status is Status.VERIFIED and e.degree == 3 for e in report.excluded)


def test_cli_names_the_classes() -> None:
    out = subprocess.run([sys.executable, "-m", "hkproof.cli", "poisson", "lotka-volterra", "--degree", "2",
                          "--json", "--integrals-degree", "0"], capture_output=True, text=True, check=True)
    data = json.loads(out.stdout)
    excluded = {e["denominator_name"]: e["denominator"] for e in data["excluded"]}
    assert set(excluded) == {"F1", "F2", "F1^2", "F1*F2", "F2^2"} and {excluded["F1"], excluded["F2"]} == {"x", "y"}
    none = subprocess.run([sys.executable, "-m", "hkproof.cli", "poisson", "lotka-volterra", "--degree", "2",
                           "--json", "--integrals-degree", "0", "--darboux-degree", "0"], capture_output=True,
                          text=True, check=True)
    assert json.loads(none.stdout)["excluded"] == []


def test_a_structure_found_with_a_smaller_denominator_is_not_found_again() -> None:
    """x y / 1 is also x^2 y / x and x y^2 / y: the classes D = x and D = y at degree 3 have a kernel mod p, but no
    larger than the span of Pi1 times D, so no second or third structure is reported (and no exclusion is made)."""
    report = with_integrals(kahan_map("lotka-volterra"), 3, integrals_degree=0)
    assert len(report.structures) == 1
    assert {e.name for e in report.excluded} == {"F1^2", "F1*F2", "F2^2"}
    assert sum("a combination of the structures found with a smaller D" in n for n in report.notes) == 2


def test_a_product_is_evaluated_factor_by_factor_as_its_expansion() -> None:
    """D = F^2 G mod p at points, factor by factor, equals the expanded product; its text reads back to D."""
    import random as _random

    from hkproof.hk.poisson_system import factored_mod
    f = kahan_map("euler-top")
    ring = f.ring
    a = ring.gen("x1") ** 2 * ring.gen("a2") - ring.gen("x2") ** 2 * ring.gen("a1")
    b = ring.gen("x3") * ring.gen("eps") + 1
    d = candidate_denominators(ring.constant(1), f.variables, [("P", a), ("Q", b)])[-2]   # F1*F2
    mmap = f.mod(1000003, {"eps": 3, "a1": 5, "a2": 7, "a3": 11})
    factored, expanded = factored_mod(mmap, d.parts()), mmap.reduce(d.poly)
    rng = _random.Random(1)
    for _ in range(5):
        x = [rng.randrange(1000003) for _ in range(3)]
        assert factored(*x) == int(expanded(*x))
    assert f.field.parse(d.text()).num in (d.poly, -d.poly)


def test_screening_excludes_and_reports_kernels_without_rebuilding() -> None:
    """--screen: the Euler top's class D = 1 is reported with its kernel (dimension 3 at degree 3, the pencil) and
    nothing is rebuilt; the other nine classes are excluded as in a full search."""
    out = subprocess.run([sys.executable, "-m", "hkproof.cli", "poisson", "euler-top", "--degree", "3", "--screen",
                          "--json", "--integrals-degree", "0"], capture_output=True, text=True, check=True)
    data = json.loads(out.stdout)
    assert data["structures"] == [] and len(data["excluded"]) == 9
    [kernel] = data["kernels"]
    assert {k: kernel[k] for k in ("denominator_name", "denominator", "degree", "dimension", "status")} == {
        "denominator_name": "1", "denominator": "1", "degree": 3, "dimension": 3, "status": "evidence(exact)"}
    assert kernel["certificate"]["status"] == "evidence(exact)"


def test_cli_class_restricts_the_search_and_an_unknown_class_exits_2() -> None:
    base = [sys.executable, "-m", "hkproof.cli", "poisson", "lotka-volterra", "--degree", "2", "--integrals-degree", "0"]
    one = subprocess.run(base + ["--json", "--class", "F1^2"], capture_output=True, text=True, check=True)
    assert [e["denominator_name"] for e in json.loads(one.stdout)["excluded"]] == ["F1^2"]
    bad = subprocess.run(base + ["--class", "F7"], capture_output=True, text=True)
    assert bad.returncode == 2 and "no candidate class F7" in bad.stderr and "Traceback" not in bad.stderr
