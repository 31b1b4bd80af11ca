"""Transport along a rational substitution of the parameters and of eps (x fixed): an injective homomorphism of
fields sigma: Q(x, eps', params') -> Q(x, eps, params) that maps one Kahan map onto another carries every rational
identity about the first map (an integral, a kernel vector, an HK system and its solution) to the second."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping, Sequence

import flint

from hkproof.algebra.factored import cancel_common, factor, learn_factors
from hkproof.algebra.fraction import Frac, Parity, homogenized_compose, normalize_sign
from hkproof.algebra.linalg import lcm
from hkproof.algebra.ring import Rational, Ring, to_fmpq
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.independence import jacobian_rank_at
from hkproof.proof.certificate import StepRecorder

__all__ = ["map_mismatches", "require_transport", "Substitution"]


@dataclass(frozen=True)
class Substitution:
    """sigma(n) = images[n] for the names of `source` listed, sigma(n) = n for the others (which `target` must have).

    Applied to a rational function of `source` by one homogenized compose over the images' common denominator.
    """

    source: Ring
    target: Ring
    images: Mapping[str, Frac]
    units: tuple[str, ...] | None = field(init=False, default=None, compare=False, repr=False)  # _laurent_units
    _composed: list[tuple[flint.fmpz_mpoly, tuple[flint.fmpz_mpoly, int]]] = field(     # recent denominators and
        init=False, default_factory=list, compare=False, repr=False)                       # their homogenized images

    def __post_init__(self) -> None:
        for n, img in self.images.items():
            if n not in self.source.names:
                raise HKProofError(f"{n} is not a variable of {self.source}")
            if img.ring != self.target:
                raise HKProofError(f"the image of {n} is not an element of {self.target}")
        kept = [n for n in self.source.names if n not in self.images and n not in self.target.names]
        if kept:
            raise HKProofError(f"{kept} are neither substituted nor variables of {self.target}")

        object.__setattr__(self, "units", _laurent_units(self.source, self.target, self.images))

    def __str__(self) -> str:
        return ", ".join(f"{n} -> {img}" for n, img in self.images.items())

    def apply(self, h: Frac) -> Frac:
        """sigma(h) in lowest terms (SingularPointError if its denominator is sent to 0). Where sigma extends to an
        automorphism of a Laurent ring (`units`), sigma(num) and sigma(den) are coprime up to monomials in the units
        and an integer, so those are cancelled without a gcd of the two big polynomials."""
        num, den = self.apply_terms(h)
        if self.units is None:
            return Frac(self.target, num, den)
        return Frac(self.target, *normalize_sign(*_strip_units(num, den, [self.target.index(u) for u in self.units])),
                    reduced=True)

    def apply_cancelled(self, h: Frac) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
        """(P, Q) with P/Q = sigma(h), the irreducible factors of the images' numerators and denominators cancelled
        where they divide both (where the common factor of sigma(num) and sigma(den) usually lies: the image of a
        symbol of h's denominator), without the gcd of the two big polynomials: not always in lowest terms."""
        num, den = self.apply_terms(h)
        factors = [q for image in self.images.values() for part in (image.num, image.den) for q, _ in factor(part)[1]]
        # the images of the small factors of h's denominator, factored one by one: a later `factor` of the image's
        # big denominator (algebra.factored.sum_of_products) then only divides
        learn_factors(self.apply_terms(Frac(self.source, q))[0] for q, _ in factor(h.den)[1])
        return cancel_common(num, den, factors)[:2]

    def apply_terms(self, h: Frac) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
        """(P, Q) with P/Q = sigma(h), not reduced."""
        if h.ring != self.source:
            raise HKProofError(f"{h} is not an element of {self.source}")
        both = self.target.extend(self.source.names)
        common = lcm([img.den for img in self.images.values()])
        images = [(img.num * (common / img.den)).project_to_context(both.ctx) for img in self.images.values()]
        lifted = Frac(both, h.num.project_to_context(both.ctx), h.den.project_to_context(both.ctx), reduced=True)
        moved, cleared = list(self.images), common.project_to_context(both.ctx)
        seen = next((image for den, image in self._composed if den == h.den), None)   # the components of one
        if seen is None:                                                               # solution share theirs
            seen = homogenized_compose(both, lifted.den, moved, images, cleared)
            self._composed[:] = [*self._composed[-3:], (h.den, seen)]
        num, den = lifted.pullback_terms(images, cleared, moved, seen)
        if den.is_zero():
            raise HKProofError(f"the substitution {self} sends the denominator of {h} to 0")
        return num.project_to_context(self.target.ctx), den.project_to_context(self.target.ctx)

    def pullback(self, point: Mapping[str, Rational]) -> dict[str, flint.fmpq]:
        """The point of the source at which h takes the value of sigma(h) at `point`: the images evaluated there, the
        kept names as they are (sigma(h)(P) = h(sigma*(P)) wherever h's denominator does not vanish at sigma*(P))."""
        out = {n: to_fmpq(point[n]) for n in self.source.names if n not in self.images}
        out.update({n: img.evaluate(point) for n, img in self.images.items()})
        return out

    def commutes_with_sign(self, name: str) -> bool:
        """sigma o iota = iota o sigma for iota: name -> -name on both rings (the image of `name` odd in it, every
        other image even): then sigma maps functions even in `name` to functions even in it."""
        return all(img.parity(name) is (Parity.ODD if n == name else Parity.EVEN) or img.is_zero() and n != name
                   for n, img in self.images.items())

    def is_injective_at(self, moved_onto: Sequence[str], point: Mapping[str, Rational]) -> bool:
        """sigma is an injective homomorphism of fields (identities carry over both ways, no non-zero denominator
        is sent to 0): the images involve none of the kept variables, and their Jacobian with respect to the target
        variables `moved_onto` (none of them kept) has full rank at one rational point."""
        kept = set(self.source.names) - set(self.images)
        if kept & set(moved_onto) or any(kept & img.variables() for img in self.images.values()):
            return False
        return jacobian_rank_at(list(self.images.values()), moved_onto, point) == len(self.images)


def require_transport(s: StepRecorder, sigma: Substitution, target: KahanMap) -> None:
    """What lets facts about sigma(h) on `target` be read on h: sigma fixes the phase variables (so the images of
    identities in them are identities) and commutes with eps -> -eps (so the images of even functions are even)."""
    s.require(not set(sigma.images) & set(target.variables), f"sigma moves a phase variable: {sigma}")
    s.require(sigma.commutes_with_sign(EPS), f"sigma does not commute with eps -> -eps: {sigma}")


def _laurent_units(source: Ring, target: Ring, images: Mapping[str, Frac]) -> tuple[str, ...] | None:
    """The units U when sigma is the inclusion Q[source] -> Q[target][U^-1] (each name to the same name) followed by
    a triangular automorphism: every moved name v goes to (c M v + r) / Q with c a non-zero integer, M and Q
    monomials in U and r free of the moved names, U free of them too. An automorphism and an inclusion keep
    coprime polynomials coprime up to units, so gcd(sigma num, sigma den) in Z[target] is an integer times a monomial
    in U. None when sigma is not of this form (then `apply` takes the gcd)."""
    moved = set(images)
    if not moved <= set(target.names):
        return None
    units: set[str] = set()
    for v, img in images.items():
        if len(img.den) != 1 or len(img.num) == 0:
            return None
        units |= target.variables_of(img.den)
        index = target.index(v)
        leading = [(m, c) for m, c in img.num.to_dict().items() if m[index]]
        if len(leading) != 1 or leading[0][0][index] != 1:
            return None
        units |= {target.names[i] for i, e in enumerate(leading[0][0]) if e and i != index}
        rest = img.num - img.num.context().from_dict(dict(leading))
        if target.variables_of(rest) & moved:
            return None
    return tuple(sorted(units)) if not units & moved else None


def _strip_units(num: flint.fmpz_mpoly, den: flint.fmpz_mpoly, units: Sequence[int]
                 ) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
    """num and den divided by their common monomial in the unit variables and their common integer content."""
    low_num, low_den = num.deflation_index()[1], den.deflation_index()[1]
    exponents = [0] * len(num.context().names())
    for i in units:
        exponents[i] = min(low_num[i], low_den[i])
    if any(exponents):
        common = num.context().from_dict({tuple(exponents): 1})
        num, den = num / common, den / common
    g = num.content().gcd(den.content())  # type: ignore[attr-defined]  # in python-flint 0.9, missing from its stubs
    if g != 1:
        num, den = num / int(g), den / int(g)
    return num, den


def map_mismatches(sigma: Substitution, source: KahanMap, target: KahanMap) -> list[str]:
    """Where sigma(source) differs from target: the Kahan matrix form M x~ = b (rows divided by their diagonal
    entry) and the explicit components N_j / Delta, each compared exactly; [] when the maps are equal."""
    if source.variables != target.variables:
        raise HKProofError(f"{source} and {target} have different phase variables")
    out = []
    (m_s, b_s), (m_t, b_t) = source.matrix, target.matrix
    rs, rt = source.ring, target.ring
    for i in range(len(b_s)):
        ds, dt = sigma.apply(Frac(rs, m_s[i][i])), Frac(rt, m_t[i][i])
        for j in range(len(b_s)):
            if sigma.apply(Frac(rs, m_s[i][j])) / ds != Frac(rt, m_t[i][j]) / dt:
                out.append(f"M[{i + 1},{j + 1}]")
        if sigma.apply(Frac(rs, b_s[i])) / ds != Frac(rt, b_t[i]) / dt:
            out.append(f"b[{i + 1}]")
    for v, got, want in zip(source.variables, source.components(), target.components(), strict=True):
        num, den = sigma.apply_terms(got)
        if not want.is_ratio(num, den):
            out.append(f"component {v}~")
    return out
