"""What a shift does to the homogeneous pieces along a line (Cuyt–Lee): the t-coefficients of P_k(t z + s).

Along x = t z + s the coefficient of t^r of a rational function's numerator is sum_{k >= r} [t^r] P_k(t z + s): the
homogeneous piece P_r itself plus contributions of the higher pieces. Once those are known, their contributions are
subtracted and P_r is interpolated on its own sparse support. [t^r] P_k(t z + s) is the homogeneous part of degree r
of P_k(z + s), so one FLINT polynomial, the sum of P_k(z + s) over the pieces solved so far, holds every contribution
(compact, in C: FLINT packs a term in a few machine words, where a Python dict of exponent tuples takes about 250
bytes), and a graded monomial order keeps each degree's terms together.

>>> moved = ShiftedPieces(2, [0, 5], 101)
>>> moved.add({(2, 1): 1})
>>> sorted(moved.part(2)), sorted(moved.part(3))
([((2, 0), 5)], [((2, 1), 1)])
"""
from __future__ import annotations

import math
import sys
from collections.abc import Iterator, Mapping, Sequence

import flint

from hkproof import budget
from hkproof.errors import ResourceLimitError

__all__ = ["ShiftedPieces"]


CHUNK_TERMS = 1 << 21
"""Terms of expansion composed at a time (a budget check between chunks)."""


class ShiftedPieces:
    """sum_k P_k(z + s) mod p over the homogeneous pieces added; its degree-r part is sum_k [t^r] P_k(t z + s).

    `limit` bounds the terms kept: a piece whose expansion could pass it raises ResourceLimitError before it is
    composed (the bound: sum over its terms of prod (e_i + 1) over the shifted variables, at most the number of
    monomials of its degree); the active budget is checked between chunks of the composition."""

    def __init__(self, n: int, shift: Sequence[int], p: int, limit: int = sys.maxsize):
        self.p, self.limit = p, limit
        self.ctx = flint.nmod_mpoly_ctx.get(tuple(f"z{i}" for i in range(n)), p, "deglex")  # type: ignore[call-arg, arg-type]  # flint's stubs lag the API
        self._shifted = [i for i, s in enumerate(shift) if s % p]
        self._moved = [g + (s % p) if s % p else g for g, s in zip(self.ctx.gens(), shift, strict=True)]
        self.total = self.ctx.from_dict({})

    def __len__(self) -> int:
        return len(self.total)

    def add(self, piece: Mapping[tuple[int, ...], int]) -> None:
        """Add P(z + s) for a piece P given as {exponents: coefficient} (FLINT compositions mod p, by chunks)."""
        terms = [(e, c % self.p) for e, c in piece.items() if c % self.p]
        if not terms:
            return
        sizes = [math.prod(e[i] + 1 for i in self._shifted) for e, _ in terms]
        degree = sum(terms[0][0])
        bound = min(sum(sizes), math.comb(degree + len(self._moved), degree))
        if len(self.total) + bound > self.limit:
            raise ResourceLimitError(
                f"the shift's contributions to the lower t-coefficients could reach {len(self.total) + bound} terms "
                f"(limit {self.limit}): the function is too large for this machine's memory with this shift",
                limit=f"{self.limit} shifted terms per reconstruction",
                raise_with="no option raises it; fixing parameters makes the reconstruction smaller")
        start = done = 0
        for stop in range(1, len(terms) + 1):
            done += sizes[stop - 1]
            if done >= CHUNK_TERMS or stop == len(terms):
                if start:
                    budget.check("expanding a shifted homogeneous piece")
                self.total += self.ctx.from_dict(dict(terms[start:stop])).compose(*self._moved)
                start, done = stop, 0

    def part(self, r: int) -> Iterator[tuple[tuple[int, ...], int]]:
        """The terms of total degree r, as (exponents, coefficient): a run of the graded order, found by bisection."""
        total = self.total
        for i in range(self._first_below(r + 1), self._first_below(r)):
            yield total.monomial(i), int(total.coefficient(i))

    def _first_below(self, r: int) -> int:
        """The first index whose term has total degree < r (terms are in descending graded order)."""
        lo, hi = 0, len(self.total)
        while lo < hi:
            mid = (lo + hi) // 2
            if sum(self.total.monomial(mid)) >= r:
                lo = mid + 1
            else:
                hi = mid
        return lo
