"""`hkproof discover SYSTEM`: from a quadratic vector field to certified integrals of its Kahan map."""
from __future__ import annotations

import argparse

from hkproof.commands import (Result, add_command, add_progress_option, add_system_argument, fixed_values,
                              progress_bar)
from hkproof.budget import Budget
from hkproof.dynamics.catalogue import get_system
from hkproof.experiments.progress import message_bar
from hkproof.pipelines.discover import discover

__all__ = ["register", "run_discover"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "discover", "search HK-bases among monomials of degree <= D, reconstruct the integrals "
                    "and certify them exactly", run_discover)
    add_system_argument(p)
    p.add_argument("--degree", type=int, default=2, help="largest degree of the basis monomials (default 2)")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="fix a parameter to a rational (repeatable); the others stay symbolic")
    p.add_argument("--seconds", type=float, default=300.0,
                   help="time budget; the report says what was covered when it runs out (default 300)")
    p.add_argument("--seed", type=int, default=0, help="seed of the random points and primes (default 0)")
    p.add_argument("--latex", action="store_true", help="print the integrals found as LaTeX")
    add_progress_option(p)


def run_discover(args: argparse.Namespace) -> Result:
    field = get_system(args.system)
    params = fixed_values(argparse.Namespace(param=args.param, eps=None))    # eps stays symbolic
    with progress_bar(args, "discover", "events") as shown:
        report = discover(field, args.degree, params=params, seed=args.seed, progress=message_bar(shown),
                          budget=Budget(args.seconds, raise_with=f"a larger --seconds than {args.seconds:g}"))
    return Result(report.to_dict(), report.latex() if args.latex else report.text(), 0)
