"""`hkproof relations SYSTEM --basis ...`: recipe (E), linear relations among kernel coordinates."""
from __future__ import annotations

import argparse
import random

from hkproof.algebra.formula import split_list
from hkproof.commands import Result, add_budget_option, add_command, answer_code, at_least, fixed_values
from hkproof.commands.scan import add_scene_options
from hkproof.dynamics.catalogue import kahan_map
from hkproof.experiments.points import random_values
from hkproof.experiments.pslq import agreement, pslq_relations
from hkproof.experiments.relations import find_relations

__all__ = ["register", "run_relations"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "relations", "recipe (E): constant-coefficient linear relations among the kernel "
                    "coordinates of HK-bases with d = 1, with eps and the parameters symbolic", run_relations)
    add_budget_option(p)
    add_scene_options(p, several_bases=True)
    p.add_argument("--names", help='names of the kernel coordinates, e.g. "c1, c2, c3" (default c1, c2, ...)')
    p.add_argument("--max-degree", type=at_least(0), default=6, help="largest degree of a coefficient tried (default 6)")
    p.add_argument("--pslq", type=at_least(1), metavar="DIGITS",
                   help="also run PSLQ at this many digits (eps and parameters fixed) and compare")


def run_relations(args: argparse.Namespace) -> Result:
    import sympy
    f = kahan_map(args.system)
    names = split_list(args.names, "--names") if args.names else None
    fixed = fixed_values(args)
    search = find_relations(f, args.basis, names=names, values=fixed or None, max_degree=args.max_degree,
                            seed=args.seed)
    payload = {"system": f.field.name, "bases": args.basis, **search.to_dict()}
    normalization = "; ".join(f"last coordinate of ({b}) = -1" for b in args.basis)
    lines = [f"kernel coordinates of {len(args.basis)} basis(es) for the Kahan map of {f.field.name} "
             f"({normalization}):",
             f"{search.dimension} independent relation(s); found {len(search.relations)} exactly "
             f"({search.samples} exact samples, coefficients of degree <= {search.degree}, "
             f"{', '.join(search.normalized) or 'nothing'} scaled to 1 and restored by weighted homogeneity)"]
    lines += [f"  {r.text()}" for r in search.relations]
    lines += [f"  note: {n}" for n in search.notes]
    if args.pslq:
        values = _pslq_values(f, fixed, args.seed)
        ps = pslq_relations(f, args.basis, values, names=search.names, digits=args.pslq, seed=args.seed)
        right, recovered = agreement(ps, search.relations, values)
        payload["pslq"] = {**ps.to_dict(), "values": {k: str(v) for k, v in values.items()},
                           "in_exact_span": right, "exact_relations_recovered": recovered}
        lines.append(f"PSLQ at {args.pslq} digits ({', '.join(f'{k}={v}' for k, v in values.items())}): "
                     f"{len(ps.relations)} relation(s), {right} in the exact span, recovering {recovered} of "
                     f"{search.dimension}; {ps.rejected} candidate(s) rejected as inconsistent across points")
        cols = [sympy.Symbol(n) for n in search.names] + [sympy.Integer(1)]
        lines += [f"  {sympy.Add(*[a * c for a, c in zip(rel, cols, strict=True)])} = 0" for rel in ps.relations]
    return Result(payload, "\n".join(lines), answer_code(len(search.relations) == search.dimension))


def _pslq_values(f, fixed: dict, seed: int) -> dict:
    """eps and parameters for PSLQ: the given ones, the others random rationals."""
    return random_values(f, random.Random(seed), fixed or None)
