"""Seeded random rationals: the one sampler behind every random point, parameter value and line of hkproof.

Points are small rationals a/b, reproducible from a seed; every search that samples says which values it used.

>>> import random
>>> rng = random.Random(0)
>>> [str(random_rational(rng, 9)) for _ in range(3)]
['4/7', '-8/5', '1']
>>> all(random_rational(rng, 5) != 0 for _ in range(100))
True
"""
from __future__ import annotations

import random
from typing import Sequence

import flint

__all__ = ["random_point", "random_rational", "random_rationals"]


def random_rational(rng: random.Random, size: int = 9, *, denominator: int | None = None,
                    zero: bool = False) -> flint.fmpq:
    """a/b with 0 < |a| <= size (a = 0 allowed when `zero`) and 1 <= b <= `denominator` (default `size`)."""
    if zero:
        a = rng.randint(-size, size)
    else:
        a = rng.randrange(2 * size)
        a = a - size if a < size else a - size + 1
    return flint.fmpq(a, rng.randint(1, denominator or size))


def random_point(rng: random.Random, names: Sequence[str], size: int = 9, *, denominator: int | None = None,
                 zero: bool = False) -> dict[str, flint.fmpq]:
    """One random rational per name."""
    return {n: random_rational(rng, size, denominator=denominator, zero=zero) for n in names}


def random_rationals(rng: random.Random, count: int, size: int = 9, *, denominator: int | None = None,
                     zero: bool = False) -> list[flint.fmpq]:
    """`count` random rationals (a phase point, a direction)."""
    return [random_rational(rng, size, denominator=denominator, zero=zero) for _ in range(count)]
