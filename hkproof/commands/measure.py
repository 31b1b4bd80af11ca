"""`hkproof measure SYSTEM [--degree D]`: Darboux polynomials, invariant measures dx/P and integrals P_i/P_j."""
from __future__ import annotations

import argparse

from hkproof.commands import (Result, add_budget_option, add_command, add_param_option, add_progress_option,
                              add_system_argument, at_least, integer, progress_bar, specialized_map)
from hkproof.commands._certificates import (add_certificate_option, certificate_target, measure_document,
                                            write_certificate)
from hkproof.commands._geometry import EPS_CONVENTION
from hkproof.pipelines.darboux import MAX_DARBOUX_DEGREE, search_darboux

__all__ = ["register", "run_measure"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "measure", "Darboux polynomials P o f = K P of degree <= D with cofactors K among the "
                    "factors of det Df, invariant measures dx/P (rho(f(x)) det Df(x) = rho(x)) and the integrals "
                    "P_i/P_j of equal cofactors: searched mod p at random rational eps and parameters, reconstructed "
                    f"with them symbolic, each checked exactly. {EPS_CONVENTION}.", run_measure)
    add_budget_option(p)
    add_system_argument(p)
    p.add_argument("--degree", type=at_least(1, MAX_DARBOUX_DEGREE), default=4,
                   help=f"largest degree of P (default 4, at most {MAX_DARBOUX_DEGREE})")
    add_param_option(p)
    p.add_argument("--seed", type=integer, default=0, help="seed of the values, prime and points (default 0)")
    add_progress_option(p)
    add_certificate_option(p)


def run_measure(args: argparse.Namespace) -> Result:
    target = certificate_target(args)
    _, f, fixed = specialized_map(args)
    with progress_bar(args, "measure", "Darboux polynomials") as shown:
        res = search_darboux(f, args.degree, seed=args.seed, fixed=fixed, progress=lambda found: shown.update())
    payload = res.to_dict()
    text = res.text() + (write_certificate(target, measure_document(f, res), payload) if target else "")
    return Result(payload, text)
