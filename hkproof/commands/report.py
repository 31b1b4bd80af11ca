"""`hkproof report`: run the registry and write docs/theorems.md (statement, method, status, time)."""
from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

from hkproof.commands import Result, add_command, add_run_options, run_options
from hkproof.errors import HKProofError
from hkproof.orchestration.registry import select
from hkproof.orchestration.report import theorems_markdown
from hkproof.orchestration.runner import execute

__all__ = ["register", "run_report", "writable_target", "write_atomically"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "report", "prove every theorem and write the Markdown table of theorems", run_report)
    p.add_argument("--write", metavar="FILE", help="write the Markdown to FILE (default: print it)")
    p.add_argument("--no-slow", action="store_true", help="do not run claims marked slow")
    add_run_options(p)


def writable_target(name: str) -> Path:
    """FILE of --write, checked before any proof runs: its directory exists and is writable, it is no directory."""
    target = Path(name)
    folder = target.parent
    if not folder.is_dir():
        raise HKProofError(f"cannot write {name}: the directory {folder} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise HKProofError(f"cannot write {name}: the directory {folder} is not writable")
    if target.is_dir():
        raise HKProofError(f"cannot write {name}: it is a directory")
    return target


def write_atomically(target: Path, text: str) -> None:
    """Write through a temporary file in the same directory and a rename: FILE is never left half written."""
    fd, temporary = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w") as out:
            out.write(text)
        os.chmod(temporary, target.stat().st_mode & 0o777 if target.exists() else 0o666 & ~_umask())
        os.replace(temporary, target)
    except BaseException:
        os.unlink(temporary)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def run_report(args: argparse.Namespace) -> Result:
    target = writable_target(args.write) if args.write else None
    claims = select()
    run = execute([c for c in claims if not (c.slow and args.no_slow)], run_options(args))
    statuses = {cid: cert.status.label for cid, cert in run.certs.items()}
    if run.interrupted:
        return Result({"written": None, "interrupted": True, "statuses": statuses},
                      f"{run.summary().strip()}; nothing written", run.exit_code)
    text = theorems_markdown(claims, run.certs)
    if target is not None:
        write_atomically(target, text)
    payload = {"written": args.write, "statuses": statuses}
    return Result(payload, f"wrote {args.write}" if args.write else text, run.exit_code)
