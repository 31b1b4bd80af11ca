"""From residues modulo several primes to rationals: Chinese remaindering and Wang's rational number reconstruction.

>>> rational_reconstruction(crt(2, 3, 3, 5), 15)         # 1/2 is 2 mod 3 and 3 mod 5
1/2
>>> lift, p, q = CoefficientLifter(), 1000003, 1000033
>>> lift.add({"a": -7 * pow(3, -1, p) % p}, p), lift.add({"a": -7 * pow(3, -1, q) % q}, q)
((['a'], []), (['a'], []))
>>> lift.rationals
{'a': -7/3}
"""
from __future__ import annotations

import math
from collections.abc import Hashable, Mapping

import flint

__all__ = ["CoefficientLifter", "crt", "rational_reconstruction"]


def crt(a: int, m: int, b: int, n: int) -> int:
    """The x mod m*n with x = a mod m and x = b mod n (coprime moduli; Chinese remaindering)."""
    return (a + m * ((b - a) * pow(m, -1, n) % n)) % (m * n)


def rational_reconstruction(a: int, m: int) -> flint.fmpq | None:
    """The fraction u/v = a mod m with |u|, v <= sqrt(m/2) and gcd(u, v) = 1 (Wang's algorithm: the extended
    Euclidean algorithm on (m, a) stopped at the first remainder below the bound), or None when there is none."""
    bound = math.isqrt(m // 2)
    r0, r1, s0, s1 = m, a % m, 0, 1
    while r1 > bound:
        q = r0 // r1
        r0, r1, s0, s1 = r1, r0 - q * r1, s1, s0 - q * s1
    if s1 == 0 or abs(s1) > bound or math.gcd(r1, s1) != 1:
        return None
    return flint.fmpq(r1, s1) if s1 > 0 else flint.fmpq(-r1, -s1)


class CoefficientLifter:
    """Residues of named coefficients over a growing product of primes, and their rational reconstructions; a
    rational is kept while each new prime agrees with it (stable), and rebuilt from the CRT image when one does not."""

    def __init__(self) -> None:
        self.modulus = 1
        self.images: dict[Hashable, int] = {}
        self.rationals: dict[Hashable, flint.fmpq] = {}
        self.primes: list[int] = []

    def add(self, residues: Mapping[Hashable, int], p: int) -> tuple[list[Hashable], list[Hashable]]:
        """Take the residues mod a new prime p (every coefficient named, the same names each time); returns the
        coefficients reconstructed now and those still unknown (their height is beyond the modulus so far)."""
        if self.primes and residues.keys() != self.images.keys():
            raise ValueError("every prime must give residues of the same coefficients")
        for key, r in residues.items():
            self.images[key] = crt(self.images.get(key, 0), self.modulus, r, p)
            q = self.rationals.get(key)
            if q is not None and int(q.p) % p != r * int(q.q) % p:
                del self.rationals[key]
        self.modulus *= p
        self.primes.append(p)
        for key in residues:
            if key not in self.rationals:
                q = rational_reconstruction(self.images[key], self.modulus)
                if q is not None:
                    self.rationals[key] = q
        missing = [k for k in residues if k not in self.rationals]
        return [k for k in residues if k in self.rationals], missing
