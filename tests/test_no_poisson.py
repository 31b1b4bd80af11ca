"""The theorem "no invariant Q/D of a class is Poisson" (issue 38; docs/poisson.md): `--screen` proves it when the
top degree's kernel mod p is small and the Schouten brackets of its basis are independent mod p (no member satisfies
Jacobi), and the checker recomputes the rows, the kernel and the brackets itself (step kind no-poisson, version 9).
Here: it is never granted when a member is Poisson, when the kernel is too large, or in an older file; the Gaudin
magnet, where it holds, is a slow test."""
from __future__ import annotations

import json
import random

import pytest

from hkproof.checker import check_document
from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.pipelines.poisson import with_integrals
from hkproof.proof.export import document, no_poisson_step


def check(steps: list[dict], version: int | None = None) -> tuple[str, str]:
    d = document("test", "no invariant Poisson structure", steps)
    if version is not None:
        d["version"] = version
    report = check_document(json.loads(json.dumps(d)))
    return report.verdict, "\n".join(report.lines)


def test_a_poisson_member_excludes_nothing() -> None:
    """Lotka-Volterra, D = 1, degree 2: the kernel is the line of xy, which is Poisson; the screen says so and grants
    no theorem, and a no-poisson step built from its data is refused by the checker."""
    f = kahan_map("lotka-volterra")
    report = with_integrals(f, 2, integrals_degree=0, darboux_degree=0, screen=True)
    [screened] = report.kernels
    member = screened.member
    assert member is not None and member.poisson_mod_p is True and screened.no_poisson is None
    assert "no invariant Q/D" not in report.text()
    step = no_poisson_step(f.field, "1", 2, member.prime, member.values, [s.signs for s in member.symmetries],
                           [(b.character, b.points) for b in member.others],
                           [(b.character, b.points, False) for b in member.kernels])
    verdict, lines = check([step])
    assert verdict == "malformed" and "members are dependent" in lines


def _euler_step(points: int, character: list[int] | None = None) -> dict:
    f = kahan_map("euler-top")
    rng = random.Random(1)
    p = 1_000_003
    xs = [[rng.randrange(p) for _ in range(3)] for _ in range(points)]
    return no_poisson_step(f.field, "1", 3, p, {"eps": 3, "a1": 2, "a2": 5, "a3": 7}, [], [],
                           [(character or [], xs, False)])


def test_a_poisson_pencil_or_a_large_kernel_proves_nothing() -> None:
    """The discrete Euler top, D = 1, degree 3: its invariant cubic bivectors form a Poisson pencil of dimension 3, so
    the brackets of the kernel's basis are dependent and the step is refused; too few points give a kernel larger than
    the checker takes, refused likewise."""
    verdict, lines = check([_euler_step(40)])
    assert verdict == "malformed" and "are dependent" in lines
    verdict, lines = check([_euler_step(5)])
    assert verdict == "malformed" and "(this checker takes 1 to 6)" in lines
    step = _euler_step(40)
    step["kernels"] *= 2                                  # one character stated twice
    verdict, lines = check([step])
    assert verdict == "malformed" and "must be distinct" in lines


def test_malformed_no_poisson_steps() -> None:
    """A kernel character that the columns do not have, a no-poisson step in a version-8 file, a kernel on the fixed
    bivectors of a flow without a torus."""
    verdict, lines = check([_euler_step(40, [1])])
    assert verdict == "malformed" and "must be distinct characters of the columns" in lines
    verdict, lines = check([_euler_step(40)], version=8)
    assert verdict == "malformed" and "no-poisson" in lines
    step = _euler_step(40)
    step["kernels"][0]["fixed"] = True
    verdict, lines = check([step])
    assert verdict == "malformed" and "needs the torus" in lines


@pytest.mark.slow
def test_gaudin_class_without_a_poisson_structure(tmp_path, capsys) -> None:
    """The Gaudin magnet, D = F4^2 = (eps^2 b g s3 - 1)^2, degree 6 (about 3 minutes): the screen proves that no
    invariant Q/D is Poisson (on the bivectors fixed by the rotation), the checker agrees on the file; the step without
    the fixed coordinates (too few rows for the 6 920 columns) and the same step for the class F4 are refused."""
    out = tmp_path / "gaudin.json"
    assert main(["poisson", "gaudin-2", "--degree", "6", "--screen", "--class", "F4^2", "--no-progress",
                 "--certificate", str(out)]) == 0
    text = capsys.readouterr().out
    assert "no invariant Q/D with deg Q <= 6 is Poisson" in text
    d = json.loads(out.read_text())
    [step] = [s for s in d["steps"] if s["kind"] == "no-poisson"]
    assert [k.get("fixed") for k in step["kernels"]] == [True]     # solved on the bivectors fixed by the rotation
    report = check_document(d)
    assert report.verdict == "verified", report.lines
    assert "no invariant Poisson structure" in " ".join(report.facts)
    plain = json.loads(json.dumps(d))
    next(s for s in plain["steps"] if s["kind"] == "no-poisson")["kernels"][0].pop("fixed")
    assert check_document(plain).verdict == "malformed"   # the points were chosen for the fixed coordinates
    step["denominator"] = "s3*eps**2*b*g - 1"
    assert check_document(d).verdict == "malformed"
