"""Exact algebra on python-flint: rings, fractions, linear algebra."""
from hkproof.algebra.fraction import Frac, Parity, homogenized_compose, poly_str
from hkproof.algebra.linalg import cramer, det, nullspace_q, rank_q
from hkproof.algebra.modular import rank_mod_p
from hkproof.algebra.ring import Ring, get_ring, to_fmpq

__all__ = ["Frac", "Parity", "Ring", "cramer", "det", "get_ring", "homogenized_compose", "nullspace_q",
           "poly_str", "rank_mod_p", "rank_q", "to_fmpq"]
