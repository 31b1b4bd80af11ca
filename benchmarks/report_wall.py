"""Wall time of `hkproof prove --all` (and --no-slow) with --jobs 1 and --jobs 2, side by side in one run; per-claim
times; peak memory of the heaviest claims. Writes a section of docs/performance.md.

    python benchmarks/report_wall.py            # --all --no-slow only (about a minute)
    python benchmarks/report_wall.py --full     # also --all (several minutes per run)

Each run is a fresh process (the command a user types: the `hkproof` console script); its peak RSS is that of the
process and its worker processes (os.wait4, the children's rusage). The peak of a claim is measured by proving it
alone (`hkproof prove ID --jobs 1`, the claims it cites included).
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "performance.md"
BEGIN, END = "<!-- report-wall:begin -->", "<!-- report-wall:end -->"
CONSOLE_SCRIPT = "import sys; from hkproof.cli import main; sys.exit(main())"


def hkproof(*argv: str) -> tuple[float, float, float, list[dict]]:
    """Run `hkproof ARGV --jsonl` in a fresh process: wall seconds, CPU seconds and peak RSS in MB (the process and
    its workers), the JSON lines."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    start = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-c", CONSOLE_SCRIPT, *argv, "--jsonl"], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, text=True)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - start
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode not in (0, 1):
        raise SystemExit(f"hkproof {' '.join(argv)} exited {proc.returncode}")
    cpu = usage.ru_utime + usage.ru_stime
    return wall, cpu, usage.ru_maxrss / 1024, [json.loads(line) for line in out.splitlines()]


def measure(selection: list[str], jobs: tuple[int, ...]) -> dict[int, tuple[float, float, float, list[dict]]]:
    """`hkproof prove SELECTION --jobs J` for each J, one after the other in this run."""
    return {j: hkproof("prove", *selection, "--jobs", str(j)) for j in jobs}


def section(results: dict[str, dict[int, tuple[float, float, float, list[dict]]]], peaks: list[tuple[str, float, float]],
            note: str) -> list[str]:
    lines = [BEGIN, "", "## Wall time of the whole report (`--jobs`)", "",
             f"Measured by `python benchmarks/report_wall.py{' --full' if 'prove --all' in results else ''}` on "
             f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
             f"{time.strftime('%Y-%m-%d %H:%M')} UTC, every run a fresh process, one after the other in one run. "
             f"{note}", "",
             "| command | wall --jobs 1 | wall --jobs 2 | speed-up | CPU (jobs 1 / jobs 2, with workers) | claims | "
             "peak RSS (jobs 1 / jobs 2) |", "|---|---|---|---|---|---|---|"]
    for name, by_jobs in results.items():
        (w1, c1, m1, r1), (w2, c2, m2, _) = by_jobs[1], by_jobs[2]
        lines.append(f"| `hkproof {name}` | {w1:.1f} s | {w2:.1f} s | {w1 / w2:.2f}x | {c1:.1f} s / {c2:.1f} s | "
                     f"{len(r1) - 1} | {m1:.0f} MB / {m2:.0f} MB |")
    for name, by_jobs in results.items():
        certs = sorted(by_jobs[1][3][:-1], key=lambda r: -r["seconds"])
        in_pool = {r["id"]: r["seconds"] for r in by_jobs[2][3][:-1]}
        total = sum(r["seconds"] for r in certs)
        lines += ["", f"Per-claim time of `hkproof {name}` (each certificate's prover time; the ten longest of "
                  f"{len(certs)}, {total:.1f} s in all with --jobs 1):", "",
                  "| claim | status | --jobs 1 | --jobs 2 (in a worker) |", "|---|---|---|---|"]
        lines += [f"| `{r['id']}` | {r['status']} | {r['seconds']:.2f} s | {in_pool.get(r['id'], 0):.2f} s |"
                  for r in certs[:10]]
    if peaks:
        lines += ["", "Peak memory of the heaviest claims, each proven alone (`hkproof prove ID --jobs 1`, the claims "
                  "it cites included; RSS of the process):", "", "| claim | wall | peak RSS |", "|---|---|---|"]
        lines += [f"| `{cid}` | {wall:.1f} s | {rss:.0f} MB |" for cid, wall, rss in peaks]
    return lines + ["", END]


def write_section(lines: list[str]) -> None:
    text = DOC.read_text() if DOC.exists() else "# Performance\n"
    block = "\n".join(lines)
    if BEGIN in text:
        text = re.sub(re.escape(BEGIN) + ".*?" + re.escape(END), lambda m: block, text, flags=re.S)
    else:
        text += "\n" + block + "\n"
    DOC.write_text(text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="also `prove --all` (slow claims included)")
    parser.add_argument("--heaviest", type=int, default=4, help="how many of the longest claims to measure alone")
    parser.add_argument("--note", default="", help="a sentence on the conditions (load on the machine)")
    args = parser.parse_args()
    selections = {"prove --all --no-slow": ["--all", "--no-slow"]}
    if args.full:
        selections["prove --all"] = ["--all"]
    results = {}
    for name, selection in selections.items():
        results[name] = measure(selection, (1, 2))
        for j, (wall, cpu, rss, records) in results[name].items():
            print(f"hkproof {name} --jobs {j}: {wall:.1f} s wall, {cpu:.1f} s CPU, {rss:.0f} MB, "
                  f"{records[-1]['summary']}", flush=True)
    last = results[list(results)[-1]][1][3][:-1]
    heaviest = [r["id"] for r in sorted(last, key=lambda r: -r["seconds"])[:args.heaviest]]
    peaks = []
    for cid in heaviest:
        wall, _, rss, _ = hkproof("prove", cid, "--jobs", "1")
        peaks.append((cid, wall, rss))
        print(f"{cid}: {wall:.1f} s, {rss:.0f} MB", flush=True)
    write_section(section(results, peaks, args.note))


if __name__ == "__main__":
    main()
