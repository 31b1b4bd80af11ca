"""Run claims for `hkproof prove`, `hkproof report` and proofs/*.py: on an executor, certificates printed as they
complete (text or JSON Lines) or as one JSON array at the end, Ctrl-C ending cleanly with the partial results."""
from __future__ import annotations

import argparse
import json
import os
import re
import sys
from dataclasses import dataclass, field
from typing import Callable, Sequence

from hkproof.algebra.formula import read_integer
from hkproof.errors import HKProofError
from hkproof.exit_codes import ExitCode, exit_code_for
from hkproof.orchestration.execution import EXECUTORS, make_executor, run_graph
from hkproof.orchestration.graph import in_dependency_order
from hkproof.orchestration.interrupts import (interrupt_label, interrupts_deferred, interrupts_ignored,
                                              interrupts_raised)
from hkproof.orchestration.output import emit
from hkproof.orchestration.registry import REGISTRY, Claim, cached, select
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status


def positive_int(text: str) -> int:
    """An argparse type: a whole number >= 1, in ASCII digits."""
    try:
        value = read_integer(text)
    except HKProofError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is not a positive number of jobs")
    return value


_ADDRESS = re.compile(r"(?:(?:tcp|tls|ucx|ws|wss)://)?(?:\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+)(?::(?P<port>[0-9]{1,5}))?")


def scheduler_address(text: str) -> str:
    """An argparse type: the address of a Dask scheduler, [PROTOCOL://]HOST[:PORT] (e.g. tcp://10.0.0.5:8786)."""
    address = text.strip()
    m = _ADDRESS.fullmatch(address)
    if not address or m is None or (m.group("port") is not None and not 0 < int(m.group("port")) < 65536):
        raise argparse.ArgumentTypeError(f"{text!r} is not a scheduler address: give [PROTOCOL://]HOST[:PORT], e.g. "
                                         "tcp://10.0.0.5:8786 (PROTOCOL tcp, tls, ucx, ws or wss; PORT 1 to 65535)")
    return address


def add_run_options(parser: argparse.ArgumentParser) -> None:
    """--jobs, --executor, --scheduler: where the claims run (the certificates do not depend on it)."""
    parser.add_argument("--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="N",
                        help="prove up to N independent claims at once (default: the machine's cores; 1: a plain "
                             "loop in this process)")
    parser.add_argument("--executor", choices=EXECUTORS, default="process",
                        help="process: a pool of local processes; dask: Dask distributed (pip install "
                             "'hkproof[dask]'), a LocalCluster of N workers unless --scheduler is given")
    parser.add_argument("--scheduler", type=scheduler_address, metavar="ADDRESS",
                        help="with --executor dask: the address of a running Dask scheduler, e.g. tcp://host:8786")


@dataclass
class Run:
    """The claims asked for and the certificates that completed (all of them unless the run was interrupted)."""

    claims: list[Claim]
    certs: dict[str, Certificate] = field(default_factory=dict)
    interrupted: bool = False
    interrupted_by: str = ""    # "Ctrl-C", "SIGTERM" or "SIGHUP"

    @property
    def finished(self) -> list[tuple[Claim, Certificate]]:
        return [(c, self.certs[c.id]) for c in self.claims if c.id in self.certs]

    @property
    def exit_code(self) -> ExitCode:
        if self.interrupted:
            return ExitCode.INTERRUPTED
        return ExitCode.VERIFIED if all(c.succeeded(cert) for c, cert in self.finished) else ExitCode.REFUTED

    def payload(self) -> list[dict]:
        return [certificate_payload(cert) for _, cert in self.finished]

    def summary(self) -> str:
        """One line: how many theorems are verified, how many open claims reached their evidence, what failed."""
        finished = self.finished
        verified = sum(cert.status is Status.VERIFIED for c, cert in finished if not c.is_open)
        theorems = sum(not c.is_open for c, _ in finished)
        open_ok = sum(c.succeeded(cert) for c, cert in finished if c.is_open)
        failed = [f"{c.id} ({cert.status.label})" for c, cert in finished if not c.succeeded(cert)]
        seconds = sum(cert.seconds for _, cert in finished)
        text = "\n"
        if self.interrupted:
            text += f"INTERRUPTED ({self.interrupted_by}) after {len(finished)} of {len(self.claims)} claims: "
        text += f"{verified} of {theorems} theorems verified"
        if theorems < len(finished):
            text += f"; {open_ok} of {len(finished) - theorems} open claims at their expected status (evidence only)"
        text += f"; {seconds:.2f} s"
        return text + ("" if not failed else "; FAILED: " + ", ".join(failed))

    def summary_record(self) -> dict:
        """The summary as the last object of a JSON Lines stream."""
        return {"summary": self.summary().strip(), "interrupted": self.interrupted,
                "signal": self.interrupted_by or None, "claims": len(self.claims),
                "finished": len(self.certs), "exit_code": int(self.exit_code),
                "failed": [c.id for c, cert in self.finished if not c.succeeded(cert)]}


def certificate_payload(cert: Certificate) -> dict:
    """A certificate as JSON, with what its claim promises."""
    return {**cert.to_dict(), "expected": REGISTRY[cert.claim_id].expected.label}


def execute(claims: Sequence[Claim], args: argparse.Namespace,
            on_done: Callable[[Certificate], None] = lambda cert: None) -> Run:
    """Prove `claims` (and what they cite) with the executor of `args`; an interrupt (Ctrl-C, SIGTERM, SIGHUP)
    stops the workers and returns the partial run."""
    run = Run(list(claims))
    ids = [c.id for c in run.claims]
    tasks = sum(cached(cid) is None for cid in in_dependency_order(ids, REGISTRY))

    def done(cert: Certificate) -> None:
        with interrupts_deferred():  # a certificate is recorded and printed whole, or not at all
            run.certs[cert.claim_id] = cert
            on_done(cert)

    executor = None
    try:
        executor = make_executor(args.executor, args.jobs, args.scheduler, tasks)
        run_graph(ids, executor, done)
    except KeyboardInterrupt as exc:
        run.interrupted, run.interrupted_by = True, interrupt_label(exc)
    finally:
        if executor is not None:
            with interrupts_ignored():
                executor.close(interrupted=run.interrupted)
    return run


def streaming(args: argparse.Namespace) -> Callable[[Certificate], None]:
    """What to print as each certificate completes: its text, a JSON line, or nothing (--json prints at the end)."""
    if getattr(args, "jsonl", False):
        return lambda cert: emit(json.dumps(certificate_payload(cert)))
    if args.json:
        return lambda cert: None
    return lambda cert: emit(cert.render())


def prove_claims(claims: Sequence[Claim], args: argparse.Namespace) -> tuple[list[dict], str, int]:
    """Prove, streaming each certificate; the JSON payload, the closing text (summary; with --jsonl a JSON line),
    and the exit code (0 all succeeded, 1 some did not, 130 interrupted)."""
    if args.json and getattr(args, "jsonl", False):
        raise HKProofError("--json (one JSON array at the end) and --jsonl (one JSON object per line) exclude each "
                           "other: choose one")
    run = execute(claims, args, streaming(args))
    if run.interrupted and args.json:
        print(run.summary().strip(), file=sys.stderr)
    closing = json.dumps(run.summary_record()) if getattr(args, "jsonl", False) else run.summary()
    return run.payload(), closing, run.exit_code


def run_script(groups: Sequence[str], argv: Sequence[str] | None = None) -> int:
    """The body of proofs/*.py: prove `groups`; --json/--jsonl for machine output, --no-slow to skip slow claims,
    --jobs/--executor/--scheduler for where they run."""
    parser = argparse.ArgumentParser(description=f"Certify the theorems of group(s) {', '.join(groups)}.")
    output = parser.add_mutually_exclusive_group()
    output.add_argument("--json", action="store_true", help="print the certificates as one JSON array at the end")
    output.add_argument("--jsonl", action="store_true", help="print each certificate as a JSON line as it completes")
    parser.add_argument("--no-slow", action="store_true", help="skip claims marked slow")
    add_run_options(parser)
    args = parser.parse_args(argv)
    try:
        with interrupts_raised():
            payload, closing, code = prove_claims(select(groups=groups, include_slow=not args.no_slow), args)
            emit(json.dumps(payload, indent=2) if args.json else closing)
    except HKProofError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return exit_code_for(exc)
    except KeyboardInterrupt as exc:    # before any claim ran
        print(f"interrupted ({interrupt_label(exc)})", file=sys.stderr)
        return ExitCode.INTERRUPTED
    return code
