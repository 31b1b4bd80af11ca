"""The status ladder of a claim: refuted < unknown < evidence(float) < evidence(exact) < verified(specialized) < verified."""
from __future__ import annotations

from enum import IntEnum


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
