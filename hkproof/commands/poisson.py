"""`hkproof poisson SYSTEM [--degree D]`: invariant Poisson bivectors Q/D of the Kahan map, proven or excluded."""
from __future__ import annotations

import argparse

from hkproof.budget import current
from hkproof.commands import (Result, add_budget_option, add_command, add_param_option, add_progress_option,
                              add_system_argument, at_least, integer, progress_bar, specialized_map)
from hkproof.commands._certificates import add_certificate_option, certificate_target, write_certificate
from hkproof.commands._geometry import EPS_CONVENTION
from hkproof.exit_codes import ExitCode
from hkproof.experiments.progress import message_bar
from hkproof.pipelines.darboux import MAX_DARBOUX_DEGREE
from hkproof.pipelines.poisson import MAX_POISSON_DEGREE, with_integrals
from hkproof.pipelines.poisson_certificate import poisson_document

__all__ = ["register", "run_poisson"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "poisson", "Invariant bivectors Pi = Q/D with Pi(f(x)) = Df Pi(x) Df^T, deg Q <= D: the "
                    "rank of the invariance rows mod p (one block per sign symmetry), the kernel rebuilt with eps and "
                    "the parameters symbolic and proven (invariance, Jacobi, rank, Casimirs, compatibility, "
                    "involution), or the whole class excluded by a full column rank mod p (a theorem). "
                    f"{EPS_CONVENTION}.", run_poisson)
    add_budget_option(p, 600.0)
    add_system_argument(p)
    p.add_argument("--degree", type=at_least(0, MAX_POISSON_DEGREE), default=3,
                   help=f"largest degree of Q (default 3, at most {MAX_POISSON_DEGREE})")
    p.add_argument("--denominator", action="append", default=[], metavar="FORMULA",
                   help="a candidate denominator D (a polynomial; repeatable); always searched: 1, the irreducible "
                   "factors of the given D, of the denominators of the integrals `discover` proves and of the Darboux "
                   "polynomials of `measure`, and the products of two factors")
    p.add_argument("--integrals-degree", type=at_least(0, 4), default=2,
                   help="degree of discover's search for the integrals (Casimirs, involution, denominators); 0: none")
    p.add_argument("--darboux-degree", type=at_least(0, MAX_DARBOUX_DEGREE), default=4,
                   help="degree of measure's search for Darboux polynomials (their factors are candidate "
                   "denominators; default 4); 0: none")
    p.add_argument("--class", dest="classes", action="append", default=[], metavar="NAME",
                   help="search only the candidate class NAME as the reports name it (1, F4, F2*F4, F4^2; "
                   "repeatable); an unknown name is an error that lists the candidates")
    p.add_argument("--screen", action="store_true",
                   help="ranks only: classes are excluded (a theorem) or reported with the lowest degree and dimension "
                   "of their kernel mod p (evidence), not rebuilt: a quick survey of large classes; a small kernel whose "
                   "members' Schouten brackets are independent mod p proves that the class has no invariant Poisson "
                   "structure (a theorem)")
    add_param_option(p)
    p.add_argument("--seed", type=integer, default=0, help="seed of the values, prime and points (default 0)")
    add_progress_option(p)
    add_certificate_option(p)


def run_poisson(args: argparse.Namespace) -> Result:
    target = certificate_target(args)
    _, f, fixed = specialized_map(args)
    denominators = [f.field.parse(text) for text in args.denominator]
    with progress_bar(args, "poisson", "events") as shown:
        report = with_integrals(f, args.degree, denominators, args.integrals_degree,
                                darboux_degree=args.darboux_degree, seed=args.seed, fixed=fixed, screen=args.screen,
                                progress=message_bar(shown), budget=current(), only=args.classes)
    code = ExitCode.VERIFIED if report.complete else ExitCode.LIMIT
    payload = report.to_dict()
    text = report.text() + (write_certificate(target, poisson_document(f, report), payload) if target else "")
    return Result(payload, text, code)
