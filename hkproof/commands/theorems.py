"""`hkproof list` and `hkproof prove`: the registry of the paper's theorems; and `run_script`, the body of proofs/*.py."""
from __future__ import annotations

import argparse
import sys
from dataclasses import replace
from typing import Callable, Sequence

from hkproof.algebra.printing import to_json
from hkproof.commands import Result, add_budget_option, add_command, add_run_options, run_options
from hkproof.commands._certificates import (add_certificate_option, certificate_target, theorem_document,
                                            write_certificate)
from hkproof.errors import HKProofError
from hkproof.exit_codes import exit_code_for
from hkproof.orchestration.interrupts import interrupts_raised
from hkproof.orchestration.output import emit
from hkproof.orchestration.registry import Claim, select
from hkproof.orchestration.runner import certificate_payload, execute
from hkproof.proof.certificate import Certificate

__all__ = ["prove_claims", "register", "run_list", "run_prove", "run_script", "streaming"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "list", "list the theorems of the paper that hkproof certifies", run_list)
    p.add_argument("--group", action="append", default=[], help="only this theorem group (repeatable)")
    p = add_command(sub, "prove", "prove theorems and print their certificates", run_prove)
    add_budget_option(p, per_claim=True)
    p.add_argument("ids", nargs="*", help="theorem ids (see `hkproof list`)")
    p.add_argument("--all", action="store_true", help="every theorem, slow ones included")
    p.add_argument("--group", action="append", default=[], help="every theorem of this group (repeatable)")
    p.add_argument("--no-slow", action="store_true", help="with --all or --group: skip theorems marked slow")
    p.add_argument("--jsonl", action="store_true",
                   help="print each certificate as one JSON line as it completes, then a summary line")
    add_certificate_option(p)
    add_run_options(p)
    p.set_defaults(holds_interrupts=True)   # an interrupt takes effect only while claims are proven (cli.main)


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
    target = certificate_target(args)
    claims = select(ids=args.ids, groups=args.group, include_slow=not args.no_slow)
    done: list[Certificate] = []
    keep = done.append if target is not None else None     # certificates are printed as they complete
    payload, closing, code = prove_claims(claims, args, keep)
    if target is not None:                  # the document is built only for a file to write
        closing += write_certificate(target, theorem_document(done), payload)
    return Result(payload, closing, code)


def streaming(args: argparse.Namespace) -> Callable[[Certificate], None]:
    """What to print as each certificate completes: its text, a JSON line, or nothing (--json prints one document at
    the end)."""
    if getattr(args, "jsonl", False):
        return lambda cert: emit(to_json(certificate_payload(cert)))
    if args.json:
        return lambda cert: None
    return lambda cert: emit(cert.render())


def prove_claims(claims: Sequence[Claim], args: argparse.Namespace,
                 keep: Callable[[Certificate], None] | None = None) -> tuple[dict, str, int]:
    """Prove, streaming each certificate (and handing it to `keep`, which gets every exact value; a text run without
    `keep` brings back only the values a cited claim needs); with --json the JSON document (`Run.document`:
    the summary record and the certificates, one shape whether interrupted or not; else an empty payload, so that
    the formulas of a text run are never written out), the closing text (summary; with --jsonl a JSON line), and
    the exit code (0 all succeeded, 1 some did not, 4 a budget ran out, 130 interrupted)."""
    if args.json and getattr(args, "jsonl", False):
        raise HKProofError("--json (one JSON document at the end) and --jsonl (one JSON object per line) exclude each "
                           "other: choose one")
    show = streaming(args)

    def completed(cert: Certificate) -> None:
        show(cert)
        if keep is not None:
            keep(cert)
    formulas = bool(args.json or getattr(args, "jsonl", False) or keep is not None)   # a text run prints none
    run = execute(claims, replace(run_options(args), values=formulas), completed)
    if run.interrupted and args.json:
        print(run.summary().strip(), file=sys.stderr)
    closing = to_json(run.summary_record()) if getattr(args, "jsonl", False) else run.summary()
    return (run.document() if args.json else {}), closing, run.exit_code


def run_script(groups: Sequence[str], argv: Sequence[str] | None = None) -> int:
    """The body of proofs/*.py: prove `groups`; --json/--jsonl for machine output, --no-slow to skip slow claims,
    --jobs/--executor/--scheduler for where they run."""
    parser = argparse.ArgumentParser(description=f"Certify the theorems of group(s) {', '.join(groups)}.")
    output = parser.add_mutually_exclusive_group()
    output.add_argument("--json", action="store_true",
                        help="print one JSON document at the end: the summary and the certificates")
    output.add_argument("--jsonl", action="store_true", help="print each certificate as a JSON line as it completes")
    parser.add_argument("--no-slow", action="store_true", help="skip claims marked slow")
    add_run_options(parser)
    try:
        with interrupts_raised(hold=True):   # an interrupt takes effect only while claims are proven
            args = parser.parse_args(argv)
            payload, closing, code = prove_claims(select(groups=groups, include_slow=not args.no_slow), args)
            emit(to_json(payload, indent=2) if args.json else closing)
    except HKProofError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return exit_code_for(exc)
    except KeyboardInterrupt:   # no signal raises outside the run (they are held): a library gave up while starting
        from hkproof.cli import interrupt_without_signal
        limit = interrupt_without_signal()
        print(f"error: {limit}", file=sys.stderr)
        return exit_code_for(limit)
    return code
