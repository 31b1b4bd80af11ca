"""Quadratic vector fields, their Kahan maps, and the catalogue of the paper's systems."""
from hkproof.dynamics.catalogue import SYSTEMS, get_system, kahan_map
from hkproof.dynamics.field import EPS, QuadraticField
from hkproof.dynamics.kahan import KahanMap

__all__ = ["EPS", "KahanMap", "QuadraticField", "SYSTEMS", "get_system", "kahan_map"]
