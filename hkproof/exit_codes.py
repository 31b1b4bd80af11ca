"""The exit codes of every hkproof command and script, defined once, and the code that each kind of error ends with.

>>> int(ExitCode.VERIFIED), int(ExitCode.REFUTED), int(ExitCode.BAD_INPUT), int(ExitCode.LIMIT)
(0, 1, 2, 4)
>>> from hkproof.errors import BudgetExhausted, ParseError
>>> [int(exit_code_for(e)) for e in (ParseError("x"), BudgetExhausted("t"), MemoryError(), ZeroDivisionError())]
[2, 4, 4, 3]
"""
from __future__ import annotations

from enum import IntEnum

from hkproof.errors import HKProofError, ResourceLimitError

__all__ = ["ExitCode", "exit_code_for"]


class ExitCode(IntEnum):
    """0 verified (or success), 1 refuted, 2 bad input, 3 internal error (a bug), 4 a resource limit or an exhausted
    budget (a partial answer, not bad input), 130 interrupted (the shell's code for SIGINT)."""

    VERIFIED = 0
    REFUTED = 1
    BAD_INPUT = 2
    INTERNAL = 3
    LIMIT = 4
    INTERRUPTED = 130


def exit_code_for(error: BaseException) -> ExitCode:
    """How a command that stopped with `error` ends: a limit or exhausted memory 4, other hkproof errors (bad input)
    2, an interrupt 130, anything else (a bug) 3."""
    if isinstance(error, (ResourceLimitError, MemoryError)):
        return ExitCode.LIMIT
    if isinstance(error, HKProofError):
        return ExitCode.BAD_INPUT
    if isinstance(error, KeyboardInterrupt):
        return ExitCode.INTERRUPTED
    return ExitCode.INTERNAL
