"""`hkproof degrees SYSTEM --iterates N`: deg f^n on random lines mod large primes (evidence), and its growth."""
from __future__ import annotations

import argparse

from hkproof.commands import Result, add_command
from hkproof.commands._geometry import EPS_CONVENTION, add_system_options
from hkproof.commands.scan import scene_values
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.degrees import MAX_DEGREE, degree_growth
from hkproof.proof.status import Status


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "degrees", "degree growth (algebraic entropy) of the Kahan map: deg f^n for n = 1..N as a "
                    "rational map in lowest terms, by restriction to random lines over large prime fields at random "
                    f"eps and parameters (evidence, not proof). {EPS_CONVENTION}.", run_degrees)
    add_system_options(p, "a rational eps (default: random mod p)")
    p.add_argument("--iterates", type=int, default=8, help="largest n (default 8)")
    p.add_argument("--runs", type=int, default=2,
                   help="independent (prime, line, values) runs that must agree (default 2)")
    p.add_argument("--seed", type=int, default=0, help="seed of the primes, lines and values (default 0)")


def run_degrees(args: argparse.Namespace) -> Result:
    f = kahan_map(args.system)
    fixed = scene_values(args)
    res = degree_growth(f, args.iterates, fixed, seed=args.seed, runs=max(1, args.runs))
    status = Status.EVIDENCE_EXACT
    payload = {"system": res.system, "degrees": res.degrees, "second_differences": res.second_differences,
               **res.growth.to_dict(), "status": status.label, "agree": res.agree,
               "stopped": len(res.degrees) < args.iterates,
               "runs": [{"prime": r.prime, "values_mod_p": r.values, "degrees": r.degrees} for r in res.runs],
               "eps_convention": EPS_CONVENTION}
    lines = [f"deg f^n of the Kahan map of {res.system}, n = 1..{len(res.degrees)}: {res.degrees}",
             f"second differences: {res.second_differences}",
             f"growth: {res.growth.kind}, deg f^n = {res.growth.formula()}"
             + (f", algebraic entropy log lambda = {res.growth.entropy:.6g}" if res.growth.entropy else "")]
    for r in res.runs:
        at = ", ".join(f"{k} = {fixed[k]}" if k in fixed else f"{k} = {v} (random)" for k, v in r.values.items())
        lines.append(f"  run mod p = {r.prime} at {at}: {r.degrees}")
    if len(res.degrees) < args.iterates:
        lines.append(f"stopped after {len(res.degrees)} iterates: the next degree could exceed {MAX_DEGREE}")
    lines.append(("the runs agree" if res.agree else "the runs DISAGREE (the largest degree is kept: a special "
                  "choice only lowers degrees)") + f"; status {status.label}: degrees computed mod p on random "
                 "lines at random values, not a proof")
    lines.append(f"({EPS_CONVENTION})")
    return Result(payload, "\n".join(lines))
