"""The dense algorithm behind hkproof.algebra.reconstruction (method "dense"): several small rational functions of a
few variables, rebuilt over Q from their values mod primes at shared points.

Where many functions come out of one costly computation (a relation's coefficients at given eps and parameters),
each probe yields all of them at once, so they are rebuilt on the same points: the degrees of each along a random
line (`degrees_on_line`), then per function the dense ansatz g Q - P = 0 of those total degrees solved mod p
(normalized by the first monomial of Q that is not zero), primes until Wang's reconstruction is stable for every
coefficient, and the shared check at fresh points modulo a fresh prime. For a few variables and low degrees this
needs far fewer probes than one sparse reconstruction per function (hkproof.algebra.sparse_reconstruction).

>>> def box(p, points):                        # g1 = (x + 2 y)/(1 + x y), g2 = y/3
...     return [None if (1 + x * y) % p == 0 else [(x + 2 * y) * pow(1 + x * y, -1, p) % p, y * pow(3, -1, p) % p]
...             for x, y in points]
>>> g1, g2 = dense(box, 2, 2, rng=random.Random(1))
>>> sorted(g1.numerator.items()), sorted(g1.denominator.items()), sorted(g2.numerator.items()), g2.denominator
([((0, 1), 2), ((1, 0), 1)], [((0, 0), 1), ((1, 1), 1)], [((0, 1), 1)], {(0, 0): 3})
"""
from __future__ import annotations

import math
import random
from collections.abc import Sequence

from hkproof import budget
from hkproof.algebra.modular import rational_fit_mod_p
from hkproof.algebra.monomials import Exponents, count_upto, exponents_upto
from hkproof.algebra.rational_lifting import CoefficientLifter
from hkproof.algebra.reconstruction import Batch, Primes, Rebuilt, agrees_at_fresh_prime, degrees_on_line, primitive
from hkproof.errors import HKProofError, ResourceLimitError

__all__ = ["ansatz_size", "dense", "line_degrees"]


def ansatz_size(variables: int, degrees: tuple[int, int]) -> int:
    """Unknowns of the dense ansatz g Q - P = 0 with deg P <= degrees[0], deg Q <= degrees[1]."""
    return sum(count_upto(variables, d) for d in degrees)


CHUNK = 16
"""Points per call of the black box: the budget is checked between calls (one probe can cost a linear solve)."""


def _probe(black_box: Batch, p: int, points: Sequence[Sequence[int]], count: int) -> list[list[int] | None]:
    values: list[list[int] | None] = []
    for start in range(0, len(points), CHUNK):
        budget.check("probing a small vector of functions mod p")
        values += black_box(p, points[start:start + CHUNK])
    if any(v is not None and len(v) != count for v in values):
        raise HKProofError(f"the black box gave a vector of another length than {count}")
    return values


def line_degrees(black_box: Batch, p: int, n: int, count: int, rng: random.Random,
                 max_degree: int) -> list[tuple[int, int]]:
    """(deg P, deg Q) of each function along a random line x = a + t b (a generic line keeps both total degrees;
    ResourceLimitError above max_degree)."""
    a = [rng.randrange(1, p) for _ in range(n)]
    b = [rng.randrange(1, p) for _ in range(n)]
    step = iter(range(1, 1 << 62))
    degrees = degrees_on_line(
        lambda ts: _probe(black_box, p, [[(x + t * y) % p for x, y in zip(a, b, strict=True)] for t in ts], count),
        p, count, lambda k: [next(step) for _ in range(k)], max_degree)
    if any(d is None for d in degrees):
        raise ResourceLimitError(f"a function has total degree above {max_degree} along a line: raise the bound")
    return [d for d in degrees if d is not None]


def _points(p: int, n: int, wanted: int, shared: int, degree: int, rng: random.Random) -> list[list[int]]:
    """`wanted` random points mod p; with `shared` > 0 the first `shared` coordinates take only as many values as a
    dense ansatz of `degree` in them needs (plus 2), each with many values of the others (a black box that costs most
    per value of those, such as a Kahan map specialized at eps and the parameters, is then called few times)."""
    if not shared:
        return [[rng.randrange(p) for _ in range(n)] for _ in range(wanted)]
    draws = count_upto(shared, degree) + 2
    per = math.ceil(wanted / draws)
    out: list[list[int]] = []
    while len(out) < wanted:
        outer = [rng.randrange(p) for _ in range(shared)]
        out += [outer + [rng.randrange(p) for _ in range(n - shared)] for _ in range(min(per, wanted - len(out)))]
    return out


def dense(black_box: Batch, n: int, count: int, *, rng: random.Random, max_degree: int = 16, bits: int = 50,
          max_primes: int = 12, degrees: Sequence[tuple[int, int]] | None = None, shared: int = 0) -> list[Rebuilt]:
    """`count` rational functions of n variables from their values mod primes (one probe gives them all): degrees
    along a line (or the `degrees` given), a dense ansatz per function on shared points (`_points`: the first
    `shared` coordinates on a grid), Chinese remaindering and Wang's reconstruction until stable, and the check at
    fresh points modulo a fresh prime. Candidates: callers prove what they use."""
    lifter: CoefficientLifter[tuple[int, int, Exponents]] = CoefficientLifter()
    primes = Primes(rng, bits=bits)
    shapes: list[tuple[tuple, tuple]] | None = None
    for _ in range(max_primes):
        p = primes.any()
        if degrees is None:
            degrees = line_degrees(black_box, p, n, count, rng, max_degree)
        unknowns = max(len(exponents_upto(n, dp)) + len(exponents_upto(n, dq)) for dp, dq in degrees)
        points: list[list[int]] = []
        values: list[list[int]] = []
        while len(points) < unknowns + 4:
            xs = _points(p, n, unknowns + 4 - len(points), shared, max(max(d) for d in degrees), rng)
            for x, v in zip(xs, _probe(black_box, p, xs, count), strict=True):
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
    out = [primitive({m: q for (jj, part, m), q in lifter.rationals.items() if jj == j and part == 0},
                     {m: q for (jj, part, m), q in lifter.rationals.items() if jj == j and part == 1})
           for j in range(count)]
    if agrees_at_fresh_prime(black_box, out, n, primes, rng) is None:
        raise HKProofError("a reconstructed function failed the check at a fresh point mod a fresh prime")
    return out
