"""`hkproof measure SYSTEM [--degree D]`: Darboux polynomials, invariant measures dx/P and integrals P_i/P_j."""
from __future__ import annotations

import argparse
from typing import Any

from hkproof.algebra.fraction import poly_str
from hkproof.commands import Result, add_command, add_param_option, add_system_argument, at_least, specialized_map
from hkproof.commands._geometry import EPS_CONVENTION, specialized_status
from hkproof.hk.darboux import search_darboux

JACOBIAN = "det Df(x) = det M(f(x), -eps) / det M(x, eps), from M(x, eps) Df(x) = M(f(x), -eps)"


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "measure", "Darboux polynomials P o f = K P of degree <= D with cofactors K among the "
                    "factors of det Df, invariant measures dx/P (rho(f(x)) det Df(x) = rho(x)) and the integrals "
                    "P_i/P_j of equal cofactors: searched mod p at random rational eps and parameters, reconstructed "
                    f"with them symbolic, each checked exactly. {EPS_CONVENTION}.", run_measure)
    add_system_argument(p)
    p.add_argument("--degree", type=at_least(1), default=4, help="largest degree of P (default 4)")
    add_param_option(p)
    p.add_argument("--seed", type=int, default=0, help="seed of the values, prime and points (default 0)")


def run_measure(args: argparse.Namespace) -> Result:
    _, f, fixed = specialized_map(args)
    res = search_darboux(f, args.degree, seed=args.seed)
    atoms = {a.name: (f"det M(x, -eps) o f = {poly_str(a.poly)} at x = f(x)" if a.pulled else poly_str(a.poly))
             for a in res.atoms}
    darboux = [{"expr": poly_str(d.poly), "cofactor": d.cofactor.text(res.atoms), "status": specialized_status(d.status, fixed),
                "method": d.detail} for d in res.darboux]
    densities = [{"expr": e, "status": specialized_status(s, fixed)} for e, s in res.densities()]
    integrals = [{"expr": e, "status": specialized_status(s, fixed)} for e, s in res.integrals()]
    payload: dict[str, Any] = {"system": res.system, "degree": res.degree, "fixed": {k: str(v) for k, v in fixed.items()}, "eps_convention": EPS_CONVENTION,
               "jacobian": {"formula": JACOBIAN, "identity": "verified" if res.jacobian_lemma else "refuted",
                            "as_atoms": res.jacobian.text(res.atoms)},
               "atoms": atoms, "darboux": darboux, "densities": densities, "integrals": integrals,
               "search": {"values": {k: str(v) for k, v in res.values.items()}, "prime": res.prime,
                          "symbolic": res.symbolic},
               "unverified": res.unverified}
    lines = [f"Kahan map of {res.system} ({EPS_CONVENTION})",
             f"{JACOBIAN}: identity {payload['jacobian']['identity']} (exact, in Q(x, eps, parameters not fixed))",
             f"det Df = {res.jacobian.text(res.atoms)} with"]
    lines += [f"  {k} = {v}" for k, v in atoms.items()]
    lines.append(f"Darboux polynomials of degree <= {res.degree} (cofactors: products of these factors):")
    lines += [f"  [{d['status']}] K = {d['cofactor']}: P = {d['expr']}" for d in darboux] or ["  none"]
    lines.append("invariant measure densities rho = 1/P (rho(f(x)) det Df(x) = rho(x)):")
    lines += [f"  [{d['status']}] {d['expr']}" for d in densities] or ["  none found"]
    lines.append("integrals (ratios of Darboux polynomials with equal cofactors):")
    lines += [f"  [{d['status']}] {d['expr']}" for d in integrals] or ["  none found"]
    for u in res.unverified:
        lines.append(f"  not reported: {u}")
    lines.append("searched at " + ", ".join(f"{k} = {v}" for k, v in res.values.items())
                 + f", reduced mod p = {res.prime}; " + (
                     "every P above reconstructed with eps and the parameters symbolic" if res.symbolic else
                     "the system is too large for the symbolic reconstruction: every P above holds at these values "
                     "only (evidence)"))
    return Result(payload, "\n".join(lines))
