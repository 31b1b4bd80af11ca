"""The `hkproof` command line: every command in hkproof.commands, each with --json.

Exit codes (hkproof.exit_codes): 0 verified (or success), 1 refuted (a mathematical answer), 2 bad input, 3 internal
error, 4 a resource limit or an exhausted budget, 130 interrupted (Ctrl-C, SIGTERM, SIGHUP).
"""
from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import signal
import sys
import traceback
from contextlib import nullcontext
from typing import NoReturn, Sequence

from hkproof.algebra.printing import to_json
from hkproof.commands import command_budget
from hkproof.errors import HKProofError, OutputError, ResourceLimitError, UsageError
from hkproof.exit_codes import ExitCode, exit_code_for
from hkproof.orchestration.interrupts import from_signal, interrupt_label, interrupts_live, interrupts_raised
from hkproof.orchestration.output import emit

__all__ = ["build_parser", "interrupt_without_signal", "main", "out_of_memory"]

EXIT_CODES = ("exit codes: 0 verified or success, 1 refuted, 2 bad input, 3 internal error, 4 a resource limit or an "
              "exhausted budget, 130 interrupted (Ctrl-C, SIGTERM, SIGHUP)")


def _limit(what: str, limit: str, raise_with: str) -> ResourceLimitError:
    return ResourceLimitError(f"{what}; to go further: {raise_with}", limit=limit, raise_with=raise_with)


def out_of_memory() -> ResourceLimitError:
    """A MemoryError, reported as the limit it is."""
    return _limit("out of memory: the computation needs more memory than this process may use",
                  "the memory this process may use (its address-space limit, or the machine's memory)",
                  "more memory (a higher `ulimit -v`), or a smaller question (a lower degree, fewer iterates, fixed "
                  "parameters)")


def interrupt_without_signal() -> ResourceLimitError:
    """A KeyboardInterrupt that no signal caused, reported as the limit that caused it."""
    return _limit("stopped by a KeyboardInterrupt that no interrupt signal caused: a library gave up while starting "
                  "(numpy's OpenBLAS does so when it cannot create its threads under a tight memory or process "
                  "limit)", "the memory and processes this process may use",
                  "a higher `ulimit -v` and `ulimit -u`, or OPENBLAS_NUM_THREADS=1")


class _Parser(argparse.ArgumentParser):
    """argparse that raises UsageError instead of printing usage and exiting, so that --json gets JSON."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{self.prog}: {message} (see `{self.prog} --help`)")


def build_parser() -> argparse.ArgumentParser:
    import hkproof.commands as pkg
    parser = _Parser(
        prog="hkproof", description="Exact proofs of integrability of Kahan / Hirota-Kimura discretizations. "
        "hkproof's eps is half the time step: x~ - x = 2 eps (polarized field).", epilog=EXIT_CODES)
    parser.add_argument("--debug", action="store_true", help="on an internal error, print the traceback")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    for mod in sorted(pkgutil.iter_modules(pkg.__path__), key=lambda m: m.name):
        if not mod.name.startswith("_"):
            importlib.import_module(f"{pkg.__name__}.{mod.name}").register(sub)
    return parser


def error_payload(exc: HKProofError) -> dict:
    """The JSON object of an error: its class and message; a limit also says which limit and how to raise it."""
    payload: dict = {"error": type(exc).__name__, "message": str(exc)}
    if isinstance(exc, ResourceLimitError):
        payload.update(limit=exc.limit, raise_with=exc.raise_with)
    return payload


def _report(as_json: bool, payload: dict) -> None:
    """One JSON object on stdout under --json, else (or when stdout cannot take it) one line on stderr."""
    if as_json:
        try:
            emit(to_json(payload))
            return
        except HKProofError:
            pass
    try:
        print(f"hkproof: error: {payload['message']}", file=sys.stderr, flush=True)
    except OSError:
        pass


def _quiet_stdout() -> None:
    """Flush stdout; if it cannot take what is left (a full device), send the rest to /dev/null so that Python's own
    flush at exit prints no traceback."""
    try:
        sys.stdout.flush()
    except OSError:
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):  # no real file descriptor (a captured stream)
            pass


def _run(argv: list[str]) -> int:
    """Run a command. Interrupts are held (main) while the command line is read and while the answer is printed, so
    that an interrupt never cuts a document in half; they take effect while the command runs -- for the commands
    that prove claims (`holds_interrupts`: prove, report) only while claims are proven, so that an interrupt at any
    moment gives their one document with the certificates finished so far."""
    args = build_parser().parse_args(argv)
    live = nullcontext() if getattr(args, "holds_interrupts", False) else interrupts_live()
    with command_budget(args).active(), live:
        result = args.run(args)
    if args.json:
        emit(to_json(result.payload, indent=2))
    elif result.text:
        emit(result.text)
    missing = result.payload.get("certificate_error") if isinstance(result.payload, dict) else None
    if missing:                 # --certificate FILE with nothing to write: the report above, then the error
        _report(False, {"message": missing})
        return result.exit_code or exit_code_for(OutputError(missing))
    return result.exit_code


def main(argv: Sequence[str] | None = None) -> int:
    if hasattr(signal, "SIGPIPE"):
        signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `hkproof list | head` ends quietly
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]
    as_json = "--json" in argv
    try:
        with interrupts_raised(hold=True) as handled:
            try:
                return _run(argv)
            except KeyboardInterrupt as exc:
                if not from_signal(exc, handled):
                    raise interrupt_without_signal() from exc
                raise
    except HKProofError as exc:
        _report(as_json, error_payload(exc))
        return exit_code_for(exc)
    except MemoryError:
        _report(as_json, error_payload(out_of_memory()))
        return ExitCode.LIMIT
    except KeyboardInterrupt as exc:
        _report(as_json, {"error": "Interrupted", "message": f"interrupted ({interrupt_label(exc)}); nothing was "
                          "certified after this point"})
        return ExitCode.INTERRUPTED
    except Exception as exc:  # a bug: say so, and keep the traceback for --debug
        if debug:
            traceback.print_exc()
        _report(as_json, {"error": "InternalError", "message": f"internal error ({type(exc).__name__}: {exc}); this "
                          "is a bug in hkproof: please report it with the command line"
                          + ("" if debug else " (rerun with --debug for the traceback)")})
        return ExitCode.INTERNAL
    finally:
        _quiet_stdout()


if __name__ == "__main__":
    sys.exit(main())
