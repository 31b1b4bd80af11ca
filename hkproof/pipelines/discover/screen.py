"""Screening (paper, sec. 4): algorithm (N) mod p on the union basis Phi_D of all monomials of degree <= D.

The kernel K_Phi(x) is the space of polynomials of degree <= D vanishing on an orbit. Products of a lower-degree
kernel with monomials (trivial inflation) are split off degree by degree. A kernel of dimension 0 mod p is exact:
the rank over Q is at least the rank mod p.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Sequence

import flint

from hkproof.algebra.sampling import random_rational
from hkproof.algebra.modular import kernel_mod_p, random_prime, rank_mod_p
from hkproof.algebra.monomials import Exponents, exponents_upto, value_mod_p
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.modular_map import ModularKahanMap
from hkproof.errors import SingularPointError, UnluckyPrimeError
from hkproof.experiments.arithmetics import pivot_columns
from hkproof.experiments.profiles_mod_p import ModP
from hkproof.experiments.profiles import fundamental_finite
from hkproof.experiments.scene import Scene

__all__ = ["Probe", "TangentOrbit", "complement_of_trivial", "screen", "trivial_products", "without_conserved"]


def without_conserved(field: QuadraticField) -> tuple[QuadraticField, list[str]]:
    """Conserved coordinates (x_i' = 0, so x~_i = x_i) become parameters: they would only inflate the kernels."""
    conserved = [v for v, f in zip(field.variables, field.rhs, strict=True) if f.is_zero()]
    if not conserved or len(conserved) == len(field.variables):
        return field, conserved
    keep = [i for i, v in enumerate(field.variables) if v not in conserved]
    return QuadraticField(field.name + "[moving]", tuple(field.variables[i] for i in keep),
                          field.parameters + tuple(conserved), tuple(field.rhs_text[i] for i in keep),
                          field.description, field.step), conserved


class TangentOrbit:
    """The orbit x, f(x), ... mod p and the Jacobians D(f^i)(x): values and gradients of monomials along it."""

    def __init__(self, modular: ModularKahanMap, x: Sequence[int], steps: int):
        self.p = modular.p
        self.points, self.jacobians = modular.tangent_orbit(x, steps)

    @classmethod
    def at(cls, scene: Scene, point: Sequence[flint.fmpq], p: int, steps: int) -> TangentOrbit:
        """The orbit mod p of a rational point of a scene (UnluckyPrimeError where p divides a denominator)."""
        return cls(scene.kmap.mod(p, scene.fixed), [ModP(p).number(v) for v in point], steps)

    def value(self, e: Exponents, i: int) -> int:
        """The monomial x^e at f^i(x), mod p."""
        return value_mod_p(e, self.points[i], self.p)

    def point_gradient(self, e: Exponents, i: int) -> list[int]:
        """grad phi at f^i(x) for the monomial phi = x^e (d/dx of phi o f^i is this times D(f^i)(x))."""
        g = []
        for j in range(len(e)):
            if not e[j]:
                g.append(0)
                continue
            lower = list(e)
            lower[j] -= 1
            g.append(e[j] * value_mod_p(tuple(lower), self.points[i], self.p) % self.p)
        return g


@dataclass
class Probe:
    """One random point and prime: the orbit mod p and the kernels of Phi_D' for D' = 1..D."""

    point: list[flint.fmpq]
    orbit: TangentOrbit
    kernels: dict[int, list[list[int]]]
    trivial_rank: dict[int, int]
    verdict: dict[int, str]

    @property
    def p(self) -> int:
        return self.orbit.p


def screen(scene: Scene, n: int, degree: int, rng: random.Random, extra: int = 3) -> Probe:
    """Kernels of the union bases at one random point mod one random prime (algorithm (N), exact in the sense
    that a rank mod p is a lower bound of the rank over Q)."""
    monos = {d: exponents_upto(n, d) for d in range(1, degree + 1)}
    top = len(monos[degree])
    for _ in range(8):
        point = [random_rational(rng, 99) for _ in range(n)]
        p = random_prime(rng)
        try:
            orbit = TangentOrbit.at(scene, point, p, top + extra - 1)
        except UnluckyPrimeError:
            continue
        kernels, trivial, verdict = {}, {}, {}
        for d, ms in monos.items():
            rows = [[orbit.value(e, i) for e in ms] for i in range(len(ms) + extra)]
            prefix = ModP(p).prefix_ranks(rows[:len(ms)])[0]
            verdict[d] = fundamental_finite(prefix)[0]
            kernels[d] = kernel_mod_p(rows, p)
            trivial[d] = rank_mod_p(trivial_products(kernels.get(d - 1, []), monos.get(d - 1, []), ms, n), p)
        return Probe(point, orbit, kernels, trivial, verdict)
    raise SingularPointError("eight random orbits met det M = 0 mod p: the map looks singular on the whole space")


def trivial_products(kernel: list[list[int]], lower: list[Exponents], monos: list[Exponents],
                     n: int) -> list[list[int]]:
    """Coefficient vectors of m * v for v in a kernel of degree D-1 and m in {1, x_1, ..., x_n} (trivial part)."""
    index = {e: i for i, e in enumerate(monos)}
    shifts = [tuple(0 for _ in range(n))] + [tuple(int(i == j) for i in range(n)) for j in range(n)]
    out = []
    for v in kernel:
        for s in shifts:
            w = [0] * len(monos)
            for e, c in zip(lower, v, strict=True):
                if c:
                    w[index[tuple(a + b for a, b in zip(e, s, strict=True))]] = c
            out.append(w)
    return out


def complement_of_trivial(kernel: list[list[int]], trivial: list[list[int]], monos: list[Exponents],
                          p: int) -> tuple[list[list[int]], list[int]]:
    """The kernel vectors vanishing on the pivot columns Z of the trivial part T (a complement of T), and Z.

    Z is chosen among the monomials with the highest powers of the last variables, so that a linear integral
    L = ... + x_n eliminates x_n: what is left are the polynomials free of the eliminated monomials."""
    if not trivial or rank_mod_p(trivial, p) == 0:
        return kernel, []
    order = sorted(range(len(monos)), key=lambda j: tuple(reversed(monos[j])), reverse=True)
    r, rank = flint.nmod_mat([[t[j] for j in order] for t in trivial], p).rref()
    pivots = [order[j] for j in pivot_columns(r, rank)]
    lam = kernel_mod_p([[v[j] for v in kernel] for j in pivots], p)
    return [[sum(l[i] * kernel[i][j] for i in range(len(kernel))) % p for j in range(len(monos))]
            for l in lam], sorted(pivots)
