"""`hkproof degrees SYSTEM --iterates N`: deg f^n on random lines mod large primes (evidence), and its growth."""
from __future__ import annotations

import argparse

from hkproof.commands import (Result, add_budget_option, add_command, add_system_argument, add_values_options,
                              at_least, fixed_values)
from hkproof.commands._certificates import add_certificate_option, certificate_target, write_certificate
from hkproof.commands._geometry import EPS_CONVENTION
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.degree_growth import MAX_DEGREE
from hkproof.exit_codes import ExitCode
from hkproof.experiments.degree_report import degree_report
from hkproof.proof.export import degrees_step, document
from hkproof.proof.status import Status

__all__ = ["register", "run_degrees"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "degrees", "degree growth (algebraic entropy) of the Kahan map: deg f^n for n = 1..N as a "
                    "rational map in lowest terms, by restriction to random lines over large prime fields at random "
                    f"eps and parameters (evidence, not proof). {EPS_CONVENTION}.", run_degrees)
    add_budget_option(p)
    add_system_argument(p)
    add_values_options(p)
    p.add_argument("--iterates", type=at_least(1), default=8,
                   help=f"largest n (default 8; fewer when a step would work with polynomials in t of degree above "
                        f"{MAX_DEGREE}, or when --seconds runs out: then the degrees found so far, exit 4)")
    p.add_argument("--runs", type=at_least(1), default=2,
                   help="independent (prime, line, values) runs that must agree (default 2)")
    p.add_argument("--symbolic-up-to", type=at_least(0), default=0, metavar="K",
                   help="also compute f^n for n <= K with eps and the parameters symbolic: those degrees are exact "
                        "(costly: the Euler top's f^5 takes about 20 s, the Clebsch f^2 minutes)")
    add_certificate_option(p)


def run_degrees(args: argparse.Namespace) -> Result:
    fixed = fixed_values(args)
    target = certificate_target(args)
    kmap = kahan_map(args.system)
    report = degree_report(kmap, args.iterates, fixed, seed=args.seed, runs=args.runs,
                           symbolic_up_to=args.symbolic_up_to)
    res, exact, status = report.found, report.symbolic, report.status
    payload = {"system": res.system, "degrees": res.degrees, "second_differences": res.second_differences,
               **res.growth.to_dict(), "status": status.label, "agree": res.agree, "stopped": report.stopped,
               "stopped_because": res.stopped, "symbolic_degrees": exact, "symbolic_agree": report.symbolic_agree,
               "runs": [{"prime": r.prime, "values_mod_p": r.values, "degrees": r.degrees} for r in res.runs],
               "eps_convention": EPS_CONVENTION}
    lines = [f"deg f^n of the Kahan map of {res.system}, n = 1..{len(res.degrees)}: {res.degrees}",
             f"second differences: {res.second_differences}", *res.growth.describe()]
    for r in res.runs:
        at = ", ".join(f"{k} = {fixed[k]}" if k in fixed else f"{k} = {v} (random)" for k, v in r.values.items())
        lines.append(f"  run mod p = {r.prime} at {at}: {r.degrees}")
    if exact:
        lines.append(f"symbolic iterates (eps and parameters symbolic), n = 1..{len(exact)}: {exact} "
                     + ("(exact; they agree with the modular values)" if report.symbolic_agree else
                        "(exact; the modular values DISAGREE: trust these)"))
    if report.stopped:
        lines.append(f"stopped after {len(res.degrees)} iterates: {res.stopped}")
    lines.append(("the runs agree" if res.agree else "the runs DISAGREE (the largest degree is kept: a special "
                  "choice only lowers degrees)") + f"; status {status.label}: {report.status_reason}")
    lines.append(f"({EPS_CONVENTION})")
    doc = None
    if status is Status.VERIFIED:
        doc = document(f"the degrees of the iterates of the Kahan map of {res.system}",
                       f"deg f^n = {exact} for n = 1..{len(exact)}, eps and every parameter symbolic",
                       [degrees_step(kmap.field, exact)])
    return Result(payload, "\n".join(lines) + write_certificate(target, doc, payload),
                  ExitCode.LIMIT if res.budget_ran_out else ExitCode.VERIFIED)

