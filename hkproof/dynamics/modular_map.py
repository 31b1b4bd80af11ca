"""The Kahan map with eps and the parameters fixed, reduced modulo a word-size prime (`KahanMap.mod(p, values)`).

One modular map serves every modular computation: orbits and their tangent maps (screening, candidate gradients),
the explicit map N/Delta as polynomials mod p (Darboux searches), and its homogenization (degree growth). The matrix
form M(x) x~ = b(x) of eq. "Kahan gen" is affine in x: M(x) = M0 + sum_k x_k M_k, b(x) = b0 + B x.
"""
from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING, Mapping, Sequence

import flint

from hkproof.algebra.modular import residue
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.errors import ParseError, UnluckyPrimeError

if TYPE_CHECKING:
    from hkproof.dynamics.kahan import KahanMap

__all__ = ["HOM", "ModularKahanMap"]

HOM = "_hom"   # the homogenizing variable of the projective map


class ModularKahanMap:
    """f(., eps) mod p with eps and every parameter fixed to residues of the given rationals."""

    def __init__(self, kmap: KahanMap, values: Mapping[str, Rational], p: int):
        names = kmap.field.control_names
        missing = [n for n in names if n not in values]
        if missing:
            raise ParseError(f"the modular map of {kmap.field.name} needs values for {missing}")
        self.kmap, self.p = kmap, p
        self.values = {n: residue(to_fmpq(values[n]), p) for n in names}
        self.n = len(kmap.variables)

    def __repr__(self) -> str:
        return f"ModularKahanMap({self.kmap.field.name}, p={self.p})"

    def _at(self, poly: flint.fmpz_mpoly) -> int:
        """A polynomial in eps and the parameters at the fixed residues."""
        ring = self.kmap.ring
        args = [self.values.get(name, 0) for name in ring.names]
        return int(poly(*args)) % self.p

    @cached_property
    def matrices(self) -> tuple[flint.nmod_mat, list[flint.nmod_mat], flint.nmod_mat, flint.nmod_mat]:
        """(M0, [M_k], b0, B) with M(x) = M0 + sum_k x_k M_k and b(x) = b0 + B x, mod p."""
        m_parts, b_parts = self.kmap.affine_matrix
        p, n = self.p, self.n

        def part(entry: dict, k: int | None) -> int:
            return self._at(entry[k]) if k in entry else 0
        m0 = flint.nmod_mat([[part(e, None) for e in row] for row in m_parts], p)
        mk = [flint.nmod_mat([[part(e, k) for e in row] for row in m_parts], p) for k in range(n)]
        b0 = flint.nmod_mat([[part(e, None)] for e in b_parts], p)
        bmat = flint.nmod_mat([[part(e, k) for k in range(n)] for e in b_parts], p)
        return m0, mk, b0, bmat

    def matrix_at(self, x: Sequence[int]) -> flint.nmod_mat:
        """M(x) mod p."""
        m0, mk, _, _ = self.matrices
        m = m0
        for k, v in enumerate(x):
            if v:
                m = m + mk[k] * v
        return m

    def step(self, x: Sequence[int]) -> list[int]:
        """x~ from M(x) x~ = b(x) mod p; UnluckyPrimeError where det M(x) = 0 mod p."""
        return self._solve(x)[0]

    def _solve(self, x: Sequence[int]) -> tuple[list[int], flint.nmod_mat, flint.nmod_mat]:
        _, _, b0, bmat = self.matrices
        m = self.matrix_at(x)
        try:
            xt = m.solve(b0 + bmat * flint.nmod_mat([[v] for v in x], self.p))
        except ZeroDivisionError:
            raise UnluckyPrimeError(f"det M(x, eps) = 0 mod {self.p}") from None
        return [int(xt[r, 0]) for r in range(self.n)], m, xt

    def orbit(self, x: Sequence[int], steps: int) -> list[list[int]]:
        """x, f(x), ..., f^steps(x) mod p; UnluckyPrimeError names the step where det M vanishes."""
        out = [list(x)]
        for i in range(steps):
            try:
                out.append(self.step(out[-1]))
            except UnluckyPrimeError as exc:
                raise UnluckyPrimeError(f"step {i + 1} of the orbit: {exc}") from None
        return out

    def tangent_orbit(self, x: Sequence[int], steps: int) -> tuple[list[list[int]], list[flint.nmod_mat]]:
        """The orbit and the Jacobians D(f^i)(x) mod p, from M(x) Df + dM x~ = B (eq. "Kahan gen" differentiated)."""
        p, n = self.p, self.n
        _, mk, _, bmat = self.matrices
        jac = flint.nmod_mat([[int(i == j) for j in range(n)] for i in range(n)], p)
        points, jacobians = [list(x)], [jac]
        for i in range(steps):
            try:
                xt_list, m, xt = self._solve(points[-1])
            except UnluckyPrimeError as exc:
                raise UnluckyPrimeError(f"step {i + 1} of the orbit: {exc}") from None
            dm = flint.nmod_mat([[int((mk[j] * xt)[r, 0]) for j in range(n)] for r in range(n)], p)
            jac = m.solve(bmat - dm) * jac
            points.append(xt_list)
            jacobians.append(jac)
        return points, jacobians

    @cached_property
    def phase_context(self) -> flint.nmod_mpoly_ctx:
        """Polynomials mod p in the phase variables."""
        return flint.nmod_mpoly_ctx.get(self.kmap.variables, self.p, "degrevlex")  # type: ignore[call-arg, arg-type]  # flint's stubs lag the API

    def reduce(self, poly: flint.fmpz_mpoly, homogenize_to: int | None = None) -> flint.nmod_mpoly:
        """poly(x, eps, params) with eps and the parameters fixed, mod p, as a polynomial in the phase variables
        (homogenized to degree `homogenize_to` in the phase variables and HOM when given)."""
        ctx = self.phase_context if homogenize_to is None else flint.nmod_mpoly_ctx.get(  # type: ignore[call-arg]
            self.kmap.variables + (HOM,), self.p, "degrevlex")  # type: ignore[arg-type]  # flint's stubs lag the API
        names = self.kmap.ring.names
        xi = [names.index(v) for v in self.kmap.variables]
        fixed = [(names.index(k), v) for k, v in self.values.items()]
        p = self.p
        data: dict[tuple[int, ...], int] = {}
        for m, c in poly.to_dict().items():
            coeff = int(c) % p
            for j, v in fixed:
                if m[j]:
                    coeff = coeff * pow(v, m[j], p) % p
            key = tuple(m[i] for i in xi)
            if homogenize_to is not None:
                key = key + (homogenize_to - sum(key),)
            data[key] = (data.get(key, 0) + coeff) % p
        return ctx.from_dict({k: c for k, c in data.items() if c})

    @cached_property
    def explicit(self) -> tuple[list[flint.nmod_mpoly], flint.nmod_mpoly]:
        """(N_i, Delta) mod p as polynomials in the phase variables: f = N / Delta."""
        nums, delta = self.kmap.explicit
        return [self.reduce(q) for q in nums], self.reduce(delta)

    def homogenized(self) -> tuple[list[flint.nmod_mpoly], int]:
        """[W^d N_i(X/W), W^d Delta(X/W)] mod p in the phase variables and W = HOM: the projective map, degree d."""
        nums, delta = self.kmap.explicit
        xi = [self.kmap.ring.index(v) for v in self.kmap.variables]
        d = max(sum(m[i] for i in xi) for q in (*nums, delta) for m in q.monoms())
        return [self.reduce(q, d) for q in (*nums, delta)], d

    def evaluate(self, x: Sequence[int]) -> list[int] | None:
        """f(x) mod p from the explicit map, None where Delta(x) = 0 mod p."""
        nums, delta = self.explicit
        d = int(delta(*x))
        if d == 0:
            return None
        inv = pow(d, -1, self.p)
        return [int(q(*x)) * inv % self.p for q in nums]
