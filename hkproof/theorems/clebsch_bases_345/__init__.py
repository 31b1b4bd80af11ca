"""Group `clebsch-bases-345` (paper, sec. 6.7, Th. "dC bases 345"): the printed data (data), the relations, A, B, C, D
and Step 1 (claims), Steps 2-5 and Th. "dClebsch max basis" (steps). Script: proofs/clebsch_bases_345.py."""
from hkproof.theorems.clebsch_bases_345 import claims, steps

__all__ = ["claims", "steps"]
