"""`discover`, the exact half: certify reconstructed integrals, sort out trivial ones, prove independence.

The search (algorithm (N) on monomial bases, kernels, reconstruction) lives in hkproof.pipelines.discover;
everything it finds passes through here before it is called an integral: h o f = h by substitution
(`check_integral`, every remaining parameter symbolic) and functional independence by an exact Jacobian rank at
a rational point (a full rank at one point proves independence).
"""
from __future__ import annotations

from typing import Mapping, Sequence

import flint

from hkproof.algebra.sampling import random_point
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import SingularPointError
from hkproof.hk.independence import gradient_at
from hkproof.hk.integrals import check_integral
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.export import substitution_step
from hkproof.proof.status import Status

__all__ = ["certify", "independent_subset", "is_phase_constant", "jacobian_points"]


def certify(kmap: KahanMap, h: Frac, fixed: Mapping[str, Rational] | None = None, name: str = "h") -> Certificate:
    """A certificate of h o f = h: exact substitution h(N/Delta) - h = 0 in Q(x, eps, parameters) (verified, or
    verified(specialized) at the parameter values `fixed`; refuted when the difference is not zero)."""
    cert = Certificate(f"integral {name}", f"{name} is an integral of the Kahan map of {kmap.field.name}",
                       "sec. 3 (an integral: h o f = h)", f"{name} = {h} satisfies h(f(x)) = h(x) identically.",
                       fixed={k: str(v) for k, v in (fixed or {}).items()})
    try:
        with cert.step("h o f = h", "substitution h(N/Delta) - h", kmap.ring) as s:
            verdict = check_integral(kmap, h.to_ring(kmap.ring))
            s.require(verdict.status is Status.VERIFIED,
                      f"{verdict.method} is not zero in {verdict.ring} ({verdict.difference_terms} terms)")
            s.note(f"{verdict.method} = 0 in {verdict.ring}")
        cert.checks.append(substitution_step(kmap.field, name, h.to_ring(kmap.ring)))
    except ProofStopped as exc:
        cert.error = str(exc)
    cert.formula(name, h)
    return cert


def is_phase_constant(h: Frac, variables: Sequence[str]) -> bool:
    """True when h involves no phase variable (a constant integral: trivial)."""
    return not (h.variables() & set(variables))


def independent_subset(functions: Sequence[Frac], variables: Sequence[str],
                       points: Sequence[Mapping[str, Rational]]) -> list[int]:
    """Indices of a maximal subset whose Jacobian has full rank at one of `points` (exact; proves independence).
    Each gradient is evaluated at most once per point (the chosen ones are reused for every later trial): for large
    kernel coordinates the evaluations, not the small ranks, are the cost."""
    rows: dict[tuple[int, int], list[flint.fmpq] | None] = {}

    def row(i: int, k: int) -> list[flint.fmpq] | None:
        if (i, k) not in rows:
            try:
                rows[i, k] = gradient_at(functions[i], variables, points[k])
            except SingularPointError:
                rows[i, k] = None
        return rows[i, k]

    chosen: list[int] = []
    for i in range(len(functions)):
        for k in range(len(points)):
            trial = [r for r in (row(j, k) for j in [*chosen, i]) if r is not None]
            if len(trial) == len(chosen) + 1 and flint.fmpq_mat(trial).rank() == len(trial):
                chosen.append(i)
                break
    return chosen


def jacobian_points(names: Sequence[str], count: int = 3, seed: int = 11) -> list[dict[str, flint.fmpq]]:
    """A few reproducible rational points fixing every name (for exact Jacobian ranks)."""
    import random
    rng = random.Random(seed)
    return [random_point(rng, names, 97, denominator=89)
            for _ in range(count)]
