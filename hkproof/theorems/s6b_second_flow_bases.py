"""Section 6, the conjecture after eq. "dC2 map": the second flow's bases Phi1, Phi2, Phi3 (p^2, m^2, m_k p_k).

hkproof's own discovery (recipe (E) with the integral L as an extra column): the kernel coordinates alpha, beta,
gamma of the second flow satisfy 23 linear relations with coefficients in Z[eps^2, w] + L Z[eps^2, w] (nine with
constant coefficients, their L-multiples, and five new ones). Recorded as evidence with the exact facts that make
them a proof route: with the rows i = 0 they leave one unknown, with the rows i = 0, 1 none.
"""
from __future__ import annotations

from typing import Mapping

import flint

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import EPS
from hkproof.experiments.relations import find_relations
from hkproof.hk.linear_relations import parse_relation, relation_rank
from hkproof.hk.reduced import Relation, orbit_points
from hkproof.proof.certificate import Certificate
from hkproof.proof.registry import claim, require_proven
from hkproof.proof.status import Status
from hkproof.theorems.s6b_clebsch_bases_345 import UNKNOWNS, bases
from hkproof.theorems.s6c_clebsch_flows import FLOW2, GROUP, RANK_POINT

L_NAMES = tuple(f"L{u}" for u in UNKNOWNS)     # L a_j, L b_j, L c_j: kernel coordinates of (p^2, m^2, L m_k p_k)
# As found by hkproof (benchmarks/clebsch_flows.py reruns the search; the claim below checks the span again).
SECOND_PHI_RELATIONS = {
    "phirel_1": "b2*w2 - b5*w1*w3 - c3*w3 + c6*w1*w2 = 0",
    "phirel_2": "Lb2*w2 - Lb5*w1*w3 - Lc3*w3 + Lc6*w1*w2 = 0",
    "phirel_3": "a1*w1 - a4*w2*w3 - b2*w2 + b5*w1*w3 = 0",
    "phirel_4": "a2*w2*(w1 - w3) - a3*w3*(w1 - w2) - a5*w1*w3*(w1 - w3) + a6*w1*w2*(w1 - w2) = 0",
    "phirel_5": "La1*w1 - La4*w2*w3 - Lb2*w2 + Lb5*w1*w3 = 0",
    "phirel_6": "La2*w2*(w1 - w3) - La3*w3*(w1 - w2) - La5*w1*w3*(w1 - w3) + La6*w1*w2*(w1 - w2) = 0",
    "phirel_7": "b1*w1*(w2 - w3) + b3*w3*(w1 - w2) - b4*w2*w3*(w2 - w3) - b6*w1*w2*(w1 - w2) = 0",
    "phirel_8": "c1*w1*(w2 - w3) - c2*w2*(w1 - w3) - c4*w2*w3*(w2 - w3) + c5*w1*w3*(w1 - w3) = 0",
    "phirel_9": "Lb1*w1*(w2 - w3) + Lb3*w3*(w1 - w2) - Lb4*w2*w3*(w2 - w3) - Lb6*w1*w2*(w1 - w2) = 0",
    "phirel_10": "Lc1*w1*(w2 - w3) - Lc2*w2*(w1 - w3) - Lc4*w2*w3*(w2 - w3) + Lc5*w1*w3*(w1 - w3) = 0",
    "phirel_11": "-La2*eps**2 + La3*eps**2 + a2*w1 - a3*w1 - a5*w1*(w1 - w3) + a6*w1*(w1 - w2) = 0",
    "phirel_12": "a2 - a3 + a4*(-w2 + w3) + b2 - b3 + b4*(-w2 + w3) + c2 - c3 + c4*(-w2 + w3) = 0",
    "phirel_13": "a1 - a3 + a5*(-w1 + w3) + b1 - b3 + b5*(-w1 + w3) + c1 - c3 + c5*(-w1 + w3) = 0",
    "phirel_14": "La4*eps**2*(w1 - w3) - Lb2*eps**2 + Lb3*eps**2 + Lb4*eps**2*(w2 - w3) + b2*w1 - b3*w1 - "
                  "b5*w1*(w1 - w3) + b6*w1*(w1 - w2) = 0",
    "phirel_15": "-La1*eps**2*w1 + 2*La2*eps**2*w1 - 2*La6*eps**2*w1*w2 + Lb2*eps**2*w2 - 2*Lb6*eps**2*w1*w2 - "
                  "Lc3*eps**2*w3 + 2*a1*w1**2 - 2*a2*w1**2 - 2*a3*w1*w3 - 2*a6*w1**2*(w1 - 2*w2) - 2*b3*w1*w3 + "
                  "2*b6*w1**2*w2 = 0",
    "phirel_16": "-La4*eps**2*w3 + La6*eps**2*w1 - Lb3*eps**2 + Lb6*eps**2*w1 + a1*w1 + a3*(-w1 + w3) - a4*w1*(w2 "
                  "- w3) - a6*w1**2 - b2*w2 + b3*w3 + b5*w1*w3 - b6*w1*w2 = 0",
    "phirel_17": "-La4*eps**2*w2 + La5*eps**2*w1 - Lc2*eps**2 + Lc5*eps**2*w1 + 2*a1*w1 + a2*(-w1 + w2) - a3*w1 + "
                  "a4*w1*(w2 - w3) - a5*w1*(2*w1 - w3) + b1*w1 - b2*w2 - b3*w1 - b5*w1*(w1 - 2*w3) + c1*w1 + c2*w2 "
                  "- c3*w1 - c5*w1**2 = 0",
    "phirel_18": "La2*eps**2 - La4*eps**2*w3 - La6*eps**2*w2 + Lb1*eps**2 - Lb2*eps**2 - Lb3*eps**2 + "
                  "Lb5*eps**2*w3 - Lb6*eps**2*w2 + Lc1*eps**2 - Lc2*eps**2 - Lc6*eps**2*w1 + 3*a1*w1 - 2*a2*w1 + "
                  "a3*(-w1 - w3) - a4*w1*(w2 - w3) - a6*w1*(3*w1 - 4*w2) - b2*w2 - b3*w3 + b5*w1*w3 + b6*w1*w2 = 0",
    "phirel_19": "-La1*eps**2 + 2*La2*eps**2 - La5*eps**2*w3 - La6*eps**2*w2 - Lb6*eps**2*w2 - Lc5*eps**2*w3 + "
                  "a1*w1 + a2*(-2*w1 - w2) + a3*(w1 - w3) + a5*w1**2 - a6*w1*(2*w1 - 3*w2) - b1*w1 + b3*(w1 - w3) + "
                  "b5*w1*(w1 - w3) + b6*w1*w2 - c1*w1 - c2*w2 + c3*w1 + c5*w1**2 = 0",
    "phirel_20": "La2*eps**2 - La4*eps**2*w2 - La6*eps**2*w2 + Lb1*eps**2 - Lb3*eps**2 - Lb5*eps**2*(w1 - w3) - "
                  "Lb6*eps**2*w2 + Lc1*eps**2 - Lc2*eps**2 - Lc3*eps**2 + 3*a1*w1 - 2*a2*w1 + a3*(-w1 - w3) + "
                  "a4*w1*(w2 - w3) - 2*a5*w1*(w1 - w3) - a6*w1*(w1 - 2*w2) - b2*w2 - b3*w3 + b5*w1*w3 + b6*w1*w2 = "
                  "0",
    "phirel_21": "-Lb1*eps**2 + Lb3*eps**2 + b1*w2 - b3*w2 - b4*w2*(w2 - w3) - b6*w2*(w1 - w2) = 0",
    "phirel_22": "La4*eps**2*w2 + Lb5*eps**2*w1 + Lc3*eps**2 + 2*a3*w1 - 2*a4*w2*w3 + 2*a5*w1*(w1 - w3) - 2*b2*w2 "
                  "+ 2*b3*w2 + 2*b4*w2*(w2 - w3) = 0",
    "phirel_23": "La4*eps**2*w2*w3 + Lb2*eps**2*w2 + Lc6*eps**2*w1*w2 + 2*a3*w1**2 - 2*a4*w1*w2*w3 + "
                  "2*a5*w1**2*(w1 - w3) - 2*b2*w1*w2 + 2*b3*w1*w2 + 2*b5*w1*w2*(w1 - w3) - 2*b6*w1*w2*(w1 - w2) = 0",
}
RANKS = {"relations": "14", "rows0": "17", "rows01": "18"}


def _combined(rel: Relation, big_l: Frac) -> Relation:
    """A relation among (a, L a) as one among a with coefficients c_k + d_k L."""
    n = len(UNKNOWNS)
    return Relation([rel.coefficients[k] + big_l * rel.coefficients[n + k] for k in range(n)], rel.rhs,
                    "L is an even integral (flow-second-theorem)")


@claim("flow-second-l-relations-found", GROUP, "Second flow: 23 relations among alpha, beta, gamma with "
       "coefficients linear in the integral L, found by recipe (E)",
       "sec. 6, conjecture after eq. \"dC2 map\" (not in the paper)",
       "Recipe (E) on the bases Phi_k = (p^2, m^2, m_k p_k) and Phi_k' = (p^2, m^2, L m_k p_k) of the second flow "
       "(whose kernel coordinates are alpha, ... and L alpha, ..., L being an integral) finds a 23-dimensional "
       "space of relations, spanned by the claimed ones; their coefficients are even in eps. Read as relations "
       "among alpha, beta, gamma with coefficients in Q(eps, w)[L] they have rank `relations`; at a rational point "
       "the rows i = 0 add up to rank `rows0` and the rows i = 0, 1 to `rows01` (so alpha, beta, gamma would follow "
       "from one row with an iterate, by Prop. \"prop: even\"). Evidence, not proof.",
       claimed={**SECOND_PHI_RELATIONS, **RANKS}, slow=True, expected=Status.EVIDENCE_EXACT)
def prove_l_relations_found(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(FLOW2)
    r = f.ring
    big_l = Frac.parse(r, require_proven(cert, "flow-second-theorem").formulas["L"])
    names = [*UNKNOWNS, *L_NAMES]
    phis = bases(f)
    with cert.step("the claimed relations: coefficients even in eps", "exact parity, Q(eps, w)", r) as s:
        rels = [parse_relation(r, claimed[k], names) for k in SECOND_PHI_RELATIONS]
        for k, rel in zip(SECOND_PHI_RELATIONS, rels):
            s.require(all(c.is_even_in(EPS) for c in (*rel.coefficients, rel.rhs)), f"{k} is not even in eps")
        s.require(relation_rank(rels) == len(rels), "the claimed relations are not independent")
    with cert.step("recipe (E) with the columns L alpha, L beta, L gamma: the space is spanned by the claimed "
                   "relations", "exact kernels at rational points, interpolation in eps and w, fresh checks", r) as s:
        search = find_relations(f, [*phis, *[b[:6] + [big_l * b[6]] for b in phis]], names=names)
        found = [Relation(rel.coefficients, rel.rhs) for rel in search.relations]
        s.require(search.dimension == len(rels) == len(found),
                  f"relation space of dimension {search.dimension}, {len(found)} reconstructed, {len(rels)} claimed")
        s.require(relation_rank(found + rels) == len(rels), "a claimed relation is not in the space found")
        s.evidence(Status.EVIDENCE_EXACT, points=search.samples)
    combined = [_combined(rel, big_l) for rel in rels]
    with cert.step("ranks: the relations, with rows i = 0, with rows i = 0, 1", "exact ranks at a rational point "
                   "(values of Phi_k o f^i and of the relations' coefficients)", "Q at one rational point") as s:
        point = {k: v for k, v in RANK_POINT.items() if k in r.names}
        orbit = orbit_points(f, point, (0, 1))
        rel_rows = [[c.evaluate(point) for c in rel.coefficients] for rel in combined]

        def hk_rows(i: int) -> list[list[flint.fmpq]]:
            return [[phis[b][k % 6].evaluate(orbit[i]) if k // 6 == b else flint.fmpq(0) for k in range(18)]
                    for b in range(3)]

        for key, rows in (("relations", rel_rows), ("rows0", hk_rows(0) + rel_rows),
                          ("rows01", hk_rows(0) + hk_rows(1) + rel_rows)):
            got = flint.fmpq_mat(rows).rank()
            s.require(str(got) == claimed[key].strip(), f"rank {key} = {got}, claimed {claimed[key]}")
        s.evidence(Status.EVIDENCE_EXACT, points=1)
        s.note("rank 18 with rows i = 0, 1 only and relations whose coefficients are even integrals: the hypotheses of "
               "Prop. \"prop: even\" hold; what remains for a proof is the symbolic solve (one row with an iterate "
               "after eliminating 17 unknowns) and the substitution of the solution into the rows i = 1")
