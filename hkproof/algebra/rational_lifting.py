"""From residues modulo several primes to rationals: Chinese remaindering and Wang's rational number reconstruction.

>>> rational_reconstruction(crt(2, 3, 3, 5), 15)         # 1/2 is 2 mod 3 and 3 mod 5
1/2
>>> lift, p, q = CoefficientLifter(), 2 ** 61 - 1, 2 ** 31 - 1
>>> lift.add({"a": -7 * pow(3, -1, p) % p}, p), lift.add({"a": -7 * pow(3, -1, q) % q}, q)
((['a'], []), (['a'], []))
>>> lift.rationals
{'a': -7/3}
"""
from __future__ import annotations

import math
from collections.abc import Hashable, Mapping
from typing import Generic, TypeVar

import flint

__all__ = ["SLACK_BITS", "CoefficientLifter", "crt", "rational_reconstruction"]

SLACK_BITS = 20
"""The lifter accepts a reconstructed u/v only when |u| v < modulus / 2^(1 + SLACK_BITS)."""


def crt(a: int, m: int, b: int, n: int) -> int:
    """The x mod m*n with x = a mod m and x = b mod n (coprime moduli; Chinese remaindering)."""
    return (a + m * ((b - a) * pow(m, -1, n) % n)) % (m * n)


def rational_reconstruction(a: int, m: int, slack_bits: int = 0) -> flint.fmpq | None:
    """The fraction u/v = a mod m with |u|, v <= sqrt(m/2) and gcd(u, v) = 1 (Wang's algorithm: the extended
    Euclidean algorithm on (m, a) stopped at the first remainder below the bound), or None when there is none; with
    slack_bits, also None unless |u| v < m / 2^(1 + slack_bits) (a residue of a larger fraction passes Wang's test
    with a fair chance, this one with a chance about 2^-slack_bits)."""
    bound = math.isqrt(m // 2)
    r0, r1, s0, s1 = m, a % m, 0, 1
    while r1 > bound:
        q = r0 // r1
        r0, r1, s0, s1 = r1, r0 - q * r1, s1, s0 - q * s1
    if s1 == 0 or abs(s1) > bound or math.gcd(r1, s1) != 1 or (r1 * abs(s1)) << (1 + slack_bits) >= m:
        return None
    return flint.fmpq(r1, s1) if s1 > 0 else flint.fmpq(-r1, -s1)


Key = TypeVar("Key", bound=Hashable)


class CoefficientLifter(Generic[Key]):
    """Residues of named coefficients over a growing product of primes, and their rational reconstructions (Wang's,
    with SLACK_BITS to spare); a rational is kept while each new prime agrees with it (stable), and rebuilt from the
    CRT image when one does not. `changed` counts the rationals the last prime dropped or built."""

    def __init__(self) -> None:
        self.changed = 0
        self.modulus = 1
        self.images: dict[Key, int] = {}
        self.rationals: dict[Key, flint.fmpq] = {}
        self.primes: list[int] = []

    def add(self, residues: Mapping[Key, int], p: int) -> tuple[list[Key], list[Key]]:
        """Take the residues mod a new prime p (every coefficient named, the same names each time); returns the
        coefficients reconstructed now and those still unknown (their height is beyond the modulus so far)."""
        if self.primes and residues.keys() != self.images.keys():
            raise ValueError("every prime must give residues of the same coefficients")
        self.changed = 0
        for key, r in residues.items():
            self.images[key] = crt(self.images.get(key, 0), self.modulus, r, p)
            q = self.rationals.get(key)
            if q is not None and int(q.p) % p != r * int(q.q) % p:
                del self.rationals[key]
                self.changed += 1
        self.modulus *= p
        self.primes.append(p)
        for key in residues:
            if key not in self.rationals:
                q = rational_reconstruction(self.images[key], self.modulus, SLACK_BITS)
                if q is not None:
                    self.rationals[key] = q
                    self.changed += 1
        missing = [k for k in residues if k not in self.rationals]
        return [k for k in residues if k in self.rationals], missing
