"""Subcommands of `hkproof`: each module has register(subparsers) and sets `run` to a function returning Result."""
from __future__ import annotations

import argparse
import math
import os
import re
from dataclasses import dataclass
from typing import Any, Callable

import flint
from tqdm import tqdm

from hkproof.algebra.formula import read_integer, read_number
from hkproof.budget import Budget
from hkproof.dynamics.catalogue import SYSTEMS, kahan_map
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, ParseError
from hkproof.exit_codes import ExitCode
from hkproof.experiments.progress import bar
from hkproof.orchestration.execution import EXECUTORS
from hkproof.orchestration.runner import RunOptions


@dataclass
class Result:
    """What a command produced: a JSON-able payload, the text for a person, and the exit status."""

    payload: Any
    text: str
    exit_code: int = ExitCode.VERIFIED


def answer_code(ok: bool) -> ExitCode:
    """The exit code of a mathematical answer: 0 for yes (verified, found), 1 for no (refuted, not found)."""
    return ExitCode.VERIFIED if ok else ExitCode.REFUTED


def add_command(sub: argparse._SubParsersAction, name: str, help: str,
                run: Callable[[argparse.Namespace], Result]) -> argparse.ArgumentParser:
    """A subparser with the common --json flag, dispatching to `run`."""
    p = sub.add_parser(name, help=help, description=help)
    p.add_argument("--json", action="store_true", help="print a JSON object instead of text")
    p.set_defaults(run=run)
    return p


def add_system_argument(p: argparse.ArgumentParser) -> None:
    """SYSTEM: a catalogue name or a TOML file."""
    p.add_argument("system", help=f"a catalogue name ({', '.join(SYSTEMS)}) or a TOML file")


def add_param_option(p: argparse.ArgumentParser) -> None:
    """--param NAME=VALUE for commands that keep eps symbolic: a specialized system, results verified(specialized)."""
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="fix a parameter to an exact rational (repeatable); results then hold for these values only "
                        "(verified(specialized))")


def specialized_map(args: argparse.Namespace) -> tuple[KahanMap, KahanMap, dict[str, flint.fmpq]]:
    """(map of SYSTEM, map of SYSTEM with the --param values fixed, those values); the same map twice without them."""
    f = kahan_map(args.system)
    values = fixed_values(argparse.Namespace(param=args.param, eps=None))
    if EPS in values:
        raise ParseError("this command keeps eps symbolic: --param fixes parameters only")
    fixed = f.field.check_values(values)
    if not fixed:
        return f, f, {}
    return f, kahan_map(f.field.specialize(fixed)), fixed


def integer(text: str) -> int:
    """An argparse type: an integer in ASCII digits (a Bengali four or '1.0' is a usage error, exit 2)."""
    try:
        return read_integer(text)
    except HKProofError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer (ASCII digits 0-9)") from None


def at_least(minimum: int, most: int | None = None) -> Callable[[str], int]:
    """An argparse type: an integer >= minimum (and <= most, if given); a bad count is a usage error, exit 2.

    >>> at_least(1)("3"), at_least(1, 8)("8")
    (3, 8)
    """
    def read(text: str) -> int:
        value = integer(text)
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{value} is too small (at least {minimum})")
        if most is not None and value > most:
            raise argparse.ArgumentTypeError(f"{value} is too large (at most {most})")
        return value
    read.__name__ = f"integer >= {minimum}" + (f" and <= {most}" if most is not None else "")
    return read


def seconds(text: str) -> float:
    """An argparse type: a time budget, a positive finite number of seconds in ASCII digits ('nan', '-5', 'inf' and
    '0' are usage errors, exit 2)."""
    try:
        value = float(read_number(text.strip()))
    except (HKProofError, OverflowError):
        value = math.nan
    if not 0 < value < math.inf:
        raise argparse.ArgumentTypeError(f"{text!r} is not a time budget: give a positive number of seconds, e.g. 60 "
                                         "or 2.5")
    return value


def add_budget_option(p: argparse.ArgumentParser, default: float | None = None, *, per_claim: bool = False) -> None:
    """--seconds: the command's time budget (checked inside every long loop; a partial answer says what it covered),
    or with `per_claim` the budget of each claim's proof."""
    what = "time budget of each claim's proof (one that runs out is unknown)" if per_claim else \
        "time budget: the command stops within it and says what it covered (exit 4 if it has no partial answer)"
    p.add_argument("--seconds", type=seconds, default=default, metavar="SECONDS",
                   help=what + (f" (default {default:g})" if default is not None else " (default: no limit)"))
    p.set_defaults(budget_per_claim=per_claim)


def command_budget(args: argparse.Namespace) -> Budget:
    """The budget a command runs in: its --seconds, unless that is a per-claim budget (or the command has none)."""
    given = getattr(args, "seconds", None)
    if given is None or getattr(args, "budget_per_claim", False):
        return Budget(None)
    return Budget(given, raise_with=f"a larger --seconds than {given:g}")


def add_values_options(p: argparse.ArgumentParser) -> None:
    """--eps, --param NAME=VALUE and --seed: eps and parameters fixed exactly, the others random."""
    p.add_argument("--eps", help="a non-zero rational eps, read exactly, e.g. 1/10 or 0.1 (hkproof's eps is half "
                   "the time step; default: random)")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="fix a parameter to an exact rational (repeatable; the others are random)")
    p.add_argument("--seed", type=integer, default=0, help="seed of the random points and values (default 0)")


def fixed_values(args: argparse.Namespace) -> dict[str, str]:
    """The values fixed on the command line (--eps and every --param NAME=VALUE), as text; QuadraticField.check_values
    reads them exactly and checks them against the system."""
    values: dict[str, str] = {}
    for item in args.param:
        name, sep, value = item.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ParseError(f"--param expects NAME=VALUE, got {item!r}")
        if name.strip() in values:
            raise ParseError(f"--param {name.strip()} is given twice")
        values[name.strip()] = value.strip()
    if args.eps is not None:
        values["eps"] = args.eps
    return values


def progress_bar(args: argparse.Namespace, desc: str, unit: str, total: int | None = None) -> tqdm:
    """A progress bar on stderr for a person at a terminal (none under --json or --no-progress, or off a terminal)."""
    quiet = getattr(args, "no_progress", False) or getattr(args, "json", False)
    return bar(total, unit, enabled=False if quiet else None, desc=desc)


def add_progress_option(p: argparse.ArgumentParser) -> None:
    """--no-progress: no progress bar on stderr."""
    p.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")


def positive_int(text: str) -> int:
    """An argparse type: a whole number >= 1, in ASCII digits."""
    try:
        value = read_integer(text)
    except HKProofError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is not a positive number of jobs")
    return value


_ADDRESS = re.compile(r"(?:(?:tcp|tls|ucx|ws|wss)://)?(?:\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+)(?::(?P<port>[0-9]{1,5}))?")


def scheduler_address(text: str) -> str:
    """An argparse type: the address of a Dask scheduler, [PROTOCOL://]HOST[:PORT] (e.g. tcp://10.0.0.5:8786)."""
    address = text.strip()
    m = _ADDRESS.fullmatch(address)
    if not address or m is None or (m.group("port") is not None and not 0 < int(m.group("port")) < 65536):
        raise argparse.ArgumentTypeError(f"{text!r} is not a scheduler address: give [PROTOCOL://]HOST[:PORT], e.g. "
                                         "tcp://10.0.0.5:8786 (PROTOCOL tcp, tls, ucx, ws or wss; PORT 1 to 65535)")
    return address


def add_run_options(parser: argparse.ArgumentParser, jobs: int | None = None) -> None:
    """--jobs (default `jobs`, or the machine's cores), --executor, --scheduler: where the claims (or a command's
    independent steps) run."""
    default = jobs or os.cpu_count() or 1
    parser.add_argument("--jobs", type=positive_int, default=default, metavar="N",
                        help="run up to N independent tasks at once (default: "
                             + ("the machine's cores" if jobs is None else str(jobs)) + "; 1: a plain loop "
                             "in this process)")
    parser.add_argument("--executor", choices=EXECUTORS, default="process",
                        help="process: a pool of local processes; dask: Dask distributed (pip install "
                             "'hkproof[dask]'), a LocalCluster of N workers unless --scheduler is given; the "
                             "points of lattice identities and the primes of modular ones run there too")
    parser.add_argument("--scheduler", type=scheduler_address, metavar="ADDRESS",
                        help="with --executor dask: the address of a running Dask scheduler, e.g. tcp://host:8786")


def run_options(args: argparse.Namespace) -> RunOptions:
    """The RunOptions of --jobs, --executor and --scheduler."""
    return RunOptions(args.jobs, args.executor, args.scheduler,
                      getattr(args, "seconds", None) if getattr(args, "budget_per_claim", False) else None)
