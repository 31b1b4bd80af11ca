"""Candidate integrals: ratios c_k / c_j of the kernel coordinates of minimal HK-bases, with gradients mod p.

For a basis with a one-dimensional kernel every ratio of two kernel coordinates is an integral (recipe (B) uses
j = l, c_l = -1). Gradients mod p through the orbit's tangent maps (M(x) dx~ + dM x~ = db, eq. "Kahan gen"
differentiated) and the quotient rule show how many independent integrals the kernels carry.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Callable, Sequence

import flint

from hkproof import budget
from hkproof.algebra.dense_reconstruction import ansatz_size
from hkproof.algebra.modular import random_prime
from hkproof.algebra.monomials import Exponents
from hkproof.algebra.reconstruction import fractions_on_line
from hkproof.errors import HKProofError
from hkproof.experiments.scene import make_scene
from hkproof.experiments.weights import Weights
from hkproof.dynamics.kahan import KahanMap
from hkproof.pipelines.discover.blackbox import KernelBlackBox
from hkproof.pipelines.discover.screen import TangentOrbit

__all__ = ["Candidate", "coordinate_gradients", "line_degrees", "modular_sampler", "normalizations",
           "ratio_candidates", "recipe_b_gradients", "recipe_b_mod_p"]


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
    l = len(basis)
    return _solve_recipe_b([[orbit.value(e, i) for e in basis] for i in range(l - 1)], orbit.p)


def _solve_recipe_b(values: list[list[int]], p: int) -> tuple[flint.nmod_mat, list[int]] | None:
    """(A, c) from the values phi_k(f^i x), row i = 0..l-2, column k = 1..l: the last column is the right-hand side."""
    a = flint.nmod_mat([row[:-1] for row in values], p)
    b = flint.nmod_mat([[row[-1]] for row in values], p)
    try:
        c = a.solve(b)
    except ZeroDivisionError:
        return None
    return a, [int(c[k, 0]) for k in range(len(values[0]) - 1)]


def recipe_b_gradients(values: list[list[int]], point_gradient: Callable[[int, int], list[int]],
                       tangents: Sequence[flint.nmod_mat], p: int) -> list[list[int]] | None:
    """Gradients mod p of the coordinates c_1..c_(l-1) of recipe (B), from the values phi_k(f^i x), the gradients
    grad phi_k at f^i x (`point_gradient(k, i)`) and the orbit's tangent maps D(f^i)(x): A dc = d(rhs) -
    sum_k c_k d(row_k), where d(phi o f^i) = grad phi(f^i x) D(f^i)(x), so each row is combined first and meets its
    tangent map once."""
    solved = _solve_recipe_b(values, p)
    if solved is None:
        return None
    a, cs = solved
    l = len(values[0])
    g = []
    for i in range(l - 1):              # l - 1 rows of up to l gradients each: long for a wide basis
        budget.check("computing the gradients of kernel coordinates mod p")
        row = point_gradient(l - 1, i)
        for k, ck in enumerate(cs):
            if ck:
                row = [(r - ck * q) % p for r, q in zip(row, point_gradient(k, i), strict=True)]
        moved = flint.nmod_mat([row], p) * tangents[i]
        g.append([int(moved[0, j]) for j in range(moved.ncols())])
    dc = a.solve(flint.nmod_mat(g, p))
    return [[int(dc[k, j]) for j in range(dc.ncols())] for k in range(l - 1)]


def coordinate_gradients(orbit: TangentOrbit, basis: list[Exponents]) -> list[list[int]] | None:
    """Gradients mod p of the kernel coordinates c_1..c_(l-1) of recipe (B), by the orbit's tangent maps."""
    values = [[orbit.value(e, i) for e in basis] for i in range(len(basis) - 1)]
    return recipe_b_gradients(values, lambda k, i: orbit.point_gradient(basis[k], i), orbit.jacobians, orbit.p)


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


def line_degrees(kmap: KahanMap, basis: list[Exponents], weights: Weights, free: list[str], rng: random.Random,
                 max_degree: int = 40) -> dict[tuple[int, int], tuple[int, int] | None]:
    """(deg P, deg Q) of every ratio c_k / c_j of the kernel coordinates of `basis` along one random line through the
    free names and the phase variables, mod a 50-bit prime: each c_k = c_k / (-c_l) by Thiele's interpolation with
    early termination (the batch black box), every other ratio from those by products and gcds of univariate
    polynomials; None above `max_degree`. A special line or prime only lowers degrees."""
    p = random_prime(rng, 50)
    inputs = list(free) + list(kmap.variables)
    box = KernelBlackBox(kmap, basis, 0, len(basis) - 1, inputs, {n: 1 for n in weights.normalized})
    a = [rng.randrange(1, p) for _ in inputs]
    b = [rng.randrange(1, p) for _ in inputs]
    l = len(basis)

    def ratios(ts: list[int]) -> list[list[int] | None]:           # c_k / c_l at x = a + t b, k < l
        coords, ok = box.vectors(p, [[(x + t * y) % p for x, y in zip(a, b, strict=True)] for t in ts])
        bottoms = [int(v) for v in coords[l - 1]]
        return [[int(coords[k][i]) * pow(bottoms[i], -1, p) % p for k in range(l - 1)] if ok[i] and bottoms[i]
                else None for i in range(len(ts))]
    nodes = iter(range(1, 1 << 62))
    found = fractions_on_line(ratios, p, l - 1, lambda k: [next(nodes) for _ in range(k)], max_degree,
                              first=2 * max_degree + 7)
    fractions: list[tuple[flint.nmod_poly, flint.nmod_poly] | None] = [
        None if f is None else (flint.nmod_poly(f[0], p), flint.nmod_poly(f[1], p)) for f in found]
    fractions.append((flint.nmod_poly([1], p), flint.nmod_poly([1], p)))         # c_l / c_l = 1
    out: dict[tuple[int, int], tuple[int, int] | None] = {}
    for j in range(l):
        budget.check("reading the degrees of kernel coordinates along a line")
        for k in range(l):
            if k == j:
                continue
            fk, fj = fractions[k], fractions[j]
            if fk is None or fj is None or fj[0].is_zero():
                out[(k, j)] = None
                continue
            upper, lower = fk[0] * fj[1], fk[1] * fj[0]
            g = upper.gcd(lower)
            out[(k, j)] = (max((upper // g).degree(), 0), max((lower // g).degree(), 0))
    return out


def normalizations(kmap: KahanMap, basis: list[Exponents], weights: Weights, free: list[str], rng: random.Random,
                   nvars: int) -> list[tuple[int, dict[int, int]]]:
    """Recipe (B)'s normalization j = l - 1 and the coordinate j whose ratios c_k / c_j have the smallest dense
    ansatzes (the simpler half first, then every size in increasing order, so that the order of the variables does
    not decide), with the size of each ratio's ansatz, from degrees along one random line (`line_degrees`)."""
    degrees = line_degrees(kmap, basis, weights, free, rng)
    l = len(basis)
    options = []
    for j in range(l - 1, -1, -1):
        sizes = {k: 10**12 if d is None else ansatz_size(nvars, d)
                 for k, d in ((k, degrees[(k, j)]) for k in range(l) if k != j)}
        ordered = sorted(sizes.values())
        options.append((sum(ordered[:max(1, len(sizes) // 2)]), ordered, j, sizes))   # the simpler half, then all
    best = min(options, key=lambda o: (o[0], o[1]))       # (ties on the simpler half broken by every size, not by
    return [(options[0][2], options[0][3])] + ([(best[2], best[3])] if best[2] != l - 1 else [])   # variable order)
