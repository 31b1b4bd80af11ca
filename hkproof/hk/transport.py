"""Transport along a rational substitution of the parameters and of eps (x fixed): an injective homomorphism of
fields sigma: Q(x, eps', params') -> Q(x, eps, params) that maps one Kahan map onto another carries every rational
identity about the first map (an integral, a kernel vector, an HK system and its solution) to the second."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import lcm
from hkproof.algebra.ring import Rational, Ring
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.independence import jacobian_rank_at

__all__ = ["map_mismatches", "Substitution"]


@dataclass(frozen=True)
class Substitution:
    """sigma(n) = images[n] for the names of `source` listed, sigma(n) = n for the others (which `target` must have).

    Applied to a rational function of `source` by one homogenized compose over the images' common denominator.
    """

    source: Ring
    target: Ring
    images: Mapping[str, Frac]

    def __post_init__(self) -> None:
        for n, img in self.images.items():
            if n not in self.source.names:
                raise HKProofError(f"{n} is not a variable of {self.source}")
            if img.ring != self.target:
                raise HKProofError(f"the image of {n} is not an element of {self.target}")
        kept = [n for n in self.source.names if n not in self.images and n not in self.target.names]
        if kept:
            raise HKProofError(f"{kept} are neither substituted nor variables of {self.target}")

    def __str__(self) -> str:
        return ", ".join(f"{n} -> {img}" for n, img in self.images.items())

    def apply(self, h: Frac) -> Frac:
        """sigma(h) in lowest terms (SingularPointError if its denominator is sent to 0)."""
        return Frac(self.target, *self.apply_terms(h))

    def apply_terms(self, h: Frac) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
        """(P, Q) with P/Q = sigma(h), not reduced."""
        if h.ring != self.source:
            raise HKProofError(f"{h} is not an element of {self.source}")
        both = self.target.extend(self.source.names)
        common = lcm([img.den for img in self.images.values()])
        images = [(img.num * (common / img.den)).project_to_context(both.ctx) for img in self.images.values()]
        lifted = Frac(both, h.num.project_to_context(both.ctx), h.den.project_to_context(both.ctx), reduced=True)
        num, den = lifted.pullback_terms(images, common.project_to_context(both.ctx), list(self.images))
        if den.is_zero():
            raise HKProofError(f"the substitution {self} sends the denominator of {h} to 0")
        return num.project_to_context(self.target.ctx), den.project_to_context(self.target.ctx)

    def is_injective_at(self, moved_onto: Sequence[str], point: Mapping[str, Rational]) -> bool:
        """sigma is an injective homomorphism of fields (identities carry over both ways, no non-zero denominator
        is sent to 0): the images involve none of the kept variables, and their Jacobian with respect to the target
        variables `moved_onto` (none of them kept) has full rank at one rational point."""
        kept = set(self.source.names) - set(self.images)
        if kept & set(moved_onto) or any(kept & img.variables() for img in self.images.values()):
            return False
        return jacobian_rank_at(list(self.images.values()), moved_onto, point) == len(self.images)


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
