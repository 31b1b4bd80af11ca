"""`hkproof check FILE`: re-verify a certificate file with the small separate checker (hkproof.checker)."""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from hkproof.checker import check_file
from hkproof.commands import Result, add_command
from hkproof.commands.report import writable_target, write_atomically
from hkproof.errors import UsageError
from hkproof.exit_codes import ExitCode
from hkproof.proof.singular import singular_script

__all__ = ["register", "run_check"]

CODES = {"verified": ExitCode.VERIFIED, "refuted": ExitCode.REFUTED, "malformed": ExitCode.BAD_INPUT}


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "check", "re-verify a certificate file written by --certificate, from the file alone "
                    "(exit 0 verified, 1 refuted, 2 malformed)", run_check)
    p.add_argument("file", help="a certificate file (JSON, docs/certificates.md)")
    p.add_argument("--export", nargs=2, metavar=("SYSTEM", "OUT"),
                   help="also write a script for a second computer algebra system that re-checks the substitution "
                        "and darboux steps (SYSTEM: singular)")


def run_check(args: argparse.Namespace) -> Result:
    target = None
    if args.export:
        if args.export[0] != "singular":
            raise UsageError(f"--export {args.export[0]}: hkproof writes scripts for singular only")
        target = writable_target(args.export[1])
    report = check_file(args.file)
    payload = {"file": args.file, "verdict": report.verdict, "steps": report.lines,
               "seconds": round(report.seconds, 4)}
    text = report.text()
    if target is not None and report.verdict == "verified":
        doc = json.loads(Path(args.file).read_text(encoding="utf-8"))
        write_atomically(target, singular_script(doc))
        payload["export"] = str(target)
        text += f"\nSingular script: {target} (run `Singular -q {target}`; it prints 'verified' per step)"
    return Result(payload, text, CODES[report.verdict])

