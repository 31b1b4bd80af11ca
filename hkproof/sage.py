"""Sage interop (optional: `pip install -e '.[sage]'`, the passagemath distributions): a system from Sage polynomials,
and hkproof's exact results back as elements of a Sage polynomial ring or fraction field.

Sage is imported on first use only; without it these functions raise hkproof's MissingDependencyError. Polynomials
travel as exponent vectors and exact rational coefficients (no text is evaluated on either side).
"""
from __future__ import annotations

from typing import Any, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.api import system
from hkproof.dynamics.field import EPS, QuadraticField
from hkproof.dynamics.orbits import ExactOrbit
from hkproof.errors import MissingDependencyError, ParseError, RingMismatchError
from hkproof.pipelines.discover import DiscoveryReport
from hkproof.proof.certificate import Certificate

__all__ = ["from_sage", "sage_ring", "to_sage"]


def _sage() -> Any:
    try:
        import sage.all__sagemath_singular as sage_all
    except ImportError:
        raise MissingDependencyError("Sage interop needs passagemath: pip install 'hkproof[sage]'") from None
    return sage_all


def _term(exponents: Sequence[int], names: Sequence[str], coefficient: Any) -> str:
    q = flint.fmpq(int(coefficient.numerator()), int(coefficient.denominator()))
    return "*".join([f"({q})", *(f"{n}**{e}" for n, e in zip(names, exponents, strict=True) if e)])


def from_sage(rhs: Sequence[Any], variables: int | Sequence[str] | None = None, *,
              name: str = "sage-system") -> QuadraticField:
    """x' = rhs for polynomials of one Sage ring over QQ: the phase variables are `variables` (names, or the first
    `variables` generators; default: the first len(rhs)), the other generators are parameters (a generator named eps
    is hkproof's eps, half the time step, so that results can come back into the same ring)."""
    if not rhs:
        raise ParseError("give at least one right-hand side")
    ring = rhs[0].parent()
    names = [str(n) for n in ring.variable_names()]
    if variables is None or isinstance(variables, int):
        phase = names[:len(rhs) if variables is None else variables]
    else:
        phase = list(variables)
    texts = [" + ".join(_term(_exponents(e), names, c) for e, c in ring(p).dict().items()) or "0" for p in rhs]
    return system(phase, texts, parameters=[n for n in names if n not in phase and n != EPS], name=name)


def _exponents(key: Any) -> tuple[int, ...]:
    """A Sage exponent key as a tuple (a univariate ring keys its terms by int)."""
    return tuple(int(e) for e in key) if hasattr(key, "__iter__") else (int(key),)


def sage_ring(names: Sequence[str], fractions: bool = False) -> Any:
    """QQ[names] in Sage, or its fraction field."""
    ring = _sage().PolynomialRing(_sage().QQ, list(names))
    return ring.fraction_field() if fractions else ring


def _poly(p: flint.fmpz_mpoly, ring: Any) -> Any:
    names = [str(n) for n in ring.variable_names()]
    used = [n for n, e in zip(p.context().names(), p.degrees(), strict=True) if e > 0]
    missing = [n for n in used if n not in names]
    if missing:
        raise RingMismatchError(f"{missing} are not generators of the Sage ring {ring}")
    place = {n: names.index(n) for n in used}
    terms = {}
    for exps, c in p.to_dict().items():
        full = [0] * len(names)
        for n, e in zip(p.context().names(), exps, strict=True):
            if e:
                full[place[n]] = e
        terms[tuple(full) if len(names) > 1 else full[0]] = _sage().QQ(int(c))
    return ring(terms)


def to_sage(result: Frac | Certificate | DiscoveryReport | ExactOrbit | QuadraticField, ring: Any = None) -> Any:
    """A rational function as an element of QQ[names] (denominator 1) or its fraction field; a certificate's exact
    formulas or discover's integrals as {name: element}; an orbit's points as tuples of QQ; a system's right-hand
    sides as polynomials. `ring`: a Sage polynomial ring holding every name used (default: one made for them)."""
    if isinstance(result, ExactOrbit):
        qq = _sage().QQ
        return [tuple(qq(int(x[v].p)) / qq(int(x[v].q)) for v in result.variables) for x in result.points]
    if isinstance(result, Certificate):
        return {k: to_sage(v, ring) for k, v in result.values.items()}
    if isinstance(result, DiscoveryReport):
        return {i.name: to_sage(i.frac, ring) for i in result.integrals if i.frac is not None}
    if isinstance(result, QuadraticField):
        return [to_sage(h, ring) for h in result.rhs]
    polys = sage_ring(result.ring.names) if ring is None else ring.ring() if ring.is_field() else ring
    num, den = _poly(result.num, polys), _poly(result.den, polys)
    return num if den == 1 else polys.fraction_field()(num) / den
