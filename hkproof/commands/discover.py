"""`hkproof discover SYSTEM`: from a quadratic vector field to certified integrals of its Kahan map."""
from __future__ import annotations

import argparse
import sys

from hkproof.commands import Result, add_command, add_system_argument, fixed_values
from hkproof.dynamics.catalogue import get_system
from hkproof.experiments.discovery import discover
from hkproof.hk.discover import DiscoveryReport


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
    p.add_argument("--no-progress", action="store_true", help="no progress lines on stderr")


def run_discover(args: argparse.Namespace) -> Result:
    field = get_system(args.system)
    progress = not args.no_progress and not args.json and sys.stderr.isatty()
    params = fixed_values(argparse.Namespace(param=args.param, eps=None))    # eps stays symbolic
    report = discover(field, args.degree, params=params, seconds=args.seconds, seed=args.seed,
                      progress=progress)
    text = format_latex(report) if args.latex else format_report(report)
    return Result(report.to_dict(), text, 0)


def format_report(r: DiscoveryReport) -> str:
    """The integrals with their status, the kernels, the bases and what the search covered."""
    fixed = f" at {', '.join(f'{k}={v}' for k, v in r.fixed.items())}" if r.fixed else ""
    lines = [f"discover {r.system}{fixed}: monomials of degree <= {r.degree} in {', '.join(r.variables)}"]
    for k in r.kernels:
        lines.append(f"  degree {k['degree']}: {k['monomials']} monomials, kernel dimension {k['dimension']} "
                     f"({k['trivial']} trivial, {k['new']} new)")
    if r.bases:
        lines.append(f"  {len(r.bases)} minimal HK-bases, e.g. " + "; ".join(
            f"({', '.join(b['basis'])}) d={b.get('dimension')}" for b in r.bases[:4]))
    for i in r.integrals:
        expr = "not reconstructed" if i.frac is None else str(i.frac)
        flag = " [independent]" if i.independent else ""
        lines.append(f"  {i.name} = {expr}: {i.status.label}{flag} ({i.kind}"
                     + (f" of ({', '.join(i.basis)})" if i.basis else "") + ")")
    lines.append(f"{r.independent} functionally independent verified integrals in dimension {len(r.variables)}"
                 + (f"; the kernels carry {r.expected_independent} (gradients mod p)"
                    if r.expected_independent is not None else ""))
    if r.negative:
        lines.append(r.negative)
    if r.skipped:
        lines.append(f"{len(r.skipped)} kernel coordinates skipped as too large for dense reconstruction")
    lines.append(("complete: " if r.complete else "budget ran out: ") + "; ".join(r.covered))
    return "\n".join(lines)


def format_latex(r: DiscoveryReport) -> str:
    """One LaTeX equation per integral found (reconstructed ones only), with its status as a comment."""
    out = [f"% integrals of the Kahan map of {r.system} (hkproof discover, degree {r.degree})"]
    for i in r.integrals:
        if i.frac is not None:
            out.append(f"% {i.name}: {i.status.label}\n\\[ \\mathrm{{{i.name}}} = {i.latex()} \\]")
    if len(out) == 1:
        out.append("% no integral found")
    return "\n".join(out)
