"""The Kahan (Hirota-Kimura) map of a quadratic field: eq. "Kahan gen", its matrix form, explicit map and iterates."""
from __future__ import annotations

from functools import cached_property
from typing import Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac, homogenized_compose, normalize_sign
from hkproof.algebra.linalg import cramer_polynomials
from hkproof.algebra.printing import latex, poly_to_sympy
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.field import EPS, TILDE, QuadraticField
from hkproof.dynamics.heights import HeightGuard
from hkproof.dynamics.modular_map import ModularKahanMap
from hkproof.errors import ParseError, SingularPointError

__all__ = ["commutator_at", "KahanMap", "SHOWN_TERMS"]

SHOWN_TERMS = 200        # a Kahan map with more terms shows in Jupyter by its term counts


class KahanMap:
    """x~ = f(x, eps) solving (x~ - x)/(2 eps) = Q(x, x~) + B(x + x~)/2 + c (eq. "Kahan gen").

    >>> riccati = KahanMap(QuadraticField("riccati", ("x",), (), ("x**2",)))   # x~ - x = 2 eps x x~
    >>> [str(c) for c in riccati.components()]
    ['(x)/(-2*x*eps + 1)']
    >>> riccati.mod(101, {"eps": 1}).orbit([3], 2)                            # x~ = x / (1 - 2x) mod 101
    [[3], [60], [64]]
    """

    def __init__(self, field: QuadraticField):
        self.field = field
        self.ring = field.ring
        self.variables = field.variables

    def __repr__(self) -> str:
        return f"KahanMap({self.field.name})"

    # ---- the equations --------------------------------------------------------------------------
    @cached_property
    def equations(self) -> tuple[flint.fmpz_mpoly, ...]:
        """E_i(x, x~, eps) in Z[x, x~, eps, params]: den_i * (x~_i - x_i - 2 eps Q_i(x, x~) - ...), bilinear."""
        t = self.field.tilde_ring
        x = [t.gen(v) for v in self.variables]
        xt = [t.gen(v) for v in self.field.tilde_variables]
        eps = t.gen(EPS)
        out = []
        for v, f in zip(self.variables, self.field.rhs, strict=True):
            g = f.to_ring(t)
            # 2*F^(x, x~) = 4 F((x + x~)/2) - F(x) - F(x~), split by degree to stay in Z[...]
            polar = _twice_polarization(t, g.num, x, xt, self.variables, self.field.tilde_variables)
            e = (t.gen(v + TILDE) - t.gen(v)) * g.den - eps * polar
            out.append(e)
        return tuple(out)

    @cached_property
    def matrix(self) -> tuple[tuple[tuple[flint.fmpz_mpoly, ...], ...], tuple[flint.fmpz_mpoly, ...]]:
        """(M, b) with M(x, eps) x~ = b(x, eps), polynomials in Z[x, eps, params] (paper's matrix form)."""
        t = self.field.tilde_ring
        r = self.ring
        zero_tilde: dict[str | int, int] = {v: 0 for v in self.field.tilde_variables}
        rows, rhs = [], []
        for e in self.equations:
            rows.append(tuple(e.derivative(t.index(w)).project_to_context(r.ctx)
                              for w in self.field.tilde_variables))
            rhs.append(-(e.subs(zero_tilde)).project_to_context(r.ctx))
        return tuple(rows), tuple(rhs)

    @cached_property
    def affine_matrix(self) -> tuple[tuple[tuple[dict, ...], ...], tuple[dict, ...]]:
        """Each entry of M and b split as e0 + sum_k x_k e_k (keys None and k), the e's polynomials in eps and
        the parameters: M and b are affine in x (eq. "Kahan gen" is bilinear)."""
        m, b = self.matrix
        return (tuple(tuple(self._split_affine(e) for e in row) for row in m),
                tuple(self._split_affine(e) for e in b))

    def _split_affine(self, e: flint.fmpz_mpoly) -> dict:
        ring = self.ring
        idx = [ring.index(v) for v in self.variables]
        pieces: dict[int | None, dict] = {}
        for mono, c in e.to_dict().items():
            deg = [mono[i] for i in idx]
            if sum(deg) > 1:
                raise ParseError(f"{self} is not affine in the phase variables: entry {e}")
            k = next((j for j, d in enumerate(deg) if d), None)
            rest = list(mono)
            if k is not None:
                rest[idx[k]] = 0
            pieces.setdefault(k, {})[tuple(rest)] = c
        return {k: ring.ctx.from_dict(d) for k, d in pieces.items()}

    def mod(self, p: int, values: Mapping[str, Rational]) -> ModularKahanMap:
        """This map with eps and every parameter fixed, reduced mod the prime p (the last few are kept)."""
        key = (p, tuple(sorted((k, str(v)) for k, v in values.items())))
        cache = self.__dict__.setdefault("_modular", {})
        if key not in cache:
            if len(cache) > 8:
                cache.clear()
            cache[key] = ModularKahanMap(self, values, p)
        return cache[key]

    @cached_property
    def explicit(self) -> tuple[tuple[flint.fmpz_mpoly, ...], flint.fmpz_mpoly]:
        """(N, Delta): f = N / Delta by Cramer's rule, with the gcd of all of N and Delta cancelled."""
        m, b = self.matrix
        delta, nums = cramer_polynomials(m, b)
        nums, delta = _cancel_common(nums, delta)
        sign = normalize_sign(delta, delta)[0]
        if sign != delta:
            delta, nums = -delta, [-p for p in nums]
        return tuple(nums), delta

    @property
    def numerators(self) -> tuple[flint.fmpz_mpoly, ...]:
        return self.explicit[0]

    @property
    def denominator(self) -> flint.fmpz_mpoly:
        """Delta(x, eps): the common denominator of f (det M up to a cancelled common factor)."""
        return self.explicit[1]

    def components(self) -> list[Frac]:
        """f_i = N_i / Delta, each in lowest terms."""
        nums, delta = self.explicit
        return [Frac(self.ring, p, delta) for p in nums]

    def _repr_markdown_(self) -> str:
        """x~ = N(x)/Delta(x) in LaTeX (term counts only for a large map): how Jupyter shows a Kahan map."""
        import sympy
        nums, delta = self.explicit
        head = f"**Kahan map of {self.field.name}** (eps = half the time step)"
        tilde = [rf"\tilde{{{latex(sympy.Symbol(v))}}}" for v in self.variables]
        if sum(len(p) for p in nums) + len(delta) > SHOWN_TERMS:
            return "\n".join([head, "", *(f"- ${t} = N_{i + 1}/\\Delta$: {len(p)} terms"
                                          for i, (t, p) in enumerate(zip(tilde, nums, strict=True))),
                              f"- $\\Delta$: {len(delta)} terms"])
        den = latex(poly_to_sympy(delta))
        return "\n\n".join([head, *(rf"$${t} = \frac{{{latex(poly_to_sympy(p))}}}{{{den}}}$$"
                                     for t, p in zip(tilde, nums, strict=True))])

    # ---- composition and iterates ---------------------------------------------------------------
    def negate_eps(self, p: flint.fmpz_mpoly) -> flint.fmpz_mpoly:
        return self.ring.substitute(p, {EPS: -self.ring.gen(EPS)})

    @cached_property
    def inverse_explicit(self) -> tuple[tuple[flint.fmpz_mpoly, ...], flint.fmpz_mpoly]:
        """(N(-eps), Delta(-eps)): the inverse map by reversibility (eq. "reversible"), to be checked."""
        nums, delta = self.explicit
        return tuple(self.negate_eps(p) for p in nums), self.negate_eps(delta)

    def equations_reversible(self) -> bool:
        """E(x~, x, -eps) = -E(x, x~, eps) for every equation: the symmetry behind f^-1(x, eps) = f(x, -eps)."""
        t = self.field.tilde_ring
        swap = {v: t.gen(w) for v, w in zip(self.variables, self.field.tilde_variables, strict=True)}
        swap.update({w: t.gen(v) for v, w in zip(self.variables, self.field.tilde_variables, strict=True)})
        swap[EPS] = -t.gen(EPS)
        return all(t.substitute(e, swap) == -e for e in self.equations)

    def pullback(self, h: Frac, power: int = 1) -> Frac:
        """h o f^power, in lowest terms; negative powers use f^-1(x, eps) = f(x, -eps)."""
        if h.ring != self.ring:
            raise ParseError(f"{h} is not in the ring {self.ring} of {self}")
        nums, delta = self.explicit if power >= 0 else self.inverse_explicit
        for _ in range(abs(power)):
            h = h.pullback(nums, delta, self.variables)
        return h

    def iterate(self, k: int, *, reduced: bool = True) -> tuple[tuple[flint.fmpz_mpoly, ...], flint.fmpz_mpoly]:
        """f^k as (numerators, common denominator); `reduced` cancels the common gcd of all of them."""
        if k == 0:
            return tuple(self.ring.gen(v) for v in self.variables), self.ring.constant(1)
        base = self.explicit if k > 0 else self.inverse_explicit
        nums, den = base
        for _ in range(abs(k) - 1):
            # f^(j+1) = f^j o f: pull numerators and the denominator of f^j back through f
            comp = [homogenized_compose(self.ring, p, self.variables, base[0], base[1]) for p in nums + (den,)]
            top = max(d for _, d in comp)
            polys = [q * base[1] ** (top - d) for q, d in comp]
            nums, den = tuple(polys[:-1]), polys[-1]
            if reduced:
                nums, den = _cancel_common(nums, den)
        return nums, den

    # ---- evaluation at points -------------------------------------------------------------------
    def step_exact(self, point: Mapping[str, Rational]) -> dict[str, flint.fmpq]:
        """One step x -> x~ at a rational point (every phase variable, eps and parameter given)."""
        m, b = self.matrix
        values = _complete(self.ring.names, point)
        q = [[self.ring.to_q(e)(*values) for e in row] for row in m]
        mat = flint.fmpq_mat(q)
        if mat.det() == 0:
            raise SingularPointError(
                f"the Kahan map of {self.field.name} is not defined at {dict(point)}: det M(x, eps) = 0 there")
        rhs = flint.fmpq_mat([[self.ring.to_q(e)(*values)] for e in b])
        sol = mat.solve(rhs)
        return {v: sol[i, 0] for i, v in enumerate(self.variables)}

    def orbit_exact(self, point: Mapping[str, Rational], steps: int) -> list[dict[str, flint.fmpq]]:
        """The exact orbit x, f(x), ..., f^steps(x) over Q; SingularPointError names the step that fails."""
        fixed = {k: to_fmpq(v) for k, v in point.items() if k not in self.variables}
        current = {k: to_fmpq(v) for k, v in point.items()}
        orbit = [{v: current[v] for v in self.variables}]
        guard = HeightGuard(steps)
        for i in range(steps):
            guard.observe(i, orbit[-1].values())
            try:
                new = self.step_exact(current)
            except SingularPointError as exc:
                raise SingularPointError(f"step {i + 1} of the orbit: {exc}") from None
            current = {**fixed, **new}
            orbit.append(new)
        return orbit


def commutator_at(f: KahanMap, g: KahanMap, point: Mapping[str, Rational]) -> dict[str, flint.fmpq]:
    """f(g(x)) - g(f(x)), exactly, at a rational point fixing x, eps and the parameters (the same for both maps)."""
    def step(kmap: KahanMap, at: Mapping[str, Rational]) -> dict[str, Rational]:
        return {**at, **kmap.step_exact(at)}
    fg, gf = step(f, step(g, point)), step(g, step(f, point))
    return {v: to_fmpq(fg[v]) - to_fmpq(gf[v]) for v in f.variables}


def _complete(names: Sequence[str], point: Mapping[str, Rational]) -> list[flint.fmpq]:
    missing = [n for n in names if n not in point]
    if missing:
        raise ParseError(f"the point must give a value for {missing}")
    return [to_fmpq(point[n]) for n in names]


def _cancel_common(nums: Sequence[flint.fmpz_mpoly], den: flint.fmpz_mpoly):
    g = den
    for p in nums:
        if g.is_one():
            break
        g = g.gcd(p)
    if g.is_one():
        return tuple(nums), den
    return tuple(p / g for p in nums), den / g


def _twice_polarization(t, num, x, xt, names, tilde_names) -> flint.fmpz_mpoly:
    """2 F^(x, x~) for F of degree <= 2: Q(x+x~) - Q(x) - Q(x~) + L(x) + L(x~) + 2c (homogeneous parts)."""
    idx = [t.index(n) for n in names]
    parts: dict[int, dict] = {0: {}, 1: {}, 2: {}}
    for m, c in num.to_dict().items():
        parts[sum(m[i] for i in idx)][m] = c
    q, lin, const = (t.ctx.from_dict(parts[k]) for k in (2, 1, 0))
    gens = list(t.gens())
    sum_args, tilde_args = list(gens), list(gens)
    for i, j, a, b in zip(idx, [t.index(n) for n in tilde_names], x, xt, strict=True):
        sum_args[i] = a + b
        tilde_args[i] = b
    q_sum = q.compose(*sum_args)
    q_t, lin_t = q.compose(*tilde_args), lin.compose(*tilde_args)
    return q_sum - q - q_t + lin + lin_t + 2 * const
