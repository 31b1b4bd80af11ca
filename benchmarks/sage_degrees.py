"""`degrees` against Sage's degree sequence of a projective dynamical system, side by side: the same Kahan maps at the
same exact eps and parameters. hkproof restricts f^n to random lines mod large primes (evidence); Sage composes the
homogenized map over Q and normalizes each iterate (exact). Needs the bench extra: pip install -e '.[bench]'.

Run: python benchmarks/sage_degrees.py [--iterates 6] [--seconds 120]  (prints a Markdown table)
"""
from __future__ import annotations

import argparse
import multiprocessing
import time

import hkproof as hk
from hkproof.algebra.fraction import Frac

CASES = {"lotka-volterra": {"eps": "1/3"}, "euler-top": {"eps": "1/3", "a1": "1", "a2": "-2", "a3": "3"},
         "volterra-3": {"eps": "1/3"}}


def projective_map(name: str, values: dict[str, str]):
    """The Kahan map at `values` as Sage's DynamicalSystem_projective [N_1^h : ... : N_n^h : Delta^h]."""
    import sage.all__sagemath_singular as sg
    from sage.all__sagemath_schemes import DynamicalSystem_projective, ProjectiveSpace

    f = hk.kahan_map(name)
    ring = hk.sage.sage_ring(f.ring.names)
    fixed = {ring(k): sg.QQ(int(v.p)) / int(v.q) for k, v in f.field.check_values(values).items()}
    nums, delta = f.explicit
    parts = [hk.sage.to_sage(Frac(f.ring, p), ring).subs(fixed)
             for p in (*nums, delta)]
    n, d = len(f.variables), max(p.total_degree() for p in parts)
    space = ProjectiveSpace(sg.QQ, n, list(f.variables) + ["h"])
    coords = space.coordinate_ring()
    return DynamicalSystem_projective([coords({tuple(e[:n]) + (d - sum(e[:n]),): c for e, c in p.dict().items()})
                                       for p in parts], domain=space)


def _sage_sequence(name: str, values: dict[str, str], iterates: int, out) -> None:
    start = time.perf_counter()
    seq = [int(k) for k in projective_map(name, values).degree_sequence(iterates)]
    out.put((seq, time.perf_counter() - start))


def sage_sequence(name: str, values: dict[str, str], iterates: int, seconds: float) -> tuple[list[int] | None, float]:
    """Sage's degrees of f^1..f^iterates and its seconds, or (None, seconds) when stopped at the time limit."""
    queue: multiprocessing.Queue = multiprocessing.Queue()
    worker = multiprocessing.Process(target=_sage_sequence, args=(name, values, iterates, queue))
    start = time.perf_counter()
    worker.start()
    worker.join(seconds)
    if worker.is_alive():
        worker.terminate()
        worker.join()
        return None, time.perf_counter() - start
    return queue.get()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--iterates", type=int, default=6)
    parser.add_argument("--seconds", type=float, default=120.0, help="time limit of one Sage run")
    args = parser.parse_args()
    print("| system | values | n | hkproof degrees (mod p, 2 runs) | seconds | Sage degree_sequence (over Q) "
          "| seconds | agree |")
    print("|---|---|---|---|---|---|---|---|")
    for name, values in CASES.items():
        for n in range(2, args.iterates + 1):
            start = time.perf_counter()
            ours = hk.degrees(name, n, values=values).degrees
            mine = time.perf_counter() - start
            theirs, sage_seconds = sage_sequence(name, values, n, args.seconds)
            shown = ", ".join(f"{k} = {v}" for k, v in values.items())
            print(f"| {name} | {shown} | {n} | {ours} | {mine:.3f} | "
                  + (f"{theirs} | {sage_seconds:.2f} | {'yes' if theirs == ours else 'NO'} |" if theirs is not None
                     else f"stopped | > {args.seconds:g} | - |"), flush=True)
            if theirs is None:
                break


if __name__ == "__main__":
    main()
