"""`hkproof integral SYSTEM EXPR`: is this rational function an integral of the system's Kahan map?"""
from __future__ import annotations

import argparse
from typing import Mapping

from hkproof.algebra.fraction import Frac
from hkproof.algebra.groebner import MembershipCertificate
from hkproof.commands import (Result, add_budget_option, add_command, add_param_option, add_system_argument,
                              integer, specialized_map)
from hkproof.commands._certificates import add_certificate_option, certificate_target, write_certificate
from hkproof.dynamics.kahan import KahanMap
from hkproof.experiments.refute import modular_witness
from hkproof.hk.integrals import check_integral
from hkproof.hk.recipe_g import recipe_g
from hkproof.proof.export import document, recipe_g_step, substitution_step
from hkproof.proof.status import Status, exit_code, specialized_label

__all__ = ["register", "run_integral"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "integral", "decide exactly whether EXPR is an integral of the Kahan map of SYSTEM "
                    "(exit 0 verified, 1 refuted)", run_integral)
    add_budget_option(p)
    add_system_argument(p)
    p.add_argument("expr", help="a rational function in the system's variables, eps (half the time step) and "
                   "parameters, e.g. \"(x1**2 - x2**2)/3\"; decimals are read exactly (0.1 = 1/10)")
    p.add_argument("--method", choices=("substitution", "groebner"), default="substitution",
                   help="substitution: h(N/Delta) - h = 0; groebner: recipe (G), Delta^k delta = sum lambda_i E_i "
                        "with cofactors checked by expansion")
    add_param_option(p)
    p.add_argument("--seed", type=integer, default=0, help="seed of the random point of the first, modular check")
    add_certificate_option(p)


def run_integral(args: argparse.Namespace) -> Result:
    target = certificate_target(args)
    full, f, fixed = specialized_map(args)
    h = full.field.parse(args.expr)
    if fixed:
        h = h.specialize(fixed, f.ring)
    payload = {"system": f.field.name, "expr": str(h), "fixed": {k: str(v) for k, v in fixed.items()}}
    notes = []
    if not h.variables() & set(f.variables):
        notes.append("h does not depend on the phase variables: it is trivially invariant")
    payload["notes"] = notes
    witness = modular_witness(f, h, seed=args.seed)
    if witness is not None:
        payload.update({"verdict": Status.REFUTED.label, "method": "evaluation mod p at a random point",
                        "witness": witness.to_dict()})
        return Result(payload, f"refuted: {args.expr} is not an integral of the Kahan map of {f.field.name}: "
                      f"{witness.text()}", exit_code(Status.REFUTED))
    if args.method == "groebner":
        result, membership = _run_recipe_g(f, h, args.expr, fixed, payload)
        step = None if membership is None else recipe_g_step(
            f.field, "h", h, membership.generators, membership.cofactors, membership.multiplier ** membership.power)
    else:
        verdict = check_integral(f, h)
        ok = verdict.status is Status.VERIFIED
        label = specialized_label(verdict.status, fixed)
        payload.update({**verdict.to_dict(), "verdict": label})
        text = (f"{label}: {args.expr} is {'an' if ok else 'not an'} integral of the Kahan map of {f.field.name} "
                f"(exact, in {verdict.ring}, by {verdict.method})" + "".join(f"\nnote: {n}" for n in notes))
        result = Result(payload, text, exit_code(verdict.status))
        step = substitution_step(f.field, "h", h)
    if result.exit_code != 0 and target is not None:
        result.text += f"\nno certificate written to {target}: the claim is not verified"
    elif result.exit_code == 0:
        doc = document(f"an integral of the Kahan map of {f.field.name}", f"h = {h} is an integral of the Kahan map "
                       f"of {f.field.name}", [step] if step else [], {k: str(v) for k, v in fixed.items()})
        result.text += write_certificate(target, doc, payload)
    return result


def _run_recipe_g(f: KahanMap, h: Frac, expr: str, fixed: Mapping[str, object],
                  payload: dict) -> tuple[Result, MembershipCertificate | None]:
    """The --method groebner branch: recipe (G) with a cofactor certificate (the identity, when verified)."""
    res = recipe_g(f, h)
    ring = f"Z[{', '.join(f.field.tilde_ring.names)}]"
    ok = res.status is Status.VERIFIED
    label = specialized_label(res.status, fixed)
    payload.update({"ring": ring, "method": "recipe (G): elimination of x~, cofactors checked by expansion",
                    **res.to_dict(), "verdict": label})
    text = (f"{label}: {expr} is {'an' if ok else 'not an'} integral of the Kahan map of "
            f"{f.field.name} (recipe (G) in {ring}; certificate det M^{res.power} * delta = sum lambda_i E_i, "
            f"lambda = adj(M)^T q, {res.certificate_terms} terms in q and adj(M))")
    return Result(payload, text, exit_code(res.status)), res.certificate
