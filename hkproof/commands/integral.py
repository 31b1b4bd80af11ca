"""`hkproof integral SYSTEM EXPR`: is this rational function an integral of the system's Kahan map?"""
from __future__ import annotations

import argparse

from hkproof.algebra.fraction import Frac
from hkproof.commands import Result, add_command
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.integrals import check_integral


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "integral", "decide exactly whether EXPR is an integral of the Kahan map of SYSTEM",
                    run_integral)
    p.add_argument("system", help="a catalogue name or a TOML file")
    p.add_argument("expr", help="a rational function in the system's variables, eps and parameters")


def run_integral(args: argparse.Namespace) -> Result:
    f = kahan_map(args.system)
    h = Frac.parse(f.ring, args.expr)
    verdict = check_integral(f, h)
    payload = {"system": f.field.name, "expr": str(h), **verdict.to_dict()}
    text = (f"{verdict.verdict}: {args.expr} is {'an' if verdict.verdict == 'verified' else 'not an'} integral of "
            f"the Kahan map of {f.field.name} (exact, in {verdict.ring}, by {verdict.method})")
    return Result(payload, text, 0 if verdict.verdict == "verified" else 1)
