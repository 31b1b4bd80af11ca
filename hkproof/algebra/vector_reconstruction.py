"""Several small rational functions of a few variables, rebuilt over Q from values mod primes at shared points.

Where many functions come out of one costly computation (a relation's coefficients at given eps and parameters),
each probe yields all of them at once, so they are rebuilt on the same points: the degrees of each along a random
line (Thiele, with early termination), then per function the dense ansatz g Q - P = 0 of those total degrees solved
mod p (normalized by the first monomial of Q that is not zero), primes until Wang's reconstruction is stable for every
coefficient, and a check at fresh points modulo a fresh prime. For a few variables and low degrees this needs far
fewer probes than one sparse reconstruction per function (hkproof.algebra.functional_reconstruction).

>>> def box(p, t):                        # g1 = (x + 2 y)/(1 + x y), g2 = y/3
...     x, y = t
...     d = (1 + x * y) % p
...     return None if d == 0 else [(x + 2 * y) * pow(d, -1, p) % p, y * pow(3, -1, p) % p]
>>> g1, g2 = reconstruct_vector(box, 2, 2, rng=random.Random(1))
>>> sorted(g1[0].items()), sorted(g1[1].items()), sorted(g2[0].items()), sorted(g2[1].items())
([((0, 1), 2), ((1, 0), 1)], [((0, 0), 1), ((1, 1), 1)], [((0, 1), 1)], [((0, 0), 3)])
"""
from __future__ import annotations

import math
import random
from collections.abc import Callable, Sequence

from hkproof import budget
from hkproof.algebra.modular import polynomial_mod_p, random_prime, rational_fit_mod_p
from hkproof.algebra.monomials import Exponents, exponents_upto
from hkproof.algebra.rational_lifting import CoefficientLifter
from hkproof.algebra.univariate_rational import ThieleInterpolator
from hkproof.errors import HKProofError, ResourceLimitError

__all__ = ["Fraction", "VectorBox", "reconstruct_vector"]

VectorBox = Callable[[int, Sequence[int]], "list[int] | None"]
"""box(p, point) -> the values mod p of every function at the point, None where one is undefined."""
Fraction = tuple[dict[Exponents, int], dict[Exponents, int]]
"""(numerator, denominator) with integer coefficients (primitive, the denominator's first monomial positive)."""

CHECKS = 4


def _probe(box: VectorBox, p: int, point: Sequence[int], count: int) -> list[int] | None:
    budget.check("probing a small vector of functions mod p")
    values = box(p, point)
    if values is not None and len(values) != count:
        raise HKProofError(f"the black box gave {len(values)} values, {count} were expected")
    return values


def _line_degrees(box: VectorBox, p: int, n: int, count: int, rng: random.Random,
                  max_degree: int) -> list[tuple[int, int]]:
    """(deg P, deg Q) of each function restricted to a random line through the origin's neighbourhood (a generic
    line keeps both total degrees), by Thiele interpolation with early termination."""
    a = [rng.randrange(1, p) for _ in range(n)]
    b = [rng.randrange(1, p) for _ in range(n)]
    thieles = [ThieleInterpolator(p) for _ in range(count)]
    s = 0
    while not all(t.terminated for t in thieles):
        s += 1
        if s > 2 * max_degree + 2 + 4 * 16:
            raise ResourceLimitError(f"a function has total degree above {max_degree} along a line: raise the bound")
        values = _probe(box, p, [(x + s * y) % p for x, y in zip(a, b, strict=True)], count)
        if values is None:
            continue
        for t, v in zip(thieles, values, strict=True):
            if not t.terminated:
                t.add(s, v)
    out = []
    for t in thieles:
        num, den = t.fraction()
        out.append((len(num) - 1 if any(num) else 0, len(den) - 1))
    return out


def _integral(num: dict, den: dict) -> Fraction:
    """Rational coefficients made integer and primitive (a common factor for numerator and denominator)."""
    scale = math.lcm(*(int(c.q) for c in (*num.values(), *den.values())))
    ints = [{m: int(c.p) * (scale // int(c.q)) for m, c in part.items()} for part in (num, den)]
    g = math.gcd(*(v for part in ints for v in part.values())) or 1
    return ({m: v // g for m, v in ints[0].items()}, {m: v // g for m, v in ints[1].items()})


def reconstruct_vector(box: VectorBox, n: int, count: int, *, rng: random.Random, max_degree: int = 16,
                       bits: int = 50, max_primes: int = 12) -> list[Fraction]:
    """`count` rational functions of n variables from their values mod primes (one probe gives them all): degrees
    along a line, a dense ansatz per function on shared points, Chinese remaindering and Wang's reconstruction until
    stable, and a check at fresh points modulo a fresh prime. A candidate: callers prove what they use."""
    lifter: CoefficientLifter[tuple[int, int, Exponents]] = CoefficientLifter()
    degrees: list[tuple[int, int]] | None = None
    shapes: list[tuple[tuple, tuple]] | None = None
    for _ in range(max_primes):
        p = random_prime(rng, bits)
        if degrees is None:
            degrees = _line_degrees(box, p, n, count, rng, max_degree)
        unknowns = max(len(exponents_upto(n, dp)) + len(exponents_upto(n, dq)) for dp, dq in degrees)
        points: list[list[int]] = []
        values: list[list[int]] = []
        while len(points) < unknowns + 4:
            x = [rng.randrange(p) for _ in range(n)]
            v = _probe(box, p, x, count)
            if v is not None:
                points.append(x)
                values.append(v)
        solved = [rational_fit_mod_p([v[j] for v in values], points, degrees[j], p) for j in range(count)]
        if any(s is None for s in solved):
            continue                     # an unlucky prime or points: another prime
        shape = [(tuple(sorted(s[0])), tuple(sorted(s[1]))) for s in solved if s is not None]
        if shapes is None:
            shapes = shape
        elif shape != shapes:
            continue                     # the supports changed: this prime was unlucky
        residues = {(j, part, m): c for j, s in enumerate(solved) if s is not None
                    for part, poly in enumerate(s) for m, c in poly.items()}
        _, missing = lifter.add(residues, p)
        if not missing and lifter.changed == 0:
            break                        # every coefficient reconstructed and confirmed by one more prime
    else:
        raise ResourceLimitError(f"the coefficients were not stable after {max_primes} primes: raise the bound")
    out: list[Fraction] = []
    keys = list(lifter.rationals)
    for j in range(count):
        num = {m: lifter.rationals[(jj, part, m)] for jj, part, m in keys if jj == j and part == 0}
        den = {m: lifter.rationals[(jj, part, m)] for jj, part, m in keys if jj == j and part == 1}
        out.append(_integral(num, den))
    _check(box, out, n, rng, bits)
    return out


def _check(box: VectorBox, fractions: list[Fraction], n: int, rng: random.Random, bits: int) -> None:
    """The candidates agree with the black box at fresh points modulo a fresh prime, or HKProofError."""
    p = random_prime(rng, bits)
    checked = 0
    while checked < CHECKS:
        x = [rng.randrange(p) for _ in range(n)]
        values = box(p, x)
        if values is None:
            continue
        for (num, den), v in zip(fractions, values, strict=True):
            d = polynomial_mod_p(den, x, p)
            if d and (v * d - polynomial_mod_p(num, x, p)) % p:
                raise HKProofError("a reconstructed function failed the check at a fresh point mod a fresh prime")
        checked += 1
