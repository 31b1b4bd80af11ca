"""One contract for every reconstruction algorithm behind hkproof.algebra.reconstruction (issue 39): a table of black
boxes, each a known rational function with integer coefficients (zero, a constant, one variable, a monomial
denominator, a pole on a coordinate hyperplane, several functions at once), rebuilt by each method and compared with
the truth exactly in lowest terms; a black box that is not a fixed rational function is never returned as one."""
from __future__ import annotations

import random
from collections.abc import Sequence

import pytest
import sympy

from hkproof.algebra.reconstruction import Rebuilt, reconstruct
from hkproof.algebra.ring import get_ring
from hkproof.errors import HKProofError, ResourceLimitError

X = sympy.symbols("x0:4")
TABLE = {
    "zero": ["0"],
    "a constant": ["-7/3"],
    "one variable": ["(x0 + 2)/(3*x0 - 1)"],
    "a monomial denominator": ["(x0**2 - 5*x1*x2 + 1)/(4*x0*x1**2)"],
    "a pole on a coordinate hyperplane": ["(x1 + x2**2)/(x2*(1 + x0*x1))"],
    "a polynomial": ["2*x0**3 - x1*x2 + 7*x3 - 1/2"],
    "several at once": ["x0/(1 + x1)", "(x2 - x3)**2/5", "1/(x0*x1 + x2*x3 + 1)"],
}
METHODS = ("sparse", "dense")


class SympyBox:
    """Values mod p of sympy rational functions (the truth, computed apart from hkproof): numerator and denominator as
    sympy's dicts of exponents and rational coefficients, evaluated mod p."""

    def __init__(self, texts: Sequence[str], n: int):
        self.parts = [[sympy.Poly(part, *X[:n]).as_dict() for part in sympy.fraction(sympy.cancel(sympy.sympify(t)))]
                      for t in texts]

    @staticmethod
    def _mod(poly: dict, x: Sequence[int], p: int) -> int:
        total = 0
        for m, c in poly.items():
            c = sympy.Rational(c)
            term = int(c.p) * pow(int(c.q), -1, p)
            for xi, e in zip(x, m):
                term = term * pow(xi, e, p) % p
            total += term
        return total % p

    def __call__(self, p: int, points: Sequence[Sequence[int]]) -> list[list[int] | None]:
        out: list[list[int] | None] = []
        for x in points:
            values: list[int] | None = []
            for num, den in self.parts:
                d = self._mod(den, x, p)
                if d == 0:
                    values = None
                    break
                values.append(self._mod(num, x, p) * pow(d, -1, p) % p)
            out.append(values)
        return out


def check_reconstruction(rebuilt: Sequence[Rebuilt], texts: Sequence[str], n: int) -> None:
    """Each rebuilt function equals its truth exactly (as rational functions), and is normalized as Rebuilt says."""
    ring = get_ring(tuple(str(v) for v in X[:n]))
    names = [str(v) for v in X[:n]]
    assert len(rebuilt) == len(texts)
    for r, t in zip(rebuilt, texts):
        truth = sympy.cancel(sympy.sympify(t))
        mine = sympy.sympify(str(r.to_frac(ring, names)))
        assert sympy.simplify(mine - truth) == 0, (t, str(r.to_frac(ring, names)))
        top = max(r.denominator, key=lambda m: (sum(m), m))
        assert r.denominator[top] > 0


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("case", TABLE)
def test_every_method_rebuilds_every_black_box_of_the_table(method, case):
    texts = TABLE[case]
    n = 4
    rebuilt = reconstruct(SympyBox(texts, n), n, len(texts), method=method, rng=random.Random(11))
    check_reconstruction(rebuilt, texts, n)


@pytest.mark.parametrize("method", METHODS)
def test_a_box_that_is_no_fixed_rational_function_is_not_returned(method):
    """Values that change from prime to prime (a 'function' that is x0 mod one prime and x0 + 1 mod the next) never
    come back as a rational function: the stability over primes or the fresh-prime check refuses them."""
    primes_seen: list[int] = []

    def box(p: int, points: Sequence[Sequence[int]]) -> list[list[int] | None]:
        if p not in primes_seen:
            primes_seen.append(p)
        shift = primes_seen.index(p) % 2
        return [[(x[0] + shift) % p] for x in points]
    with pytest.raises((HKProofError, ResourceLimitError)):
        reconstruct(box, 2, 1, method=method, rng=random.Random(3))


def test_an_unknown_method_is_refused():
    with pytest.raises(HKProofError, match="no reconstruction method"):
        reconstruct(SympyBox(["x0"], 1), 1, 1, method="guess", rng=random.Random(1))
