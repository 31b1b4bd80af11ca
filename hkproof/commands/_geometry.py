"""Options and wording shared by the geometry commands (degrees, orbit, measure, hamiltonian)."""
from __future__ import annotations

import argparse
import flint

from hkproof.commands import fixed_values
from hkproof.dynamics.catalogue import SYSTEMS, kahan_map
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ParseError
from hkproof.proof.status import Status

EPS_CONVENTION = ("hkproof's eps is HALF the time step: x~ - x = 2 eps * (polarized field), i.e. h = 2 eps in the "
                  "convention of Celledoni-McLachlan-Owren-Quispel")


def add_system_argument(p: argparse.ArgumentParser) -> None:
    """SYSTEM: a catalogue name or a TOML file."""
    p.add_argument("system", help=f"a catalogue name ({', '.join(SYSTEMS)}) or a TOML file")


def add_system_options(p: argparse.ArgumentParser, eps_help: str = "a rational eps (default: random)") -> None:
    """SYSTEM, --eps and --param NAME=VALUE (the values of scan and depend)."""
    add_system_argument(p)
    p.add_argument("--eps", help=eps_help)
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="fix a parameter to an exact rational (repeatable)")


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


def specialized_status(status: Status, fixed: dict) -> str:
    """The label of a status, lowered to verified(specialized: ...) when parameters were fixed."""
    if fixed and status is Status.VERIFIED:
        return f"verified(specialized: {', '.join(f'{k}={v}' for k, v in fixed.items())})"
    return status.label
