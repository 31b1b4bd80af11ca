"""The kernel vector by primes (hkproof.algebra.multimodular_kernel) against FLINT's fraction-free nullspace over Z,
on matrices with a planted kernel; kernels of other dimensions give None; the budget stops it between primes."""
from __future__ import annotations

import random

import flint
import pytest

from hkproof.algebra.multimodular_kernel import one_kernel_vector
from hkproof.budget import Budget
from hkproof.errors import BudgetExhausted


def _planted(rng: random.Random, rows: int, cols: int, bits: int, nullity: int = 1) -> flint.fmpz_mat:
    """A rows x cols integer matrix with entries of about `bits` bits whose kernel over Q has dimension `nullity`:
    random rows orthogonal to `nullity` random vectors of `bits`-bit entries (made integral by clearing)."""
    kernel = [[rng.getrandbits(bits) - (1 << (bits - 1)) for _ in range(cols)] for _ in range(nullity)]
    basis = flint.fmpq_mat(kernel).transpose()                       # cols x nullity
    out = []
    for _ in range(rows):
        row = [flint.fmpq(rng.getrandbits(bits)) for _ in range(cols - nullity)]
        # solve the last `nullity` entries so that row . kernel_k = 0 for each k
        a = flint.fmpq_mat([[basis[cols - nullity + j, k] for j in range(nullity)] for k in range(nullity)])
        b = flint.fmpq_mat([[-sum((row[i] * basis[i, k] for i in range(cols - nullity)), flint.fmpq(0))]
                            for k in range(nullity)])
        tail = a.solve(b)
        full = row + [tail[j, 0] for j in range(nullity)]
        den = flint.fmpz(1)
        for v in full:
            den = den.lcm(v.q)
        out.append([int(v * den) for v in full])
    return flint.fmpz_mat(out)


def _flint_vector(m: flint.fmpz_mat) -> list[flint.fmpz]:
    x, nullity = m.nullspace()
    assert nullity == 1
    column = [x[i, 0] for i in range(x.nrows())]
    g = flint.fmpz(0)
    for v in column:
        g = g.gcd(v)
    sign = 1 if next(v for v in column if v) > 0 else -1
    return [sign * (v // g) for v in column]


@pytest.mark.parametrize("rows, cols, bits", [(12, 10, 8), (40, 30, 64), (60, 45, 200)])
def test_the_vector_by_primes_is_flints_nullspace(rows, cols, bits):
    """200-bit kernel entries need several 62-bit primes; the answer is FLINT's, exactly."""
    m = _planted(random.Random(bits), rows, cols, bits)
    assert one_kernel_vector(m, random.Random(1)) == _flint_vector(m)


@pytest.mark.parametrize("nullity", [0, 2])
def test_other_kernel_dimensions_give_none(nullity):
    rng = random.Random(5)
    m = flint.fmpz_mat([[rng.getrandbits(30) for _ in range(8)] for _ in range(8)]) if nullity == 0 else \
        _planted(rng, 12, 10, 20, nullity)
    assert one_kernel_vector(m, random.Random(1)) is None


def test_the_budget_stops_it_between_primes():
    m = _planted(random.Random(3), 20, 15, 40)
    with Budget(0.0).active(), pytest.raises(BudgetExhausted):
        one_kernel_vector(m, random.Random(1))
