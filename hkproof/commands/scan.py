"""`hkproof scan SYSTEM --basis "phi1, phi2, ..."`: algorithm (N) at random points, in a chosen arithmetic."""
from __future__ import annotations

import argparse

from hkproof.commands import (Result, add_budget_option, add_command, add_progress_option, add_run_options,
                              add_system_argument, add_values_options, at_least, fixed_values)
from hkproof.experiments.profiles import HK_BASIS, SINGULAR, KernelProfile
from hkproof.experiments.scan import ScanResult, parallel_tasks, scan
from hkproof.orchestration.execution import map_executor

__all__ = ["add_scene_options", "format_scan", "register", "run_scan"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "scan", "algorithm (N): kernel-dimension profiles of a candidate HK-basis at random points",
                    run_scan)
    add_budget_option(p)
    add_scene_options(p)
    p.add_argument("--points", type=at_least(1), default=10, help="number of random initial points (default 10)")
    p.add_argument("--arithmetic", choices=["exact", "modular", "float", "mpmath"], default="exact",
                   help="exact Q, mod large primes, float64 or mpmath (default exact)")
    p.add_argument("--digits", type=at_least(1), default=50, help="decimal digits for --arithmetic mpmath (default 50)")
    add_progress_option(p)
    add_run_options(p)


def add_scene_options(p: argparse.ArgumentParser, several_bases: bool = False) -> None:
    """SYSTEM, --basis, --eps, --param and --seed: shared by scan and relations."""
    add_system_argument(p)
    p.add_argument("--basis", required=True, action="append" if several_bases else "store",
                   help='the candidate basis, e.g. "x1**2, x2**2, x3**2, 1"'
                   + (" (repeat to relate the kernels of several bases)" if several_bases else ""))
    add_values_options(p)


def run_scan(args: argparse.Namespace) -> Result:
    with map_executor(args.executor, args.jobs, args.scheduler, parallel_tasks(args.points)) as executor:
        result = scan(args.system, args.basis, points=args.points, values=fixed_values(args) or None,
                      arithmetic=args.arithmetic, digits=args.digits, seed=args.seed, executor=executor,
                      progress=False if args.no_progress or args.json else None)
    return Result(result.to_dict(), format_scan(result))


def format_scan(result: ScanResult) -> str:
    """One line per point and the dimension the points support."""
    values = ", ".join(f"{k}={v}" for k, v in result.values.items())
    lines = [f"Phi = ({', '.join(result.basis)}) for the Kahan map of {result.system} at {values}",
             f"arithmetic: {result.arithmetic}; dims = dim ker X_[0,s-1](x) for s = 1..{len(result.basis)}"]
    lines += [f"  {_format_point(p)}" for p in result.profiles]
    skipped = result.count(SINGULAR)
    d = result.dimension
    tail = (f"dimension {d}" + (" (Phi is no HK-basis)" if d == 0 else "") if d is not None
            else "dimension undecided (points disagree or the arithmetic cannot tell)")
    counts = ", ".join(f"{v} {k}" for k, v in result.to_dict()["counts"].items() if v)
    lines.append(f"{tail}; {counts}" + (f" ({skipped} orbits meet Delta = 0: skipped)" if skipped else "")
                 + f"; status {result.status.label}")
    return "\n".join(lines)


def _format_point(p: KernelProfile) -> str:
    head = f"({', '.join(p.point)})"
    if p.verdict == SINGULAR:
        return f"{head}: skipped, {p.reason}"
    sure = p.certainty
    how = (f"gap {sure['gap_ratio']:.1e}" if "gap_ratio" in sure else
           f"primes agree: {len(sure.get('primes', []))}" if "primes" in sure else "exact")
    dims = "[" + ", ".join("?" if v is None else str(v) for v in p.dims) + "]"
    verdict = f"d = {p.dimension}" if p.verdict == HK_BASIS else p.verdict
    return f"{head}: dims {dims} -> {verdict} ({how})"
