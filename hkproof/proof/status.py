"""The status ladder of a claim: refuted < unknown < evidence(float) < evidence(exact) < verified(specialized) < verified."""
from __future__ import annotations

from enum import IntEnum
from typing import Mapping

__all__ = ["specialized_label", "Status"]


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
