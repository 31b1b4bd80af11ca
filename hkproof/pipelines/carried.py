"""Integrals found for one field carried to another (a lift from a slice, a pull-back from a chart), each certificate
extended once by the step that licenses the carrying."""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable

from hkproof.algebra.fraction import Frac
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

if TYPE_CHECKING:
    from hkproof.pipelines.discover.report import DiscoveryReport

__all__ = ["carry_integrals"]


def carry_integrals(report: "DiscoveryReport", carry: Callable[[Frac], Frac], record: Callable[[Certificate], None],
                    keep: str, note: str) -> None:
    """Replace each integral's formula h by carry(h) (h kept in the integral's field `keep`: "searched" for the
    slice, "in_chart" for the chart), add `note` to its method, and record the licensing step in its certificate
    once (a certificate shared by several integrals gets it once); the integral's status is at most the
    certificate's after that step."""
    done: dict[int, Status] = {}
    for found in report.integrals:
        if found.frac is None:
            continue
        setattr(found, keep, found.frac)
        found.frac = carry(found.frac)
        found.method += note
        cert = found.certificate
        if cert is None:
            continue
        if id(cert) not in done:
            record(cert)
            done[id(cert)] = cert.status
        found.status = min(found.status, done[id(cert)])
