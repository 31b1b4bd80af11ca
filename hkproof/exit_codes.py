"""The exit codes of every hkproof command and script, defined once.

>>> int(ExitCode.VERIFIED), int(ExitCode.REFUTED), int(ExitCode.BAD_INPUT), int(ExitCode.LIMIT)
(0, 1, 2, 4)
"""
from __future__ import annotations

from enum import IntEnum

__all__ = ["ExitCode"]


class ExitCode(IntEnum):
    """0 verified (or success), 1 refuted, 2 bad input, 3 internal error (a bug), 4 a resource limit or an exhausted
    budget (a partial answer, not bad input), 130 interrupted (the shell's code for SIGINT)."""

    VERIFIED = 0
    REFUTED = 1
    BAD_INPUT = 2
    INTERNAL = 3
    LIMIT = 4
    INTERRUPTED = 130
