"""Minimal HK-bases as circuits: the minimal supports of the non-zero vectors of a kernel mod p.

Each circuit carries a one-dimensional kernel, so it is an HK-basis with d = 1 (paper, Def. "Hirota mech"), and no
search over subsets of monomials is needed.
"""
from __future__ import annotations

import itertools

from hkproof import budget
from hkproof.algebra.modular import kernel_mod_p

__all__ = ["MAX_CIRCUIT_TRIALS", "circuits", "support_vector"]

MAX_CIRCUIT_TRIALS = 20000


def circuits(kernel: list[list[int]], p: int, cap: int = MAX_CIRCUIT_TRIALS) -> tuple[list[tuple[int, ...]], bool]:
    """The minimal supports of the kernel's non-zero vectors (each is a minimal HK-basis), and whether the
    enumeration was complete (it stops after `cap` trials)."""
    d = len(kernel)
    if d == 0:
        return [], True
    support = [j for j in range(len(kernel[0])) if any(v[j] for v in kernel)]
    supports: set[tuple[int, ...]] = set()
    complete = True
    for trials, zeros in enumerate(itertools.combinations(support, d - 1)):
        if trials >= cap:
            complete = False
            break
        budget.check("enumerating the minimal HK-bases (circuits of a kernel)")
        if d == 1:
            lam = [[1]]
        else:
            sub = [[v[j] for v in kernel] for j in zeros]        # (d-1) x d: lam . columns = 0
            lam = kernel_mod_p(sub, p)
            if len(lam) != 1:
                continue
        vec = [sum(lam[0][i] * kernel[i][j] for i in range(d)) % p for j in range(len(kernel[0]))]
        supports.add(tuple(j for j, c in enumerate(vec) if c))
    minimal = [s for s in supports if not any(set(t) < set(s) for t in supports)]
    return sorted(minimal, key=lambda s: (len(s), s)), complete


def support_vector(kernel: list[list[int]], support: tuple[int, ...], p: int) -> list[int]:
    """The kernel vector supported on `support` (a circuit), mod p."""
    others = [j for j in range(len(kernel[0])) if j not in support]
    lam = kernel_mod_p([[v[j] for v in kernel] for j in others], p) if others else [[1] + [0] * (len(kernel) - 1)]
    return [sum(lam[0][i] * kernel[i][j] for i in range(len(kernel))) % p for j in range(len(kernel[0]))]
