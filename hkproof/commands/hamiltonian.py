"""`hkproof hamiltonian SYSTEM --hamiltonian H --poisson J`: the modified Hamiltonian and measure of Kahan's method."""
from __future__ import annotations

import argparse

from hkproof.algebra.fraction import Frac
from hkproof.commands import (Result, add_budget_option, add_command, add_param_option, add_system_argument,
                              specialized_map)
from hkproof.commands._certificates import (add_certificate_option, certificate_target, hamiltonian_document,
                                            write_certificate)
from hkproof.commands._geometry import EPS_CONVENTION
from hkproof.hk.modified_hamiltonian import parse_matrix, verify
from hkproof.proof.status import Status, exit_code, specialized_label

__all__ = ["FORMULA", "register", "run_hamiltonian"]

FORMULA = "H~ = H + (h/3) grad H^T (I - (h/2) F')^(-1) F, density 1/det(I - (h/2) F'), h = 2 eps"


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "hamiltonian", "for F = J grad H with H cubic and J constant and skew: construct the modified "
                    "Hamiltonian H~ = H + (h/3) grad H^T (I - (h/2) F')^-1 F and the measure dx / det(I - (h/2) F') "
                    "of Celledoni-McLachlan-Owren-Quispel (2013) and verify exactly that the Kahan map preserves "
                    f"both. {EPS_CONVENTION}.", run_hamiltonian)
    add_budget_option(p)
    add_system_argument(p)
    p.add_argument("--hamiltonian", required=True, metavar="H",
                   help="a polynomial of degree <= 3, e.g. 'p**2/2 + q**3'")
    p.add_argument("--poisson", required=True, metavar="J",
                   help="a constant skew matrix, e.g. '[[0, 1], [-1, 0]]' or '0, 1; -1, 0'")
    add_param_option(p)
    add_certificate_option(p)


def run_hamiltonian(args: argparse.Namespace) -> Result:
    target = certificate_target(args)
    original, f, fixed = specialized_map(args)
    h = Frac.parse(original.ring, args.hamiltonian)
    j = parse_matrix(original, args.poisson)
    if fixed:
        h = h.specialize(fixed, f.ring)
        j = [[e.specialize(fixed, f.ring) for e in row] for row in j]
    res = verify(f, h, j)
    payload = {"system": f.field.name, "eps_convention": EPS_CONVENTION, "formula": FORMULA,
               "hamiltonian": str(h), "fixed": {k: str(v) for k, v in fixed.items()},
               "modified_hamiltonian": {"expr": str(res.h_tilde), "status": specialized_label(res.integral, fixed)},
               "density": {"expr": f"1/({res.density_denominator})",
                           "status": specialized_label(res.measure, fixed)},
               "jacobian_identity": "verified" if res.jacobian_identity else "refuted"}
    lines = [f"Kahan map of {f.field.name}; {FORMULA} ({EPS_CONVENTION})",
             f"[{specialized_label(res.integral, fixed)}] H~ o f = H~ with H~ = {res.h_tilde}",
             f"[{specialized_label(res.measure, fixed)}] the density 1/({res.density_denominator}) is invariant: "
             "rho(f(x)) det Df(x) = rho(x), det Df = det M(f(x), -eps)/det M(x, eps)"]
    status = min(res.integral, res.measure)
    ok = status is Status.VERIFIED
    text = "\n".join(lines)
    if ok and target is not None:
        text += write_certificate(target, hamiltonian_document(f, res, {k: str(v) for k, v in fixed.items()}), payload)
    elif target is not None:
        text += f"\nno certificate written to {target}: the claim is not verified"
    return Result(payload, text, exit_code(status))
