"""`hkproof check FILE`: re-verify a certificate file with the small separate checker (hkproof.checker), in a forked
child held to a deadline and a memory ceiling (exit 4 when either stops it)."""
from __future__ import annotations

import argparse
from pathlib import Path

from hkproof.budget import Budget
from hkproof.checker import check_file, load
from hkproof.commands import Result, add_budget_option, add_command, at_least
from hkproof.commands.report import writable_target, write_atomically
from hkproof.errors import UsageError
from hkproof.exit_codes import ExitCode
from hkproof.proof.singular import singular_script

__all__ = ["register", "run_check"]

CODES = {"verified": ExitCode.VERIFIED, "refuted": ExitCode.REFUTED, "malformed": ExitCode.BAD_INPUT}
SECONDS, MEMORY_MB = 3600.0, 4096      # defaults a referee's laptop survives


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "check", "re-verify a certificate file written by --certificate, from the file alone "
                    "(exit 0 verified, 1 refuted, 2 malformed, 4 stopped by --seconds or --memory-mb)", run_check)
    p.add_argument("file", help="a certificate file (JSON, docs/certificates.md)")
    p.add_argument("--export", nargs=2, metavar=("SYSTEM", "OUT"),
                   help="also write a script for a second computer algebra system that re-checks the substitution, "
                        "darboux, recipe-g and bivector steps, exclusions aside (SYSTEM: singular)")
    add_budget_option(p, SECONDS)
    p.add_argument("--memory-mb", type=at_least(64), default=MEMORY_MB, metavar="MB",
                   help=f"memory the check may add to this process, in MB (default {MEMORY_MB}); past it the check "
                        "stops with exit 4")


def run_check(args: argparse.Namespace) -> Result:
    target = None
    if args.export:
        if args.export[0] != "singular":
            raise UsageError(f"--export {args.export[0]}: hkproof writes scripts for singular only")
        target = writable_target(args.export[1])
    budget = Budget(args.seconds, memory_mb=args.memory_mb,
                    raise_with=f"a larger --seconds than {args.seconds:g} or --memory-mb than {args.memory_mb}")
    report = budget.call(f"checking {args.file}", check_file, args.file)
    payload = {"file": args.file, "verdict": report.verdict, "steps": report.lines, "verified": report.facts,
               "seconds": round(report.seconds, 4)}
    text = report.text()
    if target is not None and report.verdict == "verified":
        write_atomically(target, singular_script(load(Path(args.file).read_bytes())))
        payload["export"] = str(target)
        text += f"\nSingular script: {target} (run `Singular -q {target}`; it prints 'verified' per step)"
    return Result(payload, text, CODES[report.verdict])
