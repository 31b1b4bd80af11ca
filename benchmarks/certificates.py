"""Checking time against proving time, claim by claim (issue 24): hkproof proves and writes a certificate, the small
checker (hkproof.checker) re-verifies it from the file alone. Prints a Markdown table for docs/performance.md.

    python benchmarks/certificates.py [--clebsch] [--cited]
        --clebsch adds `discover clebsch` (about 2 minutes); --cited adds dc345-alpha and dc345-step5, whose relations
        cite other claims' integrals, each proven again in the file by substitution (tens of minutes to check)
"""
from __future__ import annotations

import argparse
import json
import time

from hkproof.checker import check_document
from pathlib import Path

from hkproof.commands._certificates import discover_document, hamiltonian_document, measure_document, theorem_document
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.integrals import check_integral
from hkproof.hk.modified_hamiltonian import parse_matrix, verify
from hkproof.hk.recipe_g import recipe_g
from hkproof.orchestration.registry import get_claim
from hkproof.pipelines.darboux import search_darboux
from hkproof.pipelines.discover import discover
from hkproof.proof.export import document, recipe_g_step, substitution_step

C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"
CLAIMS = ("et-first-hk-basis", "et-second-hk-basis", "et-symmetric-bases", "dc-basis1-even", "dc-basis2",
          "dc-theta")
CITED = ("dc345-alpha", "dc345-step5")
CUBIC = str(Path(__file__).resolve().parents[1] / "docs" / "examples" / "cubic-oscillator.toml")


def checked(doc: dict) -> tuple[str, str, float]:
    """The step kinds, the checker's verdict and its time on a document that went through JSON text."""
    report = check_document(json.loads(json.dumps(doc)))
    return ", ".join(sorted({s["kind"] for s in doc["steps"]})), report.verdict, report.seconds


def timed(work):
    start = time.perf_counter()
    out = work()
    return out, time.perf_counter() - start


def rows(clebsch: bool, cited: bool) -> list[tuple[str, float, str, str, float]]:
    out = []
    kmap = kahan_map("euler-top")
    h = kmap.field.parse(C1)
    proving = timed(lambda: check_integral(kmap, h))[1]
    out.append(("`integral euler-top` c1", proving, *checked(document("c1", "c1", [substitution_step(kmap.field, "c1",
                                                                                                      h)]))))
    res, proving = timed(lambda: recipe_g(kmap, h))
    m = res.certificate
    assert m is not None
    out.append(("`integral euler-top` c1 `--method groebner`", proving, *checked(document("c1", "c1", [recipe_g_step(
        kmap.field, "c1", h, m.generators, m.cofactors, m.multiplier ** m.power)]))))
    for system in ("lotka-volterra", "euler-top"):
        f = kahan_map(system)
        search, proving = timed(lambda: search_darboux(f, 4))
        out.append((f"`measure {system}`", proving, *checked(measure_document(f, search))))
    f = kahan_map(CUBIC)
    res_h, proving = timed(lambda: verify(f, f.field.parse("p**2/2 + q**2/2 + a*q**3/3"),
                                          parse_matrix(f, "[[0, 1], [-1, 0]]")))
    out.append(("`hamiltonian` cubic oscillator", proving, *checked(hamiltonian_document(f, res_h, {}))))
    for claim_id in (*CLAIMS, *(CITED if cited else ())):
        cert = get_claim(claim_id).certify()
        out.append((f"`prove {claim_id}`", cert.seconds, *checked(theorem_document([cert]))))
    for system in ("euler-top", *(("clebsch",) if clebsch else ())):
        report, proving = timed(lambda: discover(system))
        doc = discover_document(report)
        out.append((f"`discover {system}` ({len(doc['claim']['integrals'])} integrals)", proving, *checked(doc)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--clebsch", action="store_true", help="also discover clebsch (about 2 minutes)")
    parser.add_argument("--cited", action="store_true", help="also dc345-alpha and dc345-step5 (slow to check)")
    args = parser.parse_args()
    print("| claim | steps | proving (s) | checker verdict | checking (s) | check / prove |")
    print("|---|---|---|---|---|---|")
    for name, proving, kinds, verdict, checking in rows(args.clebsch, args.cited):
        print(f"| {name} | {kinds} | {proving:.3f} | {verdict} | {checking:.3f} | {checking / proving:.2f} |")


if __name__ == "__main__":
    main()
