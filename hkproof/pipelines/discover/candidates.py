"""Candidate integrals: ratios c_k / c_j of the kernel coordinates of minimal HK-bases, with gradients mod p.

For a basis with a one-dimensional kernel every ratio of two kernel coordinates is an integral (recipe (B) uses
j = l, c_l = -1). Gradients mod p through the orbit's tangent maps (M(x) dx~ + dM x~ = db, eq. "Kahan gen"
differentiated) and the quotient rule show how many independent integrals the kernels carry.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Callable

import flint

from hkproof.algebra.sampling import random_rational
from hkproof.algebra.monomials import Exponents
from hkproof.errors import HKProofError
from hkproof.experiments.reconstruction import dense_size, univariate_degrees
from hkproof.experiments.scene import make_scene
from hkproof.experiments.weights import Weights
from hkproof.dynamics.kahan import KahanMap
from hkproof.pipelines.discover.screen import TangentOrbit

__all__ = ["Candidate", "coordinate_gradients", "modular_sampler", "normalizations", "ratio_candidates",
           "recipe_b_mod_p"]


@dataclass
class Candidate:
    """The ratio c_k / c_j of two coordinates of the kernel of a minimal HK-basis (an integral: K_Phi(x) is
    one-dimensional); j = l - 1 is recipe (B)'s normalization c_l = -1, up to sign."""

    basis: list[Exponents]
    k: int
    gradient: list[int]
    norm: int = -1
    estimate: int = 0            # unknowns of its dense ansatz, from degrees along one line mod p

    @property
    def j(self) -> int:
        return self.norm % len(self.basis)

    @property
    def label(self) -> str:
        return f"c{self.k + 1}/c{self.j + 1}"


def recipe_b_mod_p(orbit: TangentOrbit, basis: list[Exponents]) -> tuple[flint.nmod_mat, list[int]] | None:
    """(A, c) with A c = b: sum_k c_k phi_k(f^i x) = phi_l(f^i x), i = 0..l-2 (eq. "smaller system") mod p."""
    p, l = orbit.p, len(basis)
    a = flint.nmod_mat([[orbit.value(e, i) for e in basis[:-1]] for i in range(l - 1)], p)
    b = flint.nmod_mat([[orbit.value(basis[-1], i)] for i in range(l - 1)], p)
    try:
        c = a.solve(b)
    except ZeroDivisionError:
        return None
    return a, [int(c[k, 0]) for k in range(l - 1)]


def coordinate_gradients(orbit: TangentOrbit, basis: list[Exponents]) -> list[list[int]] | None:
    """Gradients mod p of the kernel coordinates c_1..c_(l-1) of recipe (B), by the orbit's tangent maps."""
    solved = recipe_b_mod_p(orbit, basis)
    if solved is None:
        return None
    a, cs = solved
    p = orbit.p
    g = []
    for i in range(len(basis) - 1):
        row = orbit.gradient(basis[-1], i)
        for ck, e in zip(cs, basis[:-1], strict=True):
            if ck:
                gk = orbit.gradient(e, i)
                row = [(r - ck * q) % p for r, q in zip(row, gk, strict=True)]
        g.append(row)
    dc = a.solve(flint.nmod_mat(g, p))
    return [[int(dc[k, j]) for j in range(dc.ncols())] for k in range(len(basis) - 1)]


def ratio_candidates(orbit: TangentOrbit, basis: list[Exponents], j: int) -> list[Candidate]:
    """The ratios c_k / c_j, k != j, with their gradients mod p (quotient rule on recipe (B)'s coordinates)."""
    grads = coordinate_gradients(orbit, basis)
    solved = recipe_b_mod_p(orbit, basis)
    if grads is None or solved is None:
        return []
    p, n = orbit.p, len(orbit.points[0])
    c = solved[1] + [p - 1]
    g = grads + [[0] * n]
    if c[j] == 0:
        return []
    inv = pow(c[j], -2, p)
    return [Candidate(basis, k, [(gk * c[j] - c[k] * gj) * inv % p for gk, gj in zip(g[k], g[j], strict=True)], j)
            for k in range(len(basis)) if k != j]


def modular_sampler(kmap: KahanMap, basis: list[Exponents], k: tuple[int, int] | None, weights: Weights,
                    free: list[str], p: int) -> Callable:
    """Values mod p of c_k / c_j, k = (k, j), for the kernel of a minimal basis (the whole vector c with
    c_l = -1 when k is None): cheap degree probes."""
    def sample(outer: dict, points: list[dict]) -> list:
        vals = {m: flint.fmpq(1) for m in weights.normalized} | {m: outer[m] for m in free}
        try:
            scene = make_scene(kmap, vals)
        except HKProofError:
            return [None] * len(points)
        out: list = []
        for pt in points:
            try:
                solved = recipe_b_mod_p(TangentOrbit.at(scene, [pt[v] for v in kmap.variables], p, len(basis) - 2),
                                        basis)
            except HKProofError:
                solved = None
            if solved is None:
                out.append(None)
            else:
                c = solved[1] + [p - 1]
                out.append(c if k is None else None if c[k[1]] == 0 else c[k[0]] * pow(c[k[1]], -1, p) % p)
        return out
    return sample


def normalizations(kmap: KahanMap, basis: list[Exponents], weights: Weights, free: list[str], p: int,
                   rng: random.Random, nvars: int, max_degree: int = 12) -> list[tuple[int, dict[int, int]]]:
    """Recipe (B)'s normalization j = l - 1 and the coordinate j whose ratios c_k / c_j have the smallest dense
    ansatzes, with the size of each ratio's ansatz, from degrees along one random line (values mod p). A special
    line or prime only lowers degrees, so a size above the limit is a safe reason to skip."""
    names = list(free) + list(kmap.variables)
    a = [random_rational(rng, 30) for _ in names]
    b = [random_rational(rng, 30) for _ in names]
    sample = modular_sampler(kmap, basis, None, weights, free, p)
    ts: list[int] = []
    vecs: list = []
    for t in range(1, 4 * max_degree + 20):
        if len(ts) >= 2 * max_degree + 5:
            break
        pt = dict(zip(names, (x + t * y for x, y in zip(a, b, strict=True)), strict=True))
        v = sample({m: pt[m] for m in free}, [{m: pt[m] for m in kmap.variables}])[0]
        if v is not None and all(v):
            ts.append(t)
            vecs.append(v)
    l = len(basis)
    options = []
    for j in range(l - 1, -1, -1):
        sizes = {}
        for k in range(l):
            if k != j:
                deg = univariate_degrees(ts, [v[k] * pow(v[j], -1, p) % p for v in vecs], p, max_degree)
                sizes[k] = 10**9 if deg is None else dense_size(nvars, deg)
        options.append((sum(sorted(sizes.values())[:max(1, len(sizes) // 2)]), j, sizes))   # the simpler half
    best = min(options, key=lambda o: o[0])
    return [(options[0][1], options[0][2])] + ([(best[1], best[2])] if best[1] != l - 1 else [])
