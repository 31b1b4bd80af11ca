"""Signed permutations of the phase variables, with a permutation of the parameters, that a quadratic field is
equivariant under: sigma(x_v) = s_v x_pi(v), sigma(a_j) = a_rho(j), eps fixed, and sigma(F_v) = s_v F_pi(v).

Kahan's scheme commutes with every linear change of the phase variables that fixes eps, so such a sigma is a symmetry
of the Kahan map as well: sigma(f_v) = s_v f_pi(v) (`SignedPermutation.commutes` checks it on the map itself,
exactly). A basis carried by sigma has sigma's image of the kernel as kernel: the rows of one block of a system solved
together give those of its images (hk.block_system.BlockSymmetry), as the index shift of the Clebsch flows does in the
proof of the second flow's bases.

>>> from hkproof.dynamics.field import QuadraticField
>>> from hkproof.dynamics.kahan import KahanMap
>>> euler = QuadraticField("euler", ("x", "y", "z"), ("a", "b", "c"),
...                        ("(b - c)*y*z", "(c - a)*z*x", "(a - b)*x*y"))
>>> symmetries = field_symmetries(euler)
>>> len(symmetries), str(symmetries[0])        # sign changes of two axes, and the 6 axis permutations with a, b, c
(23, 'x -> x, y -> -y, z -> -z')
>>> swap = next(s for s in symmetries if s.parameters == (("b", "c"), ("c", "b")) and s.variables[0][2] < 0)
>>> str(swap), swap.commutes(KahanMap(euler))
('x -> -x, y -> z, z -> y, b -> c, c -> b', True)
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Iterator, Sequence

import flint

from hkproof.algebra.fraction import Frac, normalize_sign
from hkproof.algebra.ring import Ring
from hkproof.budget import check
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap

__all__ = ["MAX_PERMUTED", "SignedPermutation", "field_symmetries"]

MAX_PERMUTED = 8
"""Phase variables (and, separately, parameters) above which no symmetry is searched (n! permutations of each;
the pairs are screened by the supports first, and the search checks the active budget)."""


@dataclass(frozen=True)
class SignedPermutation:
    """sigma(x_v) = sign * x_image for each phase variable, sigma(a) = a_image for each parameter moved."""

    variables: tuple[tuple[str, str, int], ...]      # (name, image, sign +-1)
    parameters: tuple[tuple[str, str], ...] = ()     # (name, image), the moved ones

    def __str__(self) -> str:
        moves = [f"{v} -> {'-' if s < 0 else ''}{w}" for v, w, s in self.variables]
        return ", ".join(moves + [f"{a} -> {b}" for a, b in self.parameters])

    def _images(self, ring: Ring) -> dict[str, flint.fmpz_mpoly]:
        out = {v: ring.gen(w) * s for v, w, s in self.variables}
        out.update({a: ring.gen(b) for a, b in self.parameters if a in ring.names})
        return out

    def apply_poly(self, ring: Ring, p: flint.fmpz_mpoly) -> flint.fmpz_mpoly:
        """sigma(p) for a polynomial of `ring` (one compose)."""
        return ring.substitute(p, self._images(ring))

    def apply(self, h: Frac) -> Frac:
        """sigma(h) (a relabeling with signs keeps lowest terms; the sign is made canonical again)."""
        return Frac(h.ring, *normalize_sign(self.apply_poly(h.ring, h.num), self.apply_poly(h.ring, h.den)),
                    reduced=True)

    def commutes(self, kmap: KahanMap) -> bool:
        """sigma(f_v) = s_v f_pi(v) for every component of the Kahan map, exactly: sigma(Delta) = Delta and
        sigma(N_v) = s_v N_pi(v) (sufficient), else the components compared in lowest terms."""
        ring = kmap.ring
        nums, delta = kmap.explicit
        index = {v: k for k, v in enumerate(kmap.variables)}
        if self.apply_poly(ring, delta) == delta and all(
                self.apply_poly(ring, nums[index[v]]) == nums[index[w]] * s for v, w, s in self.variables):
            return True
        comps = kmap.components()
        return all(self.apply(comps[index[v]]) == comps[index[w]] * s for v, w, s in self.variables)


def _coefficients(field: QuadraticField) -> list[dict[tuple[int, ...], Frac]]:
    """Each component as {phase exponents: coefficient in Q(parameters)}."""
    ring = field.ring
    phase = [ring.index(v) for v in field.variables]
    out = []
    for f in field.rhs:
        parts: dict[tuple[int, ...], dict] = {}
        for m, c in f.num.to_dict().items():
            key = tuple(m[i] for i in phase)
            rest = tuple(0 if i in phase else e for i, e in enumerate(m))
            parts.setdefault(key, {})[rest] = c
        out.append({key: Frac(ring, ring.ctx.from_dict(d), f.den) for key, d in parts.items()})
    return out


def _moved(e: tuple[int, ...], pi: Sequence[int]) -> tuple[int, ...]:
    out = [0] * len(e)
    for i, k in enumerate(e):
        out[pi[i]] += k
    return tuple(out)


def _supports_match(supports: Sequence[frozenset], pi: Sequence[int]) -> bool:
    return all(frozenset(_moved(e, pi) for e in supports[v]) == supports[pi[v]] for v in range(len(pi)))


def _signs(equations: Sequence[tuple[int, tuple[int, ...], int]], n: int) -> Iterator[tuple[int, ...]]:
    """Every s in {+1, -1}^n with s_v * prod s_i^e_i = sign for each (v, e, sign)."""
    for bits in itertools.product((1, -1), repeat=n):
        if all(bits[v] * _power(bits, e) == sign for v, e, sign in equations):
            yield bits


def _power(bits: Sequence[int], e: Sequence[int]) -> int:
    out = 1
    for b, k in zip(bits, e, strict=True):
        if k % 2:
            out *= b
    return out


def _sign_equations(coefficients: Sequence[dict[tuple[int, ...], Frac]], pi: Sequence[int],
                    relabel: SignedPermutation) -> list[tuple[int, tuple[int, ...], int]] | None:
    """(v, e, +-1) for each term: the parameters relabeled carry its coefficient to +- that of x^pi(e) in F_pi(v);
    None when one is carried to neither."""
    out = []
    for v, terms in enumerate(coefficients):
        for e, c in terms.items():
            image, target = relabel.apply(c), coefficients[pi[v]][_moved(e, pi)]
            if image == target:
                out.append((v, e, 1))
            elif image == -target:
                out.append((v, e, -1))
            else:
                return None
    return out


def field_symmetries(field: QuadraticField) -> list[SignedPermutation]:
    """The signed permutations of the phase variables with a permutation of the parameters (eps fixed) that the
    field is equivariant under, the identity left out; none searched above MAX_PERMUTED variables or parameters.
    Each is checked exactly on the field's components."""
    n, params = len(field.variables), list(field.parameters)
    if n > MAX_PERMUTED or len(params) > MAX_PERMUTED:
        return []
    coefficients = _coefficients(field)
    supports = [frozenset(c) for c in coefficients]
    identity = tuple(range(n))
    out: list[SignedPermutation] = []
    for pi in itertools.permutations(range(n)):
        if not _supports_match(supports, pi):
            continue
        for rho in itertools.permutations(range(len(params))):
            check("looking for symmetries of the field (signed permutations)")
            moved = tuple((params[j], params[rho[j]]) for j in range(len(params)) if rho[j] != j)
            equations = _sign_equations(coefficients, pi, SignedPermutation((), moved))
            if equations is None:
                continue
            for bits in _signs(equations, n):
                if pi == identity and not moved and all(b == 1 for b in bits):
                    continue
                sigma = SignedPermutation(tuple((field.variables[v], field.variables[pi[v]], bits[v])
                                                for v in range(n)), moved)
                if all(sigma.apply(f) == field.rhs[pi[v]] * bits[v] for v, f in enumerate(field.rhs)):
                    out.append(sigma)
    return out
