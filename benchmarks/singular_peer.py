"""Singular as a peer in the benchmarks: run a script, and time Cramer's rule on the very matrix hkproof solves."""
from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path
from typing import Sequence

import flint


def singular_executable() -> str | None:
    """Singular on PATH (the Debian package), else the binary passagemath-singular ships (pip install -e '.[bench]')."""
    exe = shutil.which("Singular")
    if exe:
        return exe
    try:
        import sage_wheels
    except ImportError:
        return None
    found = [Path(folder, "bin", "Singular") for folder in sage_wheels.__path__]
    return next((str(p) for p in found if p.exists()), None)


def singular_stdout(script: str, seconds: int = 1800) -> str:
    """What the script prints (what it printed so far if it runs out of time; '' without Singular)."""
    exe = singular_executable()
    if not exe:
        return ""
    with tempfile.NamedTemporaryFile("w", suffix=".sing", delete=False) as fh:
        fh.write(script)
    try:
        return subprocess.run([exe, "-q", fh.name], capture_output=True, text=True, timeout=seconds).stdout
    except subprocess.TimeoutExpired as exc:
        return (exc.stdout or b"").decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")


def timed_seconds(script: str, seconds: int = 1800) -> float | None:
    """Run a script that prints its own rtimer milliseconds last; seconds, or None if it did not finish."""
    lines = singular_stdout(script, seconds).strip().splitlines()
    return int(lines[-1]) / 1000 if lines and lines[-1].strip().isdigit() else None


def cramer_seconds(names: Sequence[str], a: Sequence[Sequence[flint.fmpz_mpoly]], b: Sequence[flint.fmpz_mpoly],
                   columns: Sequence[int] | None = None, seconds: int = 1800) -> float | None:
    """Seconds Singular takes for det [a] and the Cramer numerators of [a | b] in `columns` (all by default),
    each with its gcd against the determinant: the same cancellation hkproof does."""
    n = len(a)
    entries = ", ".join(str(x) for row in a for x in row)
    rhs = ", ".join(str(x) for x in b)
    cols = ", ".join(str(j + 1) for j in (range(n) if columns is None else columns))
    replace = " ".join(f"Mj[{i + 1}, j] = B[{i + 1}, 1];" for i in range(n))
    script = (f"ring R = 0, ({', '.join(names)}), dp;\nmatrix M[{n}][{n}] = {entries};\n"
              f"matrix B[{n}][1] = {rhs};\nintvec cols = {cols};\n"
              "system(\"--ticks-per-sec\", 1000);\nint t = rtimer;\npoly d = det(M);\nint k; int j; matrix Mj;\n"
              f"for (k = 1; k <= size(cols); k++) {{ j = cols[k]; Mj = M; {replace} "
              "poly g = gcd(det(Mj), d); kill g; }\nprint(rtimer - t);\nquit;\n")
    return timed_seconds(script, seconds)


def membership_seconds(names: Sequence[str], generators: Sequence[flint.fmpz_mpoly], target: flint.fmpz_mpoly,
                       seconds: int = 600) -> tuple[float | None, float | None]:
    """Seconds Singular takes to decide target in <generators>: (lift: cofactors, std + reduce: normal form), each in
    its own run with its own time limit; None where it did not finish. Variables are renamed v1..vk (Singular's
    identifiers cannot hold every name hkproof uses)."""
    ring = flint.fmpz_mpoly_ctx.get(tuple(f"v{i + 1}" for i in range(len(names))), "degrevlex")
    old = generators[0].context()

    def text(p: flint.fmpz_mpoly) -> str:
        return str(p.compose(*ring.gens(), ctx=ring)) if p.context() is old else str(p)
    head = (f"ring R = 0, ({', '.join(map(str, ring.gens()))}), dp;\noption(redSB);\n"
            f"ideal I = {', '.join(text(g) for g in generators)};\npoly f = {text(target)};\n"
            "system(\"--ticks-per-sec\", 1000);\nint t = rtimer;\n")
    lift = timed_seconds(head + "matrix L = lift(I, f);\nprint(rtimer - t);\nquit;\n", seconds)
    normal = timed_seconds(head + "ideal G = std(I);\npoly r = reduce(f, G);\nif (r != 0) { print(\"not in I\"); }\n"
                           "print(rtimer - t);\nquit;\n", seconds)
    return lift, normal


def gcd_seconds(names: Sequence[str], a: flint.fmpz_mpoly, b: flint.fmpz_mpoly, seconds: int = 1800) -> float | None:
    """Seconds Singular's gcd takes on the same two polynomials (rtimer inside Singular, parsing excluded)."""
    script = (f"ring R = 0, ({', '.join(names)}), dp;\npoly a = {a};\npoly b = {b};\n"
              "system(\"--ticks-per-sec\", 1000);\nint t = rtimer;\npoly g = gcd(a, b);\n"
              "print(rtimer - t);\nquit;\n")
    return timed_seconds(script, seconds)
