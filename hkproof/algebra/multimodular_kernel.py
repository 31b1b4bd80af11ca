"""The kernel vector of an integer matrix with a one-dimensional kernel over Q, by primes: kernels mod 62-bit primes
(nmod_mat), Chinese remaindering and rational reconstruction (hkproof.algebra.rational_lifting), then one exact
check M v = 0 over Z. Each prime is a short call that the command's budget can stop between; the fraction-free
nullspace over Z is one long call that it cannot (a 1 599 x 1 584 dense ansatz with 160-bit entries: 17-30 s).

>>> import random
>>> one_kernel_vector(flint.fmpz_mat([[1, 2, 3], [2, 4, 7]]), random.Random(1))
[2, -1, 0]
>>> one_kernel_vector(flint.fmpz_mat([[1, 0], [0, 1]]), random.Random(1)) is None
True
"""
from __future__ import annotations

import random

import flint

from hkproof.algebra.linalg import primitive_vector
from hkproof.algebra.modular import random_prime
from hkproof.algebra.rational_lifting import CoefficientLifter
from hkproof.budget import check

__all__ = ["MAX_PRIMES", "one_kernel_vector"]

MAX_PRIMES = 200            # 62-bit primes: coefficients of up to about 6 000 bits each in the kernel vector
RETRIES = 3                 # primes tried before a kernel of dimension > 1 mod p is believed


def one_kernel_vector(m: flint.fmpz_mat, rng: random.Random) -> list[flint.fmpz] | None:
    """The primitive integer vector spanning the kernel of m over Q (its first non-zero entry positive), or None when
    that kernel is not one-dimensional: 0 when some prime shows full column rank (exact: a rank mod p bounds the rank
    over Q from below), and > 1 when RETRIES primes all show a larger kernel. The vector returned satisfies m v = 0
    exactly."""
    lifter: CoefficientLifter[int] = CoefficientLifter()
    pivot: int | None = None
    wide = 0
    for _ in range(MAX_PRIMES):
        check("solving a dense ansatz by kernels mod primes")
        p = random_prime(rng)
        x, nullity = flint.nmod_mat(m, p).nullspace()
        if nullity == 0:
            return None
        if nullity > 1:
            wide += 1
            if wide >= RETRIES and pivot is None:
                return None
            continue
        column = [int(x[i, 0]) for i in range(x.nrows())]
        if pivot is None:
            pivot = next(i for i, v in enumerate(column) if v)
        if column[pivot] == 0:
            continue                    # an unlucky prime: the kernel mod p is not the reduction of the one over Q
        inverse = pow(column[pivot], -1, p)
        lifter.add({i: v * inverse % p for i, v in enumerate(column)}, p)
        if len(lifter.rationals) == len(column) and lifter.changed == 0:
            vector = primitive_vector([lifter.rationals[i] for i in range(len(column))])
            if _is_kernel_vector(m, vector):
                return vector
    return None


def _is_kernel_vector(m: flint.fmpz_mat, vector: list[flint.fmpz]) -> bool:
    """m v = 0 over Z, exactly."""
    product = m * flint.fmpz_mat([[v] for v in vector])
    return all(product[i, 0] == 0 for i in range(product.nrows()))
