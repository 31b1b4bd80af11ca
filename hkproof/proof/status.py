"""The status ladder of a claim: refuted < unknown < evidence(float) < evidence(exact) < verified(specialized) < verified."""
from __future__ import annotations

from enum import IntEnum
from typing import Mapping

from hkproof.exit_codes import ExitCode

__all__ = ["exit_code", "specialized_label", "Status"]


class Status(IntEnum):
    """How far a claim stands; a certificate's status is the lowest of its steps."""

    REFUTED = 0
    UNKNOWN = 1
    EVIDENCE_FLOAT = 2
    EVIDENCE_EXACT = 3
    VERIFIED_SPECIALIZED = 4
    VERIFIED = 5

    @property
    def label(self) -> str:
        return {
            Status.REFUTED: "refuted",
            Status.UNKNOWN: "unknown",
            Status.EVIDENCE_FLOAT: "evidence(float)",
            Status.EVIDENCE_EXACT: "evidence(exact)",
            Status.VERIFIED_SPECIALIZED: "verified(specialized)",
            Status.VERIFIED: "verified",
        }[self]

    @property
    def is_verified(self) -> bool:
        return self is Status.VERIFIED


def specialized_label(status: Status, fixed: Mapping[str, object]) -> str:
    """The label of a status, as verified(specialized: a=1, ...) when a verified result holds at fixed values only.

    >>> specialized_label(Status.VERIFIED, {"a": 1}), specialized_label(Status.VERIFIED, {})
    ('verified(specialized: a=1)', 'verified')
    """
    if fixed and status >= Status.VERIFIED_SPECIALIZED:
        return f"verified(specialized: {', '.join(f'{k}={v}' for k, v in fixed.items())})"
    return status.label


def exit_code(status: Status) -> ExitCode:
    """How a command that states one status ends (the one place): 0 verified, verified(specialized) or evidence (an
    answer, labelled as such), 1 refuted, 4 unknown (the method or its budget could not decide).

    >>> [int(exit_code(s)) for s in (Status.VERIFIED, Status.VERIFIED_SPECIALIZED, Status.REFUTED, Status.UNKNOWN)]
    [0, 0, 1, 4]
    """
    if status is Status.REFUTED:
        return ExitCode.REFUTED
    return ExitCode.LIMIT if status is Status.UNKNOWN else ExitCode.VERIFIED
