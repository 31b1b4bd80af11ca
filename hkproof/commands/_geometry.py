"""Options and wording shared by the geometry commands (degrees, orbit, measure, hamiltonian)."""
from __future__ import annotations

import argparse

from hkproof.dynamics.catalogue import SYSTEMS

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
