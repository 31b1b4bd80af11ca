"""Univariate rational functions mod p from values: Thiele interpolation with early termination, and the linear
fit of a rational function of known degrees with some coefficients already known (FireFly's line solves).

>>> p = 101
>>> g = lambda t: (3 * t * t + 1) * pow(t + 2, -1, p) % p
>>> thiele = ThieleInterpolator(p)
>>> for t in range(1, 8):
...     thiele.add(t, g(t))
>>> thiele.terminated, thiele.fraction()
(True, ([51, 0, 52], [1, 51]))
"""
from __future__ import annotations

from collections.abc import Mapping, Sequence

import flint

from hkproof.errors import UnluckyPrimeError

__all__ = ["THIELE_AGREEMENTS", "ThieleInterpolator", "fit_lines"]

THIELE_AGREEMENTS = 2
"""Thiele interpolation stops when this many consecutive new points agree with the current interpolant."""


class ThieleInterpolator:
    """Thiele's continued fraction a_0 + (t - t_0)/(a_1 + (t - t_1)/(a_2 + ...)) through points added one at a time
    mod p, with early termination: `terminated` once THIELE_AGREEMENTS consecutive new points agree with it."""

    def __init__(self, p: int):
        self.p = p
        self.nodes: list[int] = []
        self.coefficients: list[int] = []
        self.agreements = 0

    @property
    def terminated(self) -> bool:
        return self.agreements >= THIELE_AGREEMENTS

    def value(self, t: int) -> int | None:
        """The interpolant at t (None at a pole of a partial fraction)."""
        top = self._projective(t)
        return None if top is None else top[0] * pow(top[1], -1, self.p) % self.p

    def _projective(self, t: int) -> tuple[int, int] | None:
        """The interpolant at t as (num, den) mod p, den != 0, evaluated bottom-up without a division: v = a +
        (t - t_k)/v' is num = a num' + (t - t_k) den', den = num' (None where a partial fraction v' vanishes)."""
        p = self.p
        if not self.coefficients:
            return None
        num, den = self.coefficients[-1], 1
        for a, node in zip(reversed(self.coefficients[:-1]), reversed(self.nodes[:-1])):
            if num == 0:
                return None
            num, den = (a * num + (t - node) * den) % p, num
        return num, den

    def add(self, t: int, y: int) -> None:
        """Take the value y at a new node t: count an agreement, or extend the continued fraction (a point where the
        reciprocal differences divide by zero is skipped). The comparison and the reciprocal differences r <- (t -
        t_k)/(r - a_k) are kept as fractions mod p, so that each new node costs one modular inverse, not one per
        level (they were most of the time of sparse reconstruction's line solves)."""
        p = self.p
        r = y % p
        top = self._projective(t)
        if top is not None and top[0] == r * top[1] % p:
            self.agreements += 1
            return
        self.agreements = 0
        num, den = r, 1
        for a, node in zip(self.coefficients, self.nodes):
            difference = (num - a * den) % p
            if difference == 0:
                return
            num, den = (t - node) * den % p, difference
        self.nodes.append(t % p)
        self.coefficients.append(num * pow(den, -1, p) % p)

    def fraction(self) -> tuple[list[int], list[int]]:
        """(numerator, denominator) coefficient lists, lowest degree first, coprime, the denominator normalized to
        constant term 1 when that is non-zero (otherwise to a monic leading coefficient)."""
        p = self.p
        num, den = flint.nmod_poly([self.coefficients[-1]], p), flint.nmod_poly([1], p)
        for a, node in zip(reversed(self.coefficients[:-1]), reversed(self.nodes[:-1])):
            num, den = a * num + flint.nmod_poly([-node, 1], p) * den, num
        g = num.gcd(den)
        num, den = num // g, den // g
        lead = int(den.coeffs()[0]) or int(den.coeffs()[-1])
        inv = pow(lead, -1, p)
        return [int(c) * inv % p for c in num.coeffs()] or [0], [int(c) * inv % p for c in den.coeffs()]


def fit_lines(nodes: Sequence[Sequence[int]], values: Sequence[Sequence[int]], p: int, unknown_num: Sequence[int],
              unknown_den: Sequence[int], known_num: Sequence[Mapping[int, int]],
              known_den: Sequence[Mapping[int, int]]) -> list[list[int]]:
    """For each line, the unknown t-coefficients of N/D = values at its nodes, where N = sum n_r t^r,
    D = sum d_r t^r and the coefficients in known_num / known_den are given (FireFly's linear system along a line,
    one equation N(t) - y D(t) = 0 per node). Returns, per line, the unknown n_r then the unknown d_r.

    Lines with the same nodes and a known denominator share one matrix (one solve for all of them).
    UnluckyPrimeError when a system is singular mod p.

    >>> fit_lines([[1, 2, 3]], [[2, 3, 4]], 7, [0, 1, 2], [], [{}], [{0: 1}])
    [[1, 1, 0]]
    """
    top = max([0, *unknown_num, *unknown_den, *(r for k in (*known_num, *known_den) for r in k)])
    tables: dict[tuple[int, ...], list[list[int]]] = {}

    def powers(ts: Sequence[int]) -> list[list[int]]:
        key = tuple(ts)
        if key not in tables:
            rows = []
            for t in ts:
                row = [1]
                for _ in range(top):
                    row.append(row[-1] * t % p)
                rows.append(row)
            tables[key] = rows
        return tables[key]

    def right_side(line: int) -> list[int]:
        return [(y * sum(c * pw[r] for r, c in known_den[line].items())
                 - sum(c * pw[r] for r, c in known_num[line].items())) % p
                for y, pw in zip(values[line], powers(nodes[line]))]

    def solve(rows: list[list[int]], columns: list[list[int]]) -> list[list[int]]:
        try:
            sol = flint.nmod_mat(rows, p).solve(flint.nmod_mat([list(r) for r in zip(*columns)], p))
        except ZeroDivisionError:
            raise UnluckyPrimeError(f"the rational fit along a line is singular mod p = {p} (the line meets a "
                                    f"common factor, or the degrees drop mod p)") from None
        table = sol.tolist()
        return [[int(table[i][k]) for i in range(len(rows))] for k in range(len(columns))]

    out: list[list[int] | None] = [None] * len(nodes)
    if not unknown_den:
        groups: dict[tuple[int, ...], list[int]] = {}
        for line, ts in enumerate(nodes):
            groups.setdefault(tuple(ts), []).append(line)
        for ts, lines in groups.items():
            rows = [[pw[r] for r in unknown_num] for pw in powers(ts)]
            for line, sol in zip(lines, solve(rows, [right_side(line) for line in lines])):
                out[line] = sol
    else:
        for line, ts in enumerate(nodes):
            rows = [[pw[r] for r in unknown_num] + [-y * pw[r] % p for r in unknown_den]
                    for y, pw in zip(values[line], powers(ts))]
            out[line] = solve(rows, [right_side(line)])[0]
    return [sol for sol in out if sol is not None]
