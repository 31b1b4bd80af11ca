"""`hkproof depend SYSTEM --target T --on U ...`: rational relations T = Q(U)/P(U) at fixed parameters (evidence)."""
from __future__ import annotations

import argparse
import random

from hkproof.algebra.fraction import Frac
from hkproof.algebra.formula import check_name, check_new_names, read_integer, split_list
from hkproof.commands import (Result, add_budget_option, add_command, add_system_argument, add_values_options,
                              answer_code, at_least, fixed_values)
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, ParseError
from hkproof.experiments.rational_relations import find_rational_relations
from hkproof.experiments.points import random_values
from hkproof.orchestration.registry import proven

__all__ = ["register", "run_depend"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "depend", "find relations T * P(U) = Q(U) among integrals, exactly, at fixed eps and "
                    "parameters (evidence: a formula to prove, not a proof)", run_depend)
    add_budget_option(p)
    add_system_argument(p)
    p.add_argument("--target", required=True, metavar="NAME=EXPR | CLAIM:NAME",
                   help="the function T: a formula, or a formula recorded by a proven claim (e.g. dc-theta:g1)")
    p.add_argument("--on", required=True, action="append", metavar="NAME=EXPR | CLAIM:NAME[,NAME...]",
                   help="the functions U (repeatable), e.g. --on dc345-abcd:A,B,C,D")
    p.add_argument("--degrees", type=at_least(0), nargs=2, default=(1, 1), metavar=("DEG_P", "DEG_Q"),
                   help="total degrees of P and Q (default 1 1)")
    p.add_argument("--cap", action="append", default=[], metavar="NAME=K",
                   help="degree cap of one U in the monomials (e.g. D=1 when D^2 is known in the others)")
    add_values_options(p)


def run_depend(args: argparse.Namespace) -> Result:
    f = kahan_map(args.system)
    target_given = _functions(f, args.target)
    if len(target_given) != 1:
        raise ParseError(f"--target names one function T, not {len(target_given)} ({', '.join(target_given)})")
    (target_name, target), = target_given.items()
    given = [_functions(f, item) for item in args.on]
    check_new_names([target_name, *(name for g in given for name in g)], f.ring.names, "function name")
    knowns = {name: h for g in given for name, h in g.items()}
    caps = {}
    for item in args.cap:
        name, sep, k = item.partition("=")
        if not sep or not k.strip().isascii() or not k.strip().isdigit():
            raise ParseError(f"--cap expects NAME=K with K a non-negative integer, got {item!r}")
        if name.strip() not in knowns:
            raise ParseError(f"--cap {name.strip()}: not one of the functions U given with --on ({list(knowns)})")
        caps[name.strip()] = read_integer(k)
    values = random_values(f, random.Random(args.seed), fixed_values(args) or None)
    search = find_rational_relations(target, knowns, values, f.variables, degrees=tuple(args.degrees),
                                     max_degree=caps, target_name=target_name, seed=args.seed)
    at = ", ".join(f"{k} = {v}" for k, v in values.items())
    lines = [f"{target_name} * P({', '.join(knowns)}) = Q(...), deg P <= {args.degrees[0]}, deg Q <= "
             f"{args.degrees[1]}, at {at}: {search.dimension} independent relation(s) "
             f"({search.samples} exact samples, {search.unknowns} unknown coefficients)"]
    lines += [f"  {r.text()}" for r in search.relations]
    if search.among_knowns:
        lines.append(f"and {len(search.among_knowns)} relation(s) among {', '.join(knowns)} alone (not counted):")
        lines += [f"  {r.text()}" for r in search.among_knowns]
    lines.append("evidence at these values only: guess the coefficients in eps and the parameters from several "
                 "runs, then prove the identity exactly")
    payload = {"system": f.field.name, "target": target_name, "on": list(knowns), "degrees": list(args.degrees),
               "at": {k: str(v) for k, v in values.items()}, "dimension": search.dimension,
               "relations": [r.to_dict() for r in search.relations],
               "among_knowns": [r.to_dict() for r in search.among_knowns]}
    return Result(payload, "\n".join(lines), answer_code(search.dimension > 0))


def _functions(f: KahanMap, item: str) -> dict[str, Frac]:
    """NAME=EXPR (a formula in the system's ring) or CLAIM:NAME[,NAME...] (formulas of a proven claim)."""
    if "=" in item:
        name, expr = item.split("=", 1)
        return {check_name(name.strip(), "function name"): f.field.parse(expr)}
    claim_id, sep, names = item.partition(":")
    if not sep:
        raise ParseError(f"{item!r}: give NAME=EXPR or CLAIM:NAME[,NAME...]")
    cert = proven(claim_id.strip())
    if not cert.status.is_verified:
        raise HKProofError(f"claim {claim_id} is {cert.status.label}: its formulas are not integrals proven here")
    out = {}
    for name in split_list(names, "list of names"):
        if name not in cert.formulas:
            raise ParseError(f"claim {claim_id} records no formula {name!r} (it has {sorted(cert.formulas)})")
        out[name] = Frac.parse(f.ring, cert.formulas[name])
    return out
