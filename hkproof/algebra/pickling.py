"""FLINT's multivariate polynomials over Z sent to other processes as data: a context as its names and ordering, a
polynomial as its exponent vectors and coefficients (python-flint 0.9 pickles neither), so that the parts of one
computation -- the points of a lattice, the primes of a modular identity -- can run as tasks on Dask workers.
Registered with `copyreg` when this module is imported (hkproof.orchestration.execution imports it).

>>> import pickle
>>> ctx = flint.fmpz_mpoly_ctx.get(("x", "y"), "deglex")
>>> x, y = ctx.gens()
>>> pickle.loads(pickle.dumps(3 * x**2 * y - 2**70))
3*x^2*y - 1180591620717411303424
"""
from __future__ import annotations

import copyreg

import flint

__all__ = ["register"]


def _context(names: tuple[str, ...], ordering: str) -> flint.fmpz_mpoly_ctx:
    return flint.fmpz_mpoly_ctx.get(names, ordering)


def _reduce_context(ctx: flint.fmpz_mpoly_ctx) -> tuple:
    return _context, (tuple(ctx.names()), ctx.ordering().name)


def _polynomial(ctx: flint.fmpz_mpoly_ctx, monomials: list[tuple[int, ...]], coefficients: list[int]
                ) -> flint.fmpz_mpoly:
    return ctx.from_dict(dict(zip(monomials, coefficients, strict=True)))


def _reduce_polynomial(p: flint.fmpz_mpoly) -> tuple:
    return _polynomial, (p.context(), [tuple(int(e) for e in m) for m in p.monoms()], [int(c) for c in p.coeffs()])


def register() -> None:
    """Teach pickle (and Dask's cloudpickle) to send FLINT's polynomials over Z and their contexts as data."""
    copyreg.pickle(flint.fmpz_mpoly_ctx, _reduce_context)
    copyreg.pickle(flint.fmpz_mpoly, _reduce_polynomial)


register()
