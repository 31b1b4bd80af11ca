"""Ideal membership with certificates: cofactors checked by expansion, and Groebner normal forms on FLINT."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import flint

__all__ = ["groebner_basis", "in_ideal", "MembershipCertificate"]


@dataclass
class MembershipCertificate:
    """multiplier**power * target = sum cofactors[i] * generators[i], to be checked by plain expansion."""

    target: flint.fmpz_mpoly
    generators: Sequence[flint.fmpz_mpoly]
    cofactors: Sequence[flint.fmpz_mpoly]
    multiplier: flint.fmpz_mpoly
    power: int

    def check(self) -> bool:
        """Expand both sides and compare: the only step the conclusion rests on."""
        total = self.target.context().constant(0)
        for lam, g in zip(self.cofactors, self.generators, strict=True):
            total += lam * g
        return total == self.multiplier ** self.power * self.target

    @property
    def terms(self) -> int:
        """Total number of terms in the cofactors (the certificate's size)."""
        return sum(len(c) for c in self.cofactors)


def groebner_basis(generators: Sequence[flint.fmpz_mpoly],
                   limits: tuple[int, int, int] | None = None) -> flint.fmpz_mpoly_vec | None:
    """A reduced Groebner basis over Q (primitive integer polynomials), or None when `limits` stop Buchberger."""
    ctx = generators[0].context()
    vec = flint.fmpz_mpoly_vec(list(generators), ctx)
    if limits is None:
        return vec.buchberger_naive().autoreduction()
    basis, complete = vec.buchberger_naive(limits=limits)
    return basis.autoreduction() if complete else None  # type: ignore[attr-defined]  # missing from flint's stubs


def in_ideal(p: flint.fmpz_mpoly, basis: flint.fmpz_mpoly_vec) -> bool:
    """p in the ideal over Q iff its normal form modulo the Groebner basis is zero."""
    return p.reduction_primitive_part(basis).is_zero()  # type: ignore[attr-defined]  # missing from flint's stubs
