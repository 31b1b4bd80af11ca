"""`hkproof list` and `hkproof prove`: the registry of the paper's theorems."""
from __future__ import annotations

import argparse

from hkproof.commands import Result, add_command
from hkproof.proof.registry import select
from hkproof.proof.runner import summary


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "list", "list the theorems of the paper that hkproof certifies", run_list)
    p.add_argument("--group", action="append", default=[], help="only this theorem group (repeatable)")
    p = add_command(sub, "prove", "prove theorems and print their certificates", run_prove)
    p.add_argument("ids", nargs="*", help="theorem ids (see `hkproof list`)")
    p.add_argument("--all", action="store_true", help="every theorem, slow ones included")
    p.add_argument("--group", action="append", default=[], help="every theorem of this group (repeatable)")
    p.add_argument("--no-slow", action="store_true", help="with --all or --group: skip theorems marked slow")


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
    certs = [c.prove() for c in claims]
    text = "\n".join(cert.render() for cert in certs) + summary(claims, certs)
    ok = all(c.succeeded(cert) for c, cert in zip(claims, certs, strict=True))
    return Result([{**cert.to_dict(), "expected": c.expected.label} for c, cert in zip(claims, certs, strict=True)], text,
                  0 if ok else 1)
