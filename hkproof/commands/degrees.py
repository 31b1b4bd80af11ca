"""`hkproof degrees SYSTEM --iterates N`: deg f^n on random lines mod large primes (evidence), and its growth."""
from __future__ import annotations

import argparse

from hkproof.commands import Result, add_command, add_system_argument, add_values_options, at_least, fixed_values
from hkproof.commands._geometry import EPS_CONVENTION
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.degrees import MAX_DEGREE, degree_growth, fit_growth, symbolic_degree
from hkproof.proof.status import Status

__all__ = ["register", "run_degrees"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "degrees", "degree growth (algebraic entropy) of the Kahan map: deg f^n for n = 1..N as a "
                    "rational map in lowest terms, by restriction to random lines over large prime fields at random "
                    f"eps and parameters (evidence, not proof). {EPS_CONVENTION}.", run_degrees)
    add_system_argument(p)
    add_values_options(p)
    p.add_argument("--iterates", type=at_least(1), default=8, help="largest n (default 8)")
    p.add_argument("--runs", type=at_least(1), default=2,
                   help="independent (prime, line, values) runs that must agree (default 2)")
    p.add_argument("--symbolic-up-to", type=at_least(0), default=0, metavar="K",
                   help="also compute f^n for n <= K with eps and the parameters symbolic: those degrees are exact "
                        "(costly: the Euler top's f^5 takes about 20 s, the Clebsch f^2 minutes)")


def run_degrees(args: argparse.Namespace) -> Result:
    f = kahan_map(args.system)
    fixed = fixed_values(args)
    res = degree_growth(f, args.iterates, fixed, seed=args.seed, runs=args.runs)
    exact = [symbolic_degree(f, n) for n in range(1, min(args.symbolic_up_to, len(res.degrees)) + 1)]
    agree = exact == res.degrees[:len(exact)]
    if not agree:       # the symbolic degrees are exact: they replace the modular ones, and the growth is refitted
        res.degrees[:len(exact)] = exact
        res.growth = fit_growth(res.degrees)
    status = Status.VERIFIED if agree and len(exact) == args.iterates == len(res.degrees) else Status.EVIDENCE_EXACT
    payload = {"system": res.system, "degrees": res.degrees, "second_differences": res.second_differences,
               **res.growth.to_dict(), "status": status.label, "agree": res.agree,
               "stopped": len(res.degrees) < args.iterates,
               "symbolic_degrees": exact, "symbolic_agree": exact == res.degrees[:len(exact)],
               "runs": [{"prime": r.prime, "values_mod_p": r.values, "degrees": r.degrees} for r in res.runs],
               "eps_convention": EPS_CONVENTION}
    lines = [f"deg f^n of the Kahan map of {res.system}, n = 1..{len(res.degrees)}: {res.degrees}",
             f"second differences: {res.second_differences}",
             f"growth: {res.growth.kind}, deg f^n = {res.growth.formula()}"
             + (f", algebraic entropy log lambda = {res.growth.entropy:.6g}" if res.growth.entropy else "")]
    for r in res.runs:
        at = ", ".join(f"{k} = {fixed[k]}" if k in fixed else f"{k} = {v} (random)" for k, v in r.values.items())
        lines.append(f"  run mod p = {r.prime} at {at}: {r.degrees}")
    if exact:
        same = exact == res.degrees[:len(exact)]
        lines.append(f"symbolic iterates (eps and parameters symbolic), n = 1..{len(exact)}: {exact} "
                     + ("(exact; they agree with the modular values)" if same else
                        "(exact; the modular values DISAGREE: trust these)"))
    if len(res.degrees) < args.iterates:
        lines.append(f"stopped after {len(res.degrees)} iterates: the next degree could exceed {MAX_DEGREE}")
    lines.append(("the runs agree" if res.agree else "the runs DISAGREE (the largest degree is kept: a special "
                  "choice only lowers degrees)") + f"; status {status.label}: "
                 + ("every degree from the symbolic iterates" if status is Status.VERIFIED else
                    "degrees computed mod p on random lines at random values, not a proof"
                    + (f" beyond n = {len(exact)}" if exact else "")))
    lines.append(f"({EPS_CONVENTION})")
    return Result(payload, "\n".join(lines))
