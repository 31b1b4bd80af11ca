"""`hkproof integral SYSTEM EXPR`: is this rational function an integral of the system's Kahan map?"""
from __future__ import annotations

import argparse

from hkproof.algebra.fraction import Frac
from hkproof.commands import Result, add_command
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.integrals import check_integral
from hkproof.hk.recipe_g import recipe_g


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "integral", "decide exactly whether EXPR is an integral of the Kahan map of SYSTEM",
                    run_integral)
    p.add_argument("system", help="a catalogue name or a TOML file")
    p.add_argument("expr", help="a rational function in the system's variables, eps and parameters")
    p.add_argument("--method", choices=("substitution", "groebner"), default="substitution",
                   help="substitution: h(N/Delta) - h = 0; groebner: recipe (G), Delta^k delta = sum lambda_i E_i "
                        "with cofactors checked by expansion")


def run_integral(args: argparse.Namespace) -> Result:
    f = kahan_map(args.system)
    h = Frac.parse(f.ring, args.expr)
    if getattr(args, "method", "substitution") == "groebner":
        return _run_recipe_g(f, h, args.expr)
    verdict = check_integral(f, h)
    payload = {"system": f.field.name, "expr": str(h), **verdict.to_dict()}
    text = (f"{verdict.verdict}: {args.expr} is {'an' if verdict.verdict == 'verified' else 'not an'} integral of "
            f"the Kahan map of {f.field.name} (exact, in {verdict.ring}, by {verdict.method})")
    return Result(payload, text, 0 if verdict.verdict == "verified" else 1)


def _run_recipe_g(f, h: Frac, expr: str) -> Result:
    """The --method groebner branch: recipe (G) with a cofactor certificate."""
    res = recipe_g(f, h)
    ring = f"Z[{', '.join(f.field.tilde_ring.names)}]"
    payload = {"system": f.field.name, "expr": str(h), "ring": ring, "method": "recipe (G): elimination of x~, "
               "cofactors checked by expansion", **res.to_dict()}
    text = (f"{res.verdict}: {expr} is {'an' if res.verdict == 'verified' else 'not an'} integral of the Kahan map of "
            f"{f.field.name} (recipe (G) in {ring}; certificate det M^{res.power} * delta = sum lambda_i E_i, "
            f"{res.cofactor_terms} cofactor terms)")
    return Result(payload, text, 0 if res.verdict == "verified" else 1)
