"""Run claims for `hkproof prove`, `hkproof report`, proofs/*.py and the Python API: on an executor, each certificate
handed to a callback as it completes (the front ends print it); an interrupt (Ctrl-C, SIGTERM, SIGHUP) stops the
workers and ends cleanly with the partial results."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Sequence

from hkproof.exit_codes import ExitCode
from hkproof.orchestration.execution import make_executor, run_graph
from hkproof.orchestration.graph import in_dependency_order
from hkproof.orchestration.interrupts import interrupt_label, interrupts_deferred, interrupts_ignored, interrupts_live
from hkproof.orchestration.registry import RAN_OUT, REGISTRY, Claim, cached
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

__all__ = ["Run", "RunOptions", "certificate_payload", "execute"]


@dataclass(frozen=True)
class RunOptions:
    """Where the claims run (the certificates do not depend on it): `jobs` at once, on the `executor` ("process":
    local worker processes, "dask": Dask distributed, a LocalCluster unless `scheduler` gives an address); with
    `values` False a certificate no claim of the run cites comes back without its exact values, whose formulas
    cannot then be read (for runs that print statuses only)."""

    jobs: int = 1
    executor: str = "process"
    scheduler: str | None = None
    seconds: float | None = None     # the budget of each claim's proof (None: no limit)
    values: bool = True              # every certificate's exact values come back (False: only those a claim cites)


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
        failed = [cert for c, cert in self.finished if not c.succeeded(cert)]
        if not failed:
            return ExitCode.VERIFIED
        if all(cert.status is not Status.REFUTED and RAN_OUT in cert.notes for cert in failed):
            return ExitCode.LIMIT      # nothing refuted: the per-claim budget stopped a proof (or one it cites)
        return ExitCode.REFUTED

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

    def document(self) -> dict:
        """The one JSON document of `--json`, of one shape whether the run ended or was interrupted (before its first
        claim finished or after some): the summary record, then the certificates that completed."""
        return {**self.summary_record(), "certificates": self.payload()}


def certificate_payload(cert: Certificate) -> dict:
    """A certificate as JSON, with what its claim promises."""
    return {**cert.to_dict(), "expected": REGISTRY[cert.claim_id].expected.label}


def execute(claims: Sequence[Claim], options: RunOptions = RunOptions(),
            on_done: Callable[[Certificate], None] = lambda cert: None) -> Run:
    """Prove `claims` (and what they cite) where `options` say, calling `on_done` with each certificate as it
    completes; an interrupt (Ctrl-C, SIGTERM, SIGHUP) stops the workers and returns the partial run."""
    run = Run(list(claims))
    ids = [c.id for c in run.claims]
    tasks = sum(cached(cid) is None for cid in in_dependency_order(ids, REGISTRY))

    def done(cert: Certificate) -> None:
        with interrupts_deferred():  # a certificate is recorded and printed whole, or not at all
            run.certs[cert.claim_id] = cert
            on_done(cert)

    executor = None
    try:
        with interrupts_live():     # a signal held before the run (while the command line was read) stops it here
            executor = make_executor(options.executor, options.jobs, options.scheduler, tasks, options.seconds)
            run_graph(ids, executor, done, options.values)
    except KeyboardInterrupt as exc:
        run.interrupted, run.interrupted_by = True, interrupt_label(exc)
    finally:
        if executor is not None:
            with interrupts_ignored():
                executor.close(interrupted=run.interrupted)
    return run
