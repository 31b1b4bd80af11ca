"""`hkproof report`: run the registry and write docs/theorems.md (statement, method, status, time)."""
from __future__ import annotations

import argparse
import os
import stat
import tempfile
from dataclasses import replace
from pathlib import Path

from hkproof.commands import (Result, add_budget_option, add_command, add_progress_option, add_run_options,
                              progress_bar, run_options)
from hkproof.errors import OutputError
from hkproof.experiments.progress import message_bar
from hkproof.orchestration.output import output_error
from hkproof.orchestration.registry import select
from hkproof.orchestration.report import theorems_markdown
from hkproof.orchestration.runner import execute

__all__ = ["register", "run_report", "writable_target", "write_atomically"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "report", "prove every theorem and write the Markdown table of theorems", run_report)
    add_budget_option(p, per_claim=True)
    p.add_argument("--write", metavar="FILE", help="write the Markdown to FILE (default: print it)")
    p.add_argument("--no-slow", action="store_true", help="do not run claims marked slow")
    add_run_options(p)
    add_progress_option(p)
    p.set_defaults(holds_interrupts=True)   # an interrupt takes effect only while claims are proven (cli.main)


def writable_target(name: str) -> Path:
    """FILE of --write, checked before any proof runs: a regular file or a new name, in an existing directory where a
    new file can be created -- tried, not read off the permission bits (root passes every access check, yet /proc
    takes no new file)."""
    target = Path(name)
    check_replaceable(target)
    folder = target.parent
    if not folder.is_dir():
        raise OutputError(f"cannot write {name}: the directory {folder} does not exist")
    try:
        fd, probe = tempfile.mkstemp(dir=folder, prefix=f".{target.name}.", suffix=".tmp")
    except OSError as exc:
        raise OutputError(f"cannot write {name}: no file can be created in the directory {folder} "
                          f"({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(probe)
    return target


def check_replaceable(target: Path) -> None:
    """FILE may be replaced: it does not exist or is a regular file. A symbolic link, a device node, a FIFO or a
    directory is refused: the rename that writes FILE would put a regular file in its place (as root, /dev/null)."""
    try:
        mode = os.lstat(target).st_mode
    except FileNotFoundError:
        return
    except OSError as exc:
        raise OutputError(f"cannot write {target}: {exc.strerror or exc}") from None
    if stat.S_ISREG(mode):
        return
    kind = ("a symbolic link (give the file it points to, or a new name)" if stat.S_ISLNK(mode) else
            "a directory" if stat.S_ISDIR(mode) else "not a regular file (a device, a FIFO or a socket)")
    raise OutputError(f"cannot write {target}: it is {kind}; --write replaces a regular file or creates a new one")


def write_atomically(target: Path, text: str) -> None:
    """Write through a temporary file in the same directory and a rename: FILE is never left half written, and the
    temporary file is removed on every failure (a full disk, an interrupt; only SIGKILL can leave it behind)."""
    check_replaceable(target)       # again: the proofs ran in between
    try:
        fd, temporary = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    except OSError as exc:
        raise output_error(exc, str(target)) from None
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as out:
            out.write(text)
            out.flush()
            os.fsync(out.fileno())
        os.chmod(temporary, target.stat().st_mode & 0o777 if target.exists() else 0o666 & ~_umask())
        os.replace(temporary, target)
    except BaseException as exc:
        os.unlink(temporary)
        if isinstance(exc, OSError):
            raise output_error(exc, str(target)) from None
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def run_report(args: argparse.Namespace) -> Result:
    target = writable_target(args.write) if args.write else None
    claims = select()
    chosen = [c for c in claims if not (c.slow and args.no_slow)]
    with progress_bar(args, "report", "claims", total=len(chosen)) as shown:
        show = message_bar(shown)
        run = execute(chosen, replace(run_options(args), values=False),    # the table reads no formulas
                      lambda cert: show(f"{cert.claim_id}: {cert.status.label}"))
    # one shape whether interrupted or not: the summary record of the run, the file written and each status
    payload = {**run.summary_record(), "written": None,
               "statuses": {cid: cert.status.label for cid, cert in run.certs.items()}}
    if run.interrupted:
        return Result(payload, f"{run.summary().strip()}; nothing written", run.exit_code)
    text = theorems_markdown(claims, run.certs)
    if target is not None:
        write_atomically(target, text)
    payload["written"] = args.write
    return Result(payload, f"wrote {args.write}" if args.write else text, run.exit_code)
