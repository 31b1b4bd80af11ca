"""A continuous linear symmetry of the field splits the invariant bivectors by weight (hkproof.hk.torus, issue 38):
the symmetry is found exactly, its eigen-coordinates mod p exist only where they should, exclusions made with it agree
with the plain search and are re-checked by hkproof check (a changed weight or generator is caught), and a class with
a kernel is rebuilt in the field's own coordinates."""
from __future__ import annotations

import copy
import json
import random

import flint

import hkproof as hk
from hkproof.checker import check_document
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.torus import commuting_linear_fields, eigen_coordinates, generic_generator, is_semi_invariant
from hkproof.pipelines.poisson import search_poisson
from hkproof.pipelines.poisson_candidates import Denominator
from hkproof.pipelines.poisson_certificate import poisson_document
from hkproof.proof.status import Status


def test_the_gaudin_rotation_is_found_and_diagonalizes_only_where_i_exists() -> None:
    f = kahan_map("gaudin-2")
    [a] = commuting_linear_fields(f.field)
    assert a.charpoly().degree() == 6 and not commuting_linear_fields(kahan_map("clebsch").field)
    assert eigen_coordinates(a, 1000000007) is None                 # 1000000007 = 3 mod 4: no sqrt(-1)
    torus = eigen_coordinates(a, 998244353)                          # 998244353 = 1 mod 4
    assert torus is not None and sorted(set(torus.weights))[0] == 0 and len(set(torus.weights)) == 3
    t = flint.nmod_mat([list(r) for r in torus.rows], torus.prime)
    am = flint.nmod_mat([[int(e.p) * pow(int(e.q), -1, torus.prime) for e in a.entries()[i * 6:(i + 1) * 6]]
                         for i in range(6)], torus.prime)
    diag = flint.nmod_mat(6, 6, [torus.weights[i] * (i == j) for i in range(6) for j in range(6)], torus.prime)
    assert t * am == diag * t
    ring = f.ring
    s3, t3, s1 = ring.gen("s3"), ring.gen("t3"), ring.gen("s1")
    assert is_semi_invariant(f, a, s3 + t3) and not is_semi_invariant(f, a, s1)


def test_torus_exclusions_agree_with_the_plain_search_and_are_rechecked() -> None:
    f = kahan_map("gaudin-2")
    report = search_poisson(f, 3, denominators=[Denominator("1", f.ring.constant(1)),
                                                 Denominator("s1", f.ring.gen("s1"))])
    by_name = {e.name: e for e in report.excluded}
    assert by_name["1"].torus is not None and len(by_name["1"].blocks) == 11      # 11 weights against 2 signs
    assert by_name["s1"].torus is None                                             # s1 is not semi-invariant
    assert all(e.certificate.status is Status.VERIFIED for e in report.excluded)
    doc = json.loads(json.dumps(poisson_document(f, report)))
    assert check_document(doc).verdict == "verified"
    step = next(s for s in doc["steps"] if s["kind"] == "exclusion" and s.get("torus"))
    weights = copy.deepcopy(doc)
    moved = next(s for s in weights["steps"] if s["kind"] == "exclusion" and s.get("torus"))
    moved["torus"]["weights"][2] = (moved["torus"]["weights"][2] + 1) % step["prime"]
    assert check_document(weights).verdict == "malformed"
    generator = copy.deepcopy(doc)
    moved = next(s for s in generator["steps"] if s["kind"] == "exclusion" and s.get("torus"))
    moved["torus"]["generator"][0][1] = str(int(moved["torus"]["generator"][0][1]) + 1)
    assert check_document(generator).verdict == "refuted"


def test_a_class_with_a_kernel_is_rebuilt_in_the_fields_coordinates() -> None:
    """The symmetric Euler top (x3 conserved) has the rotation about x3 as a symmetry; its invariant bivectors of
    degree <= 3 show a kernel in the torus' coordinates, and are then searched and rebuilt with the sign symmetries:
    the same structures as without the torus."""
    top = hk.system(["x1", "x2", "x3"], ["a*x2*x3", "-a*x1*x3", "0"], parameters=["a"], name="symmetric-top")
    f = hk.kahan_map(top)
    assert commuting_linear_fields(f.field)
    report = search_poisson(f, 2)
    assert report.structures and all(s.status is Status.VERIFIED for s in report.structures)
    assert any(c["torus"] for c in report.costs) and not report.costs[-1]["torus"]
    assert generic_generator([], random.Random(0)) is None
