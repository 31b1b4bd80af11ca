"""The matrices X_[0,k](x) of eq. "balance" at exact rational points: rows (phi_1, ..., phi_l) along an orbit."""
from __future__ import annotations

from typing import Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational
from hkproof.dynamics.kahan import KahanMap

__all__ = ["orbit_matrix"]


def orbit_matrix(kmap: KahanMap, functions: Sequence[Frac], point: Mapping[str, Rational], rows: int) -> flint.fmpq_mat:
    """X_[0, rows-1] at `point` (phase variables, eps and parameters all fixed): row i is phi(f^i(x)), exactly over Q.

    A non-zero k x k minor here is a rational function of (x, eps, parameters) that is non-zero at this point, hence
    not identically zero: an exact rank at one point is a lower bound for the generic rank.
    """
    fixed = {k: v for k, v in point.items() if k not in kmap.variables}
    orbit = kmap.orbit_exact(point, rows - 1)
    return flint.fmpq_mat([[h.evaluate({**fixed, **x}) for h in functions] for x in orbit])
