"""Progress bars on stderr through tqdm: shown at a terminal, silent otherwise or when switched off."""
from __future__ import annotations

import sys
from typing import Callable, TextIO

from tqdm import tqdm

__all__ = ["bar", "message_bar"]


def bar(total: int | None, unit: str, *, enabled: bool | None = None, stream: TextIO | None = None,
        desc: str = "") -> tqdm:
    """A tqdm bar of `total` units (None: a counter) on `stream` (stderr); enabled=None shows it only at a terminal.

    >>> import io
    >>> out = io.StringIO()
    >>> with bar(3, "points", enabled=True, stream=out) as b:
    ...     b.update(3)
    ...     _ = b.refresh()
    >>> "3/3" in out.getvalue()
    True
    """
    stream = stream or sys.stderr
    shown = stream.isatty() if enabled is None else enabled
    return tqdm(total=total, unit=unit, desc=desc, file=stream, disable=not shown, leave=False, dynamic_ncols=True,
                mininterval=0.2)


def message_bar(progress: tqdm) -> Callable[[str], None]:
    """A progress callback of a pipeline (one line per event) shown as the bar's description, counting the events."""
    def show(line: str) -> None:
        progress.set_description_str(line, refresh=False)
        progress.update()
    return show
