"""`hkproof list` and `hkproof prove`: the registry of the paper's theorems."""
from __future__ import annotations

import argparse

from hkproof.commands import Result, add_command
from hkproof.orchestration.registry import select
from hkproof.orchestration.runner import add_run_options, prove_claims


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "list", "list the theorems of the paper that hkproof certifies", run_list)
    p.add_argument("--group", action="append", default=[], help="only this theorem group (repeatable)")
    p = add_command(sub, "prove", "prove theorems and print their certificates", run_prove)
    p.add_argument("ids", nargs="*", help="theorem ids (see `hkproof list`)")
    p.add_argument("--all", action="store_true", help="every theorem, slow ones included")
    p.add_argument("--group", action="append", default=[], help="every theorem of this group (repeatable)")
    p.add_argument("--no-slow", action="store_true", help="with --all or --group: skip theorems marked slow")
    p.add_argument("--jsonl", action="store_true",
                   help="print each certificate as one JSON line as it completes, then a summary line")
    add_run_options(p)


def run_list(args: argparse.Namespace) -> Result:
    claims = select(groups=args.group)
    payload = [{"id": c.id, "group": c.group, "title": c.title, "paper_ref": c.paper_ref, "slow": c.slow,
                "expected": c.expected.label, "claimed": sorted(c.claimed)} for c in claims]
    width = max((len(c.id) for c in claims), default=0)
    text = "\n".join(f"{c.id:<{width}}  [{c.group}]{' (slow)' if c.slow else ''}"
                     f"{' (open: ' + c.expected.label + ')' if c.is_open else ''}  {c.title}" for c in claims)
    return Result(payload, text)


def run_prove(args: argparse.Namespace) -> Result:
    if not (args.ids or args.all or args.group):
        args.all = True
    claims = select(ids=args.ids, groups=args.group, include_slow=not args.no_slow)
    payload, closing, code = prove_claims(claims, args)  # certificates are printed as they complete
    return Result(payload, closing, code)
