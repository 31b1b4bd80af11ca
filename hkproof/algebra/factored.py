"""Sums of products of big rational functions in lowest terms without a gcd of the big numerator: the
denominators are factored (they are small next to the numerators), the sum is taken over the lcm of the factored
denominators, and each factor is then cancelled by exact division where it divides."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Sequence

import flint
from flint.utils.flint_exceptions import DomainError

from hkproof.algebra.fraction import Frac, normalize_sign
from hkproof.algebra.ring import Ring

__all__ = ["cancel_common", "exact_quotient", "factor", "learn_factors", "Quotient", "sum_of_products"]


@dataclass(frozen=True)
class Quotient:
    """num / den over `ring`, not necessarily in lowest terms: an input of `sum_of_products`, whose sum is reduced
    anyway (it spares the gcd of a big numerator and denominator that only feed a sum)."""

    ring: Ring
    num: flint.fmpz_mpoly
    den: flint.fmpz_mpoly


_FACTORED: dict[tuple, list[tuple[flint.fmpz_mpoly, tuple[flint.fmpz, list[tuple[flint.fmpz_mpoly, int]]]]]] = {}
_IRREDUCIBLE: dict[int, dict[str, flint.fmpz_mpoly]] = {}    # per context: the irreducible factors seen so far


def _fingerprint(p: flint.fmpz_mpoly) -> tuple:
    """A cheap key for a polynomial (its text costs milliseconds per 10 000 terms); equal keys are compared exactly."""
    return id(p.context()), len(p), tuple(p.degrees()), int(p.coefficient(0)) if len(p) else 0, \
        int(p.coefficient(len(p) - 1)) if len(p) else 0


def factor(p: flint.fmpz_mpoly) -> tuple[flint.fmpz, list[tuple[flint.fmpz_mpoly, int]]]:
    """FLINT's factorization (content, [(irreducible, multiplicity)]), remembered for the denominators that many
    components of one solution share (a 30 000-term denominator takes seconds to factor); the irreducible factors
    already seen (here or by `learn_factors`) are divided out first, so FLINT factors only what is new (a
    denominator that is a product of known factors costs a few exact divisions)."""
    key = _fingerprint(p)
    same = next((result for q, result in _FACTORED.get(key, ()) if q == p), None)
    if same is not None:
        return same
    if sum(map(len, _FACTORED.values())) > 64:
        _FACTORED.clear()
        _IRREDUCIBLE.clear()
    known = _IRREDUCIBLE.setdefault(key[0], {})
    rest, found = p, []
    for q in known.values():
        e = 0
        while (quotient := exact_quotient(rest, q)) is not None:
            rest, e = quotient, e + 1
        if e:
            found.append((q, e))
    content, new = rest.factor()
    known.update((str(q), q) for q, _ in new)
    result = (content, found + list(new))
    _FACTORED.setdefault(key, []).append((p, result))
    return result


def learn_factors(polys: Iterable[flint.fmpz_mpoly]) -> None:
    """Factor these (small) polynomials now, so that `factor` of a big product of them later only divides: e.g. the
    images of the factors of a denominator under a substitution, whose product FLINT would factor in seconds."""
    for p in polys:
        if not p.is_constant():
            factor(p)


def _product(factors: dict[str, tuple[flint.fmpz_mpoly, int]], one: flint.fmpz_mpoly) -> flint.fmpz_mpoly:
    out = one
    for q, e in factors.values():
        out = out * q ** e
    return out


def exact_quotient(p: flint.fmpz_mpoly, q: flint.fmpz_mpoly) -> flint.fmpz_mpoly | None:
    """p / q when q divides p exactly, else None (FLINT's exact division stops at the first failing term)."""
    try:
        return p / q
    except DomainError:
        return None


def cancel_common(num: flint.fmpz_mpoly, den: flint.fmpz_mpoly, factors: Iterable[flint.fmpz_mpoly]
                  ) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly, flint.fmpz_mpoly]:
    """(num / t, den / t, t): each of `factors` (each distinct one once) divided out of both while it divides both,
    without a gcd of the two; the denominator is tried first (usually the smaller, it fails faster)."""
    taken = den.context().constant(1)
    seen: set[str] = set()
    for q in factors:
        if str(q) in seen:
            continue
        seen.add(str(q))
        while (d := exact_quotient(den, q)) is not None and (n := exact_quotient(num, q)) is not None:
            num, den, taken = n, d, taken * q
    return num, den, taken


def sum_of_products(terms: Sequence[Sequence[Frac | Quotient]]) -> Frac:
    """sum_i prod_j terms[i][j] in lowest terms, for big numerators over denominators that FLINT can factor (the
    terms need not be in lowest terms themselves: every factor of the sum's denominator is cancelled where it divides).

    >>> from hkproof.algebra.ring import get_ring
    >>> r = get_ring(("x", "y"))
    >>> a, b, g = Frac.parse(r, "1/(x + y)"), Frac.parse(r, "y/(x + y)"), Frac.parse(r, "1/x")
    >>> sum_of_products([[a], [g, b]])
    (1)/(x)
    """
    ring = terms[0][0].ring
    one = ring.constant(1)
    for den in sorted({id(f.den): f.den for factors in terms for f in factors}.values(), key=len):
        factor(den)           # the small denominators first: a big one is often a small one times a new factor
    contents, parts = [], []
    for factors in terms:
        num = one
        dens: dict[str, tuple[flint.fmpz_mpoly, int]] = {}
        content = flint.fmpz(1)
        for f in factors:
            c, fs = factor(f.den)
            num = num * (f.num if c > 0 else -f.num)
            content *= abs(c)
            for q, e in fs:
                key = str(q)
                dens[key] = (q, dens.get(key, (q, 0))[1] + e)
        contents.append(content)
        parts.append((num, dens))
    common: dict[str, tuple[flint.fmpz_mpoly, int]] = {}
    for _, dens in parts:
        for key, (q, e) in dens.items():
            if e > common.get(key, (q, 0))[1]:
                common[key] = (q, e)
    scale = flint.fmpz(1)
    for c in contents:
        scale = scale * c // scale.gcd(c)
    total = one - one
    for (num, dens), content in zip(parts, contents, strict=True):
        cofactor = {k: (q, e - dens.get(k, (q, 0))[1]) for k, (q, e) in common.items()}
        total += num * _product(cofactor, one) * int(scale // content)
    remaining = dict(common)
    for key, (q, e) in common.items():
        while e and (quotient := exact_quotient(total, q)) is not None:
            total, e = quotient, e - 1
        remaining[key] = (q, e)
    if total.is_zero():
        return Frac(ring, 0)
    den = _product(remaining, one) * int(scale)
    g = total.content().gcd(scale)  # type: ignore[attr-defined]  # in python-flint 0.9, missing from its stubs
    if g != 1:
        total, den = total / int(g), den / int(g)
    return Frac(ring, *normalize_sign(total, den), reduced=True)
