"""Checking time against proving time, claim by claim (issue 24): hkproof proves and writes a certificate, the small
checker (hkproof.checker) re-verifies it from the file alone. Prints a Markdown table for docs/performance.md.

    python benchmarks/certificates.py [--clebsch]      (--clebsch adds `discover clebsch`, about 2 minutes)
"""
from __future__ import annotations

import argparse
import json
import time

from hkproof.checker import check_document
from hkproof.commands._certificates import discover_document, theorem_document
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.integrals import check_integral
from hkproof.orchestration.registry import get_claim
from hkproof.pipelines.discover import discover
from hkproof.proof.export import document, substitution_step

C1 = "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)"
CLAIMS = ("et-first-hk-basis", "et-second-hk-basis", "et-symmetric-bases", "dc-basis1-even", "dc-basis2",
          "dc-theta")


def checked(doc: dict) -> tuple[str, float]:
    """The checker's verdict and time on a document that went through JSON text."""
    if not doc["steps"]:
        return f"not exported ({'; '.join(doc['claim'].get('not exported', {}).values())})", 0.0
    report = check_document(json.loads(json.dumps(doc)))
    return report.verdict, report.seconds


def rows(clebsch: bool) -> list[tuple[str, str, float, str, float]]:
    out = []
    kmap = kahan_map("euler-top")
    h = kmap.field.parse(C1)
    start = time.perf_counter()
    check_integral(kmap, h)
    proving = time.perf_counter() - start
    out.append(("`integral euler-top` c1", "substitution", proving,
                *checked(document("c1", "c1", [substitution_step(kmap.field, "c1", h)]))))
    for claim_id in CLAIMS:
        cert = get_claim(claim_id).certify()
        kinds = ", ".join(sorted({s["kind"] for s in cert.checks}))
        out.append((f"`prove {claim_id}`", kinds, cert.seconds, *checked(theorem_document([cert]))))
    for system in ("euler-top", *(("clebsch",) if clebsch else ())):
        start = time.perf_counter()
        report = discover(system)
        proving = time.perf_counter() - start
        doc = discover_document(report)
        kinds = ", ".join(sorted({s["kind"] for s in doc["steps"]}))
        out.append((f"`discover {system}` ({len(doc['claim']['integrals'])} integrals)", kinds, proving,
                    *checked(doc)))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--clebsch", action="store_true", help="also discover clebsch (about 2 minutes)")
    args = parser.parse_args()
    print("| claim | steps | proving (s) | checker verdict | checking (s) | check / prove |")
    print("|---|---|---|---|---|---|")
    for name, kinds, proving, verdict, checking in rows(args.clebsch):
        print(f"| {name} | {kinds} | {proving:.3f} | {verdict} | {checking:.3f} | {checking / proving if checking else 0:.2f} |")


if __name__ == "__main__":
    main()
