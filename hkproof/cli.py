"""The `hkproof` command line: every command in hkproof.commands, each with --json.

Exit codes: 0 verified (or success), 1 refuted (a mathematical answer), 2 bad input, 3 internal error, 130 interrupted.
"""
from __future__ import annotations

import argparse
import importlib
import json
import pkgutil
import signal
import sys
import traceback
from typing import NoReturn, Sequence

from hkproof.errors import HKProofError, UsageError

__all__ = ["build_parser", "main"]

EXIT_VERIFIED, EXIT_REFUTED, EXIT_BAD_INPUT, EXIT_INTERNAL, EXIT_INTERRUPTED = 0, 1, 2, 3, 130


class _Parser(argparse.ArgumentParser):
    """argparse that raises UsageError instead of printing usage and exiting, so that --json gets JSON."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{self.prog}: {message} (see `{self.prog} --help`)")


def build_parser() -> argparse.ArgumentParser:
    import hkproof.commands as pkg
    parser = _Parser(
        prog="hkproof", description="Exact proofs of integrability of Kahan / Hirota-Kimura discretizations. "
        "hkproof's eps is half the time step: x~ - x = 2 eps (polarized field).",
        epilog="exit codes: 0 verified or success, 1 refuted, 2 bad input, 3 internal error, 130 interrupted")
    parser.add_argument("--debug", action="store_true", help="on an internal error, print the traceback")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for mod in sorted(pkgutil.iter_modules(pkg.__path__), key=lambda m: m.name):
        if not mod.name.startswith("_"):
            importlib.import_module(f"{pkg.__name__}.{mod.name}").register(sub)
    return parser


def _error(as_json: bool, kind: str, message: str) -> None:
    """One line on stderr, or one JSON object on stdout under --json."""
    if as_json:
        print(json.dumps({"error": kind, "message": message}))
    else:
        print(f"hkproof: error: {message}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `hkproof list | head` ends quietly
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]
    as_json = "--json" in argv
    try:
        args = build_parser().parse_args(argv)
        result = args.run(args)
        if args.json:
            print(json.dumps(result.payload, indent=2))
        elif result.text:
            print(result.text)
        return result.exit_code
    except HKProofError as exc:
        _error(as_json, type(exc).__name__, str(exc))
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        _error(as_json, "Interrupted", "interrupted by the user; nothing was certified after this point")
        return EXIT_INTERRUPTED
    except Exception as exc:  # a bug: say so, and keep the traceback for --debug
        if debug:
            traceback.print_exc()
        kind = "out of memory" if isinstance(exc, MemoryError) else f"{type(exc).__name__}: {exc}"
        _error(as_json, "InternalError", f"internal error ({kind}); this is a bug in hkproof: please report it "
               "with the command line" + ("" if debug else " (rerun with --debug for the traceback)"))
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
