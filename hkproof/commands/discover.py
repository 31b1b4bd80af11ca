"""`hkproof discover SYSTEM`: from a quadratic vector field to certified integrals of its Kahan map."""
from __future__ import annotations

import argparse

from hkproof.budget import current
from hkproof.commands import (Result, add_budget_option, add_command, add_progress_option, add_run_options,
                              add_system_argument, at_least, fixed_values, integer, progress_bar)
from hkproof.commands._certificates import add_certificate_option, certificate_target, write_certificate
from hkproof.dynamics.catalogue import get_system
from hkproof.experiments.progress import message_bar
from hkproof.orchestration.execution import map_executor
from hkproof.pipelines.discover import discover
from hkproof.pipelines.discover.run import MAX_SEARCH_DEGREE
from hkproof.pipelines.discover.certificate import discover_document

__all__ = ["register", "run_discover"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "discover", "search HK-bases among monomials of degree <= D, reconstruct the integrals "
                    "and certify them exactly", run_discover)
    add_system_argument(p)
    p.add_argument("--degree", type=at_least(1, MAX_SEARCH_DEGREE), default=2,
                   help=f"largest degree of the basis monomials (default 2, at most {MAX_SEARCH_DEGREE})")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="fix a parameter to a rational (repeatable); the others stay symbolic")
    add_budget_option(p, 300.0)
    p.add_argument("--seed", type=integer, default=0, help="seed of the random points and primes (default 0)")
    p.add_argument("--latex", action="store_true", help="print the integrals found as LaTeX")
    add_progress_option(p)
    add_certificate_option(p)
    add_run_options(p, jobs=1)


def run_discover(args: argparse.Namespace) -> Result:
    target = certificate_target(args)
    field = get_system(args.system)
    params = fixed_values(argparse.Namespace(param=args.param, eps=None))    # eps stays symbolic
    with progress_bar(args, "discover", "events") as shown, \
            map_executor(args.executor, args.jobs, args.scheduler, args.jobs) as pool:
        report = discover(field, args.degree, params=params, seed=args.seed, progress=message_bar(shown),
                          budget=current(), mapper=None if pool is None else pool.map)
    payload = report.to_dict()
    text = report.latex() if args.latex else report.text()
    if target is not None:
        text += write_certificate(target, discover_document(report), payload)
    return Result(payload, text, 0)
