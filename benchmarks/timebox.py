"""Run a peer or a slow stage in a child process and stop it at a time limit (the benchmark goes on either way)."""
from __future__ import annotations

import multiprocessing as mp
from typing import Any, Callable


def in_child(target: Callable[..., None], args: tuple, seconds: float) -> Any | None:
    """target(*args, queue) in its own process; what it put on the queue, or None if it ran past `seconds`, failed
    or put nothing."""
    queue: mp.Queue = mp.Queue()
    proc = mp.Process(target=target, args=(*args, queue))
    proc.start()
    proc.join(seconds)
    if proc.is_alive():
        proc.terminate()
        proc.join()
        return None
    return queue.get(timeout=5) if proc.exitcode == 0 and not queue.empty() else None
