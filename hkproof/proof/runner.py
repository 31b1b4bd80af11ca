"""Run theorem groups as a script: print each certificate, exit non-zero unless every claim is verified."""
from __future__ import annotations

import argparse
import json
import sys
from typing import Sequence

from hkproof.proof.registry import select
from hkproof.proof.status import Status


def run_script(groups: Sequence[str], argv: Sequence[str] | None = None) -> int:
    """The body of proofs/*.py: prove `groups`; `--json` for machine output, `--no-slow` to skip slow claims."""
    parser = argparse.ArgumentParser(description=f"Certify the theorems of group(s) {', '.join(groups)}.")
    parser.add_argument("--json", action="store_true", help="print the certificates as JSON")
    parser.add_argument("--no-slow", action="store_true", help="skip claims marked slow")
    args = parser.parse_args(argv)
    certs = [c.prove() for c in select(groups=groups, include_slow=not args.no_slow)]
    if args.json:
        print(json.dumps([c.to_dict() for c in certs], indent=2))
    else:
        for c in certs:
            print(c.render())
        bad = [c for c in certs if c.status is not Status.VERIFIED]
        print(f"\n{len(certs) - len(bad)} of {len(certs)} verified in {sum(c.seconds for c in certs):.2f} s"
              + ("" if not bad else "; NOT verified: " + ", ".join(f"{c.claim_id} ({c.status.label})" for c in bad)),
              file=sys.stderr if bad else sys.stdout)
    return 0 if all(c.status is Status.VERIFIED for c in certs) else 1
