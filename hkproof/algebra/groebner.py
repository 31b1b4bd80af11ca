"""Ideal membership with certificates: cofactors checked by expansion, and Groebner normal forms on FLINT."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import flint

__all__ = ["groebner_basis", "in_ideal", "MembershipCertificate"]


@dataclass
class MembershipCertificate:
    """multiplier**power * target = sum_j weights[j] * G_j with G_j = sum_i combination[j][i] * generators[i], to be
    checked by plain expansion; the cofactors of the generators are lambda_i = sum_j weights[j] * combination[j][i].
    Without `combination` the weights are the cofactors (G = the generators). Any polynomial combination gives a
    valid certificate: the identity alone puts multiplier**power * target in the ideal of the generators."""

    target: flint.fmpz_mpoly
    generators: Sequence[flint.fmpz_mpoly]
    weights: Sequence[flint.fmpz_mpoly]
    multiplier: flint.fmpz_mpoly
    power: int
    combination: Sequence[Sequence[flint.fmpz_mpoly]] | None = None

    def combined(self) -> list[flint.fmpz_mpoly]:
        """G_j = sum_i combination[j][i] * generators[i] (the generators themselves without a combination)."""
        if self.combination is None:
            return list(self.generators)
        zero = self.target.context().constant(0)
        return [sum((a * g for a, g in zip(row, self.generators, strict=True) if not a.is_zero()), zero)
                for row in self.combination]

    def check(self) -> bool:
        """Expand both sides and compare: the only step the conclusion rests on."""
        total = self.target.context().constant(0)
        for w, g in zip(self.weights, self.combined(), strict=True):
            total += w * g
        return total == self.multiplier ** self.power * self.target

    @property
    def cofactors(self) -> list[flint.fmpz_mpoly]:
        """lambda_i = sum_j weights[j] * combination[j][i], expanded (large: for export, not for the check)."""
        if self.combination is None:
            return list(self.weights)
        zero = self.target.context().constant(0)
        return [sum((w * row[i] for w, row in zip(self.weights, self.combination, strict=True) if not row[i].is_zero()),
                    zero) for i in range(len(self.generators))]

    @property
    def terms(self) -> int:
        """Terms of the weights and of the combination (the certificate's size as checked)."""
        return sum(len(w) for w in self.weights) + sum(len(a) for row in self.combination or () for a in row)


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
