"""Subcommands of `hkproof`: each module has register(subparsers) and sets `run` to a function returning Result."""
from __future__ import annotations

import argparse
from dataclasses import dataclass
from typing import Any, Callable


@dataclass
class Result:
    """What a command produced: a JSON-able payload, the text for a person, and the exit status."""

    payload: Any
    text: str
    exit_code: int = 0


def add_command(sub: argparse._SubParsersAction, name: str, help: str,
                run: Callable[[argparse.Namespace], Result]) -> argparse.ArgumentParser:
    """A subparser with the common --json flag, dispatching to `run`."""
    p = sub.add_parser(name, help=help, description=help)
    p.add_argument("--json", action="store_true", help="print a JSON object instead of text")
    p.set_defaults(run=run)
    return p
