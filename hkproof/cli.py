"""The `hkproof` command line: every command in hkproof.commands, each with --json; exit 0 only on success."""
from __future__ import annotations

import argparse
import importlib
import json
import pkgutil
import signal
import sys
from typing import Sequence

from hkproof.errors import HKProofError


def build_parser() -> argparse.ArgumentParser:
    import hkproof.commands as pkg
    parser = argparse.ArgumentParser(
        prog="hkproof", description="Exact proofs of integrability of Kahan / Hirota-Kimura discretizations.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for mod in sorted(pkgutil.iter_modules(pkg.__path__), key=lambda m: m.name):
        if not mod.name.startswith("_"):
            importlib.import_module(f"{pkg.__name__}.{mod.name}").register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `hkproof list | head` ends quietly
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        result = args.run(args)
    except HKProofError as exc:
        if getattr(args, "json", False):
            print(json.dumps({"error": type(exc).__name__, "message": str(exc)}))
        else:
            print(f"hkproof: error: {exc}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps(result.payload, indent=2))
    elif result.text:
        print(result.text)
    return result.exit_code


if __name__ == "__main__":
    sys.exit(main())
