"""Writing what a command prints: a line flushed at once, and a failed write turned into an hkproof error -- a full
disk or device is a resource limit (exit 4), any other failure an OutputError (exit 2); never a traceback."""
from __future__ import annotations

import errno
import sys
from typing import TextIO

from hkproof.errors import HKProofError, OutputError, ResourceLimitError

__all__ = ["emit", "output_error"]

_NO_SPACE = {errno.ENOSPC, errno.EDQUOT, errno.EFBIG}


def output_error(exc: OSError, where: str) -> HKProofError:
    """The error for a write to `where` that failed with `exc`."""
    reason = exc.strerror or str(exc)
    if exc.errno in _NO_SPACE:
        return ResourceLimitError(f"cannot write {where}: {reason} (free some space, or write to another device)",
                                  limit="the free space of the device written to",
                                  raise_with="free some space, or write to another device")
    return OutputError(f"cannot write {where}: {reason}")


def emit(text: str, stream: TextIO | None = None) -> None:
    """Print `text` and a newline to `stream` (standard output by default) and flush them, whole: a signal that
    interrupts a long write to a pipe makes Python's text layer drop the rest of the line, so the bytes go to the
    binary buffer in a loop until every one is written."""
    out = sys.stdout if stream is None else stream
    try:
        binary = getattr(out, "buffer", None)
        if binary is None:          # a text-only stream (io.StringIO)
            print(text, file=out, flush=True)
            return
        out.flush()
        data = memoryview((text + "\n").encode(out.encoding or "utf-8", errors="backslashreplace"))
        while data:
            data = data[binary.write(data):]
        binary.flush()
    except OSError as exc:
        raise output_error(exc, "the standard output" if out is sys.stdout else "the output") from None
