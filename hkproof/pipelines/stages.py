"""Stage timing and progress messages for a user-facing pipeline (the front end decides where messages go)."""
from __future__ import annotations

import time
from typing import Callable

__all__ = ["Progress", "Stages"]

Progress = Callable[[str], None]


class Stages:
    """Seconds spent per named stage, and progress messages through an optional callback.

    >>> lines = []
    >>> s = Stages("discover", lines.append)
    >>> s.start("screening", "screening"); s.stop()
    >>> list(s.seconds), lines[0].startswith("discover: screening")
    (['screening'], True)
    """

    def __init__(self, name: str, progress: Progress | None = None):
        self.name, self.progress = name, progress
        self.started = time.perf_counter()
        self.seconds: dict[str, float] = {}
        self._stage, self._stage_start = "", 0.0

    def start(self, stage: str, message: str = "") -> None:
        """End the running stage (its time is added up) and start `stage`, saying `message`."""
        self.stop()
        self._stage, self._stage_start = stage, time.perf_counter()
        self.say(message or stage)

    def stop(self) -> None:
        if self._stage:
            self.seconds[self._stage] = self.seconds.get(self._stage, 0.0) + time.perf_counter() - self._stage_start
            self._stage = ""

    def say(self, message: str) -> None:
        if self.progress is not None:
            self.progress(f"{self.name}: {message} ({time.perf_counter() - self.started:.1f} s)")
