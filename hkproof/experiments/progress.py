"""A one-line progress bar on stderr for long scans (no dependency)."""
from __future__ import annotations

import sys
import time
from typing import TextIO

__all__ = ["Progress"]


class Progress:
    """`[#####.....] 12/40 points, 3.1 s` rewritten in place; silent when disabled."""

    def __init__(self, total: int, label: str = "points", enabled: bool | None = None, stream: TextIO | None = None,
                 width: int = 30):
        self.stream = stream or sys.stderr
        self.total = total
        self.label = label
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.width = width
        self.done = 0
        self.start = time.perf_counter()

    def update(self, n: int = 1) -> None:
        self.done += n
        if not self.enabled:
            return
        filled = int(self.width * self.done / max(self.total, 1))
        self.stream.write(f"\r[{'#' * filled}{'.' * (self.width - filled)}] {self.done}/{self.total} {self.label}, "
                          f"{time.perf_counter() - self.start:.1f} s")
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()
