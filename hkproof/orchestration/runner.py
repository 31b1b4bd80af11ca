"""Run claims for `hkproof prove`, `hkproof report` and proofs/*.py: on an executor, certificates printed as they
complete (text or JSON Lines) or as one JSON array at the end, Ctrl-C ending cleanly with the partial results."""
from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import threading
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Callable, Iterator, Sequence

from hkproof.errors import HKProofError
from hkproof.orchestration.execution import EXECUTORS, make_executor, run_graph
from hkproof.orchestration.graph import in_dependency_order
from hkproof.orchestration.registry import REGISTRY, Claim, cached, select
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

INTERRUPTED = 130  # the shell's code for a process ended by SIGINT


def positive_int(text: str) -> int:
    """An argparse type: a whole number >= 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"{value} is not a positive number of jobs")
    return value


def add_run_options(parser: argparse.ArgumentParser) -> None:
    """--jobs, --executor, --scheduler: where the claims run (the certificates do not depend on it)."""
    parser.add_argument("--jobs", type=positive_int, default=os.cpu_count() or 1, metavar="N",
                        help="prove up to N independent claims at once (default: the machine's cores; 1: a plain "
                             "loop in this process)")
    parser.add_argument("--executor", choices=EXECUTORS, default="process",
                        help="process: a pool of local processes; dask: Dask distributed (pip install "
                             "'hkproof[dask]'), a LocalCluster of N workers unless --scheduler is given")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help="with --executor dask: the address of a running Dask scheduler, e.g. tcp://host:8786")


@dataclass
class Run:
    """The claims asked for and the certificates that completed (all of them unless the run was interrupted)."""

    claims: list[Claim]
    certs: dict[str, Certificate] = field(default_factory=dict)
    interrupted: bool = False

    @property
    def finished(self) -> list[tuple[Claim, Certificate]]:
        return [(c, self.certs[c.id]) for c in self.claims if c.id in self.certs]

    @property
    def exit_code(self) -> int:
        if self.interrupted:
            return INTERRUPTED
        return 0 if all(c.succeeded(cert) for c, cert in self.finished) else 1

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
            text += f"INTERRUPTED (Ctrl-C) after {len(finished)} of {len(self.claims)} claims: "
        text += f"{verified} of {theorems} theorems verified"
        if theorems < len(finished):
            text += f"; {open_ok} of {len(finished) - theorems} open claims at their expected status (evidence only)"
        text += f"; {seconds:.2f} s"
        return text + ("" if not failed else "; FAILED: " + ", ".join(failed))

    def summary_record(self) -> dict:
        """The summary as the last object of a JSON Lines stream."""
        return {"summary": self.summary().strip(), "interrupted": self.interrupted, "claims": len(self.claims),
                "finished": len(self.certs), "exit_code": self.exit_code,
                "failed": [c.id for c, cert in self.finished if not c.succeeded(cert)]}


def certificate_payload(cert: Certificate) -> dict:
    """A certificate as JSON, with what its claim promises."""
    return {**cert.to_dict(), "expected": REGISTRY[cert.claim_id].expected.label}


@contextmanager
def _sigint_ignored() -> Iterator[None]:
    """A second Ctrl-C while the workers are being stopped is ignored (no traceback from the cleanup)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


@contextmanager
def _sigint_deferred() -> Iterator[None]:
    """Ctrl-C inside the block takes effect at its end (a line of output is never cut in half)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[int] = []
    previous = signal.signal(signal.SIGINT, lambda signum, frame: caught.append(signum))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:
        raise KeyboardInterrupt


def execute(claims: Sequence[Claim], args: argparse.Namespace,
            on_done: Callable[[Certificate], None] = lambda cert: None) -> Run:
    """Prove `claims` (and what they cite) with the executor of `args`; Ctrl-C returns the partial run."""
    run = Run(list(claims))
    ids = [c.id for c in run.claims]
    tasks = sum(cached(cid) is None for cid in in_dependency_order(ids, REGISTRY))

    def done(cert: Certificate) -> None:
        with _sigint_deferred():  # a certificate is recorded and printed whole, or not at all
            run.certs[cert.claim_id] = cert
            on_done(cert)

    executor = None
    try:
        executor = make_executor(args.executor, args.jobs, args.scheduler, tasks)
        run_graph(ids, executor, done)
    except KeyboardInterrupt:
        run.interrupted = True
    finally:
        if executor is not None:
            with _sigint_ignored():
                executor.close(interrupted=run.interrupted)
    return run


def streaming(args: argparse.Namespace) -> Callable[[Certificate], None]:
    """What to print as each certificate completes: its text, a JSON line, or nothing (--json prints at the end)."""
    if getattr(args, "jsonl", False):
        return lambda cert: print(json.dumps(certificate_payload(cert)), flush=True)
    if args.json:
        return lambda cert: None
    return lambda cert: print(cert.render(), flush=True)


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
        payload, closing, code = prove_claims(select(groups=groups, include_slow=not args.no_slow), args)
    except HKProofError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps(payload, indent=2) if args.json else closing)
    return code
