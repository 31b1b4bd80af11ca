"""The printed data of section 6.7 (Th. "dC bases 345"), read by the claims of this group and by the Clebsch flows:
the bases Phi1, Phi2, Phi3, the unknowns alpha_j, beta_j, gamma_j, eqs. "rel18_1" ... "rel18_8", "M2", the six
relations "dC Psi add lin rel 1" ... "6", eq. "ABCD dependence" and the printed forms A^(2), D^(4)."""
from __future__ import annotations

from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.hk.linear_relations import parse_relation_chain
from hkproof.hk.reduced import Relation

__all__ = ["ABCD_DEPENDENCE", "ADD", "ADD_ABCD", "A_2", "BLOCK", "COMMON", "D_4", "F_TEXT", "GROUP", "M2", "REL18",
           "REL18_EXTRA", "TARGETS", "UNKNOWNS", "bases", "relation_rows"]

GROUP = "clebsch-bases-345"
COMMON = ("p1**2", "p2**2", "p3**2", "m1**2", "m2**2", "m3**2")
TARGETS = ("m1*p1", "m2*p2", "m3*p3")
UNKNOWNS = tuple(f"{c}{j}" for c in "abc" for j in range(1, 7))   # a_j = alpha_j, b_j = beta_j, c_j = gamma_j
BLOCK = {c: [UNKNOWNS.index(f"{c}{j}") for j in range(1, 7)] for c in "abc"}   # the unknowns of each basis

REL18 = {
    "rel18_1": "(w1 - w3)*a5 = (w1 - w2)*a6",
    "rel18_2": "(w2 - w3)*b4 = (w2 - w1)*b6",
    "rel18_3": "(w3 - w2)*c4 = (w3 - w1)*c5",
    "rel18_4": "a4 = b5 = c6",
    "rel18_6": "(a2 - a3 - (w2 - w3)*a4)/(w2 - w3) = (b2 - b3 - (w2 - w3)*b4)/(w3 - w1)"
               " = (c2 - c3 - (w2 - w3)*c4)/(w1 - w2)",
    "rel18_8": "(a3 - a1 - (w3 - w1)*a5)/(w2 - w3) = (b3 - b1 - (w3 - w1)*b5)/(w3 - w1)"
               " = (c3 - c1 - (w3 - w1)*c5)/(w1 - w2)",
}
REL18_EXTRA = ("(a1 - a2 - (w1 - w2)*a6)/(w2 - w3) = (b1 - b2 - (w1 - w2)*b6)/(w3 - w1)"
               " = (c1 - c2 - (w1 - w2)*c6)/(w1 - w2)")
F_TEXT = "(w2 - w3)*a1 + (w3 - w1)*a2 + (w1 - w2)*a3"
M2 = ("a4 = D, a5 = A/(w1 - w3), a6 = A/(w1 - w2), b4 = B/(w2 - w3), b5 = D, b6 = B/(w2 - w1), "
      "c4 = C/(w3 - w2), c5 = C/(w3 - w1), c6 = D")
ADD = {
    "add_1": "a4 - b4 - c4 = d7/2", "add_2": "-a5 + b5 - c5 = d8/2", "add_3": "-a6 - b6 + c6 = d9/2",
    "add_4": "a4 + b4 + c4 = g4", "add_5": "a5 + b5 + c5 = g5", "add_6": "a6 + b6 + c6 = g6",
}
ADD_ABCD = {
    "add_1_abcd": "D - (B - C)/(w2 - w3) = d7/2", "add_2_abcd": "D - (C - A)/(w3 - w1) = d8/2",
    "add_3_abcd": "D - (A - B)/(w1 - w2) = d9/2", "add_4_abcd": "D + (B - C)/(w2 - w3) = g4",
    "add_5_abcd": "D + (C - A)/(w3 - w1) = g5", "add_6_abcd": "D + (A - B)/(w1 - w2) = g6",
}
ABCD_DEPENDENCE = ("D**2 - A*B/((w1 - w3)*(w2 - w3)) - B*C/((w2 - w1)*(w3 - w1)) "
                   "- C*A/((w3 - w2)*(w1 - w2)) = 0")
A_2 = "m1**2 + m2**2 + m3**2 + (w2 + w3 - 2*w1)*p1**2 + (w3 + w1 - 2*w2)*p2**2 + (w1 + w2 - 2*w3)*p3**2"
D_4 = ("(m1*p1 + m2*p2 + m3*p3)**2 + (p1**2 + p2**2 + p3**2)*((w2 + w3 - 2*w1)*p1**2 "
       "+ (w3 + w1 - 2*w2)*p2**2 + (w1 + w2 - 2*w3)*p3**2)")


def bases(f) -> list[list[Frac]]:
    """Phi1, Phi2, Phi3 of eqs. "dC basis Psi1" ... "dC basis Psi3" (the last element is the normalized one)."""
    common = [Frac.parse(f.ring, t) for t in COMMON]
    return [common + [Frac.parse(f.ring, t)] for t in TARGETS]


def relation_rows(f, text: str, unknowns: Sequence[str] = UNKNOWNS,
                  known: Mapping[str, Frac] | None = None) -> list[Relation]:
    """A printed chain of this section as relations among alpha_j, beta_j, gamma_j (the default unknowns)."""
    return parse_relation_chain(f.ring, text, unknowns, known)
