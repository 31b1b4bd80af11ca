"""`hkproof list` and `hkproof prove`: the registry of the paper's theorems."""
from __future__ import annotations

import argparse

from hkproof.commands import Result, add_command
from hkproof.proof.registry import select
from hkproof.proof.status import Status


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
                "claimed": sorted(c.claimed)} for c in claims]
    width = max((len(c.id) for c in claims), default=0)
    text = "\n".join(f"{c.id:<{width}}  [{c.group}]{' (slow)' if c.slow else ''}  {c.title}" for c in claims)
    return Result(payload, text)


def run_prove(args: argparse.Namespace) -> Result:
    if not (args.ids or args.all or args.group):
        args.all = True
    claims = select(ids=args.ids, groups=args.group, include_slow=not args.no_slow)
    certs = []
    lines = []
    for c in claims:
        cert = c.prove()
        certs.append(cert)
        lines.append(cert.render())
    verified = sum(c.status is Status.VERIFIED for c in certs)
    total_time = sum(c.seconds for c in certs)
    lines.append(f"\n{verified} of {len(certs)} theorems verified in {total_time:.2f} s")
    ok = verified == len(certs)
    return Result([c.to_dict() for c in certs], "\n".join(lines), 0 if ok else 1)
