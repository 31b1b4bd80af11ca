"""`hkproof report`: run the registry and write docs/theorems.md (statement, method, status, time)."""
from __future__ import annotations

import argparse
from pathlib import Path

from hkproof.commands import Result, add_command
from hkproof.proof.registry import select
from hkproof.proof.report import theorems_markdown


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "report", "prove every theorem and write the Markdown table of theorems", run_report)
    p.add_argument("--write", metavar="FILE", help="write the Markdown to FILE (default: print it)")
    p.add_argument("--no-slow", action="store_true", help="do not run claims marked slow")


def run_report(args: argparse.Namespace) -> Result:
    claims = select()
    certs = {c.id: c.prove() for c in claims if not (c.slow and args.no_slow)}
    text = theorems_markdown(claims, certs)
    if args.write:
        Path(args.write).write_text(text)
    ok = all(c.succeeded(certs[c.id]) for c in claims if c.id in certs)
    payload = {"written": args.write, "statuses": {k: v.status.label for k, v in certs.items()}}
    return Result(payload, f"wrote {args.write}" if args.write else text, 0 if ok else 1)
