"""Run theorem groups as a script: print each certificate, exit non-zero unless every claim is verified."""
from __future__ import annotations

import argparse
import json
from typing import Sequence

from hkproof.proof.certificate import Certificate
from hkproof.proof.registry import Claim, select
from hkproof.proof.status import Status


def run_script(groups: Sequence[str], argv: Sequence[str] | None = None) -> int:
    """The body of proofs/*.py: prove `groups`; `--json` for machine output, `--no-slow` to skip slow claims."""
    parser = argparse.ArgumentParser(description=f"Certify the theorems of group(s) {', '.join(groups)}.")
    parser.add_argument("--json", action="store_true", help="print the certificates as JSON")
    parser.add_argument("--no-slow", action="store_true", help="skip claims marked slow")
    args = parser.parse_args(argv)
    claims = select(groups=groups, include_slow=not args.no_slow)
    certs = [c.prove() for c in claims]
    if args.json:
        print(json.dumps([c.to_dict() for c in certs], indent=2))
    else:
        for c in certs:
            print(c.render())
        print(summary(claims, certs))
    return 0 if all(c.succeeded(cert) for c, cert in zip(claims, certs, strict=True)) else 1


def summary(claims: Sequence[Claim], certs: Sequence[Certificate]) -> str:
    """One line: how many theorems are verified, how many open claims reached their evidence, what failed."""
    verified = sum(cert.status is Status.VERIFIED for c, cert in zip(claims, certs, strict=True) if not c.is_open)
    theorems = sum(not c.is_open for c in claims)
    open_ok = sum(c.succeeded(cert) for c, cert in zip(claims, certs, strict=True) if c.is_open)
    failed = [f"{c.id} ({cert.status.label})" for c, cert in zip(claims, certs, strict=True) if not c.succeeded(cert)]
    seconds = sum(cert.seconds for cert in certs)
    text = f"\n{verified} of {theorems} theorems verified"
    if theorems < len(claims):
        text += f"; {open_ok} of {len(claims) - theorems} open claims at their expected status (evidence only)"
    text += f"; {seconds:.2f} s"
    return text + ("" if not failed else "; FAILED: " + ", ".join(failed))
