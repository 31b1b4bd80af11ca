"""Scaling symmetries of a Kahan map: weights making eq. "Kahan gen" and a basis weighted homogeneous.

If x_i -> l^w(x_i) x_i, eps -> l^w(eps) eps, a -> l^w(a) a maps the field to itself (up to the time scale
carried by eps), then kernel coordinates and their relations (recipe (E)) are weighted homogeneous.  Parameters
whose weights are independent can then be set to 1 while sampling and restored afterwards.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import nullspace_q
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap

__all__ = ["scaling_weights", "Weights"]


@dataclass(frozen=True)
class Weights:
    """A basis of the weight vectors (one integer weight per ring name) and the names that may be set to 1."""

    names: tuple[str, ...]
    basis: tuple[tuple[flint.fmpq, ...], ...]
    normalized: tuple[str, ...]

    def of_monomial(self, exponents: dict[str, int]) -> list[flint.fmpq]:
        """The weight of a monomial under each basis vector."""
        return [sum((w[self.names.index(n)] * e for n, e in exponents.items()), flint.fmpq(0)) for w in self.basis]

    def of_frac(self, h: Frac) -> list[flint.fmpq]:
        """Weight of a weighted-homogeneous h = num/den (its first monomials)."""
        ring = h.ring
        num = dict(zip(ring.names, h.num.monoms()[0], strict=True))
        den = dict(zip(ring.names, h.den.monoms()[0], strict=True))
        return [a - b for a, b in zip(self.of_monomial(num), self.of_monomial(den), strict=True)]

    def restore(self, exponents: dict[str, int], offset: Sequence[flint.fmpq],
                target: Sequence[flint.fmpq]) -> dict[str, flint.fmpq] | None:
        """Exponents of the normalized names making a monomial (with `offset` added) have weight `target`."""
        if not self.normalized:
            return {}
        have = [a + b for a, b in zip(self.of_monomial(exponents), offset, strict=True)]
        rows = [[w[self.names.index(n)] for n in self.normalized] for w in self.basis]
        rhs = [t - h for t, h in zip(target, have, strict=True)]
        system = flint.fmpq_mat([r + [b] for r, b in zip(rows, rhs, strict=True)])
        if system.rank() != len(self.normalized):
            return None
        r, rank = system.rref()
        sol = {}
        for i in range(rank):
            j = next(j for j in range(len(self.normalized) + 1) if r[i, j] != 0)
            if j == len(self.normalized):
                return None
            sol[self.normalized[j]] = r[i, len(self.normalized)]
        return sol


    def restore_frac(self, h: Frac, weight: Sequence[flint.fmpq]) -> Frac | None:
        """h sampled with the normalized names set to 1, made weighted homogeneous of `weight` again (None if no
        integer exponents do it)."""
        if not self.normalized:
            return h
        ring = h.ring
        names = ring.names
        terms = []
        for which, poly in (("num", h.num), ("den", h.den)):
            for m, c in poly.to_dict().items():
                terms.append((which, {n: e for n, e in zip(names, m, strict=True) if e}, c))
        den_terms = [t for t in terms if t[0] == "den"]
        base = self.of_monomial(den_terms[0][1])
        targets = {"den": base, "num": [a + b for a, b in zip(base, weight, strict=True)]}
        extra = []
        for which, exps, _ in terms:
            e = self.restore(exps, [flint.fmpq(0)] * len(base), targets[which])
            if e is None or any(v.q != 1 for v in e.values()):
                return None
            extra.append(e)
        shift = {n: min(int(e.get(n, 0)) for e in extra) for n in self.normalized}
        data: dict[str, dict] = {"num": {}, "den": {}}
        for (which, exps, c), e in zip(terms, extra, strict=True):
            mono = [0] * len(names)
            for n, v in exps.items():
                mono[ring.index(n)] += v
            for n in self.normalized:
                mono[ring.index(n)] += int(e.get(n, 0)) - shift[n]
            data[which][tuple(mono)] = c
        return Frac(ring, ring.ctx.from_dict(data["num"]), ring.ctx.from_dict(data["den"]))


def _homogeneity_rows(ring_names: Sequence[str], h: flint.fmpz_mpoly) -> list[list[int]]:
    monos = h.monoms()
    return [[a - b for a, b in zip(m, monos[0], strict=True)] for m in monos[1:]]


def scaling_weights(kmap: KahanMap, functions: Sequence[Frac] = (), fixed: Sequence[str] = ()) -> Weights:
    """All weights under which the field (with eps of the weight of time) and `functions` are homogeneous,
    `fixed` names of weight 0; and a maximal set of eps and parameters that can be scaled to 1."""
    ring = kmap.ring
    names = ring.names
    rows: list[list[int]] = []
    for v, f in zip(kmap.variables, kmap.field.rhs, strict=True):
        rows += _homogeneity_rows(names, f.num) + _homogeneity_rows(names, f.den)
        if not f.num.is_zero():
            row = [a - b for a, b in zip(f.num.monoms()[0], f.den.monoms()[0], strict=True)]
            row[names.index(v)] -= 1
            row[names.index(EPS)] += 1
            rows.append(row)
    for h in functions:
        rows += _homogeneity_rows(names, h.num) + _homogeneity_rows(names, h.den)
    for n in fixed:
        rows.append([1 if m == n else 0 for m in names])
    basis = nullspace_q(rows) if rows else [[flint.fmpq(1 if i == j else 0) for i in range(len(names))]
                                            for j in range(len(names))]
    normalized: list[str] = []
    for n in (EPS,) + kmap.field.parameters:
        if n in fixed:
            continue
        trial = normalized + [n]
        if flint.fmpq_mat([[w[names.index(m)] for m in trial] for w in basis]).rank() == len(trial):
            normalized = trial
    return Weights(names, tuple(tuple(w) for w in basis), tuple(normalized))
