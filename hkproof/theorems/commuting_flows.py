"""Section 7 (Conclusions): the Kahan maps of the first and second Clebsch flows do not commute, and do not share the
integrals proven here.  Both are negative statements decided exactly: one rational point where an identity of
rational functions fails refutes the identity in Q(m, p, eps, w) (the same eps for both maps)."""
from __future__ import annotations

from typing import Mapping

import flint

from hkproof.algebra.formula import split_list
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.kahan import KahanMap, commutator_at
from hkproof.errors import ParseError
from hkproof.hk.integrals import point_text, shared_integrals
from hkproof.orchestration.registry import claim, require_proven
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import recall

__all__ = ["FIRST_FLOW_INTEGRALS", "GROUP", "prove_commutation", "prove_shared_integrals", "SECOND_FLOW_INTEGRALS",
           "SYMBOLIC_LIMIT", "WITNESS", "WITNESS_RING"]

GROUP = "commuting-flows"
FLOW1, FLOW2 = "clebsch", "clebsch-flow2"
WITNESS: dict[str, Rational] = {"m1": 1, "m2": 2, "m3": -1, "p1": 3, "p2": 1, "p3": 2, "eps": flint.fmpq(1, 5), "w1": 1, "w2": 2, "w3": 3}
FIRST_FLOW_INTEGRALS = {"dc-basis1-even": ("c1", "c2", "c3"), "dc-basis2": ("d7", "d8", "d9"),
                        "dc-theta": ("g1", "g2", "g3", "g4", "g5", "g6"), "dc345-abcd": ("A", "B", "C", "D")}
SECOND_FLOW_INTEGRALS = {"flow-second-theorem": ("L",)}
# a non-identity of rational functions is refuted in the full ring by one point: the step is not a specialization
WITNESS_RING = "Q(m, p, eps, w) (identity refuted at one rational point)"
SYMBOLIC_LIMIT = 2000     # terms of an integral above which a point check that passes is not followed by substitution


@claim("flows-commutation", GROUP, "The Kahan maps of the first and second Clebsch flows do not commute",
       "sec. 7, Conclusions (\"the maps ... of various flows do not commute with each other\")",
       "f1 o f2 != f2 o f1 for the Kahan maps f1 (catalogue clebsch) and f2 (clebsch-flow2) with the same eps and w: "
       "at the witness point (m, p) = (1, 2, -1, 3, 1, 2), eps = 1/5, w = (1, 2, 3) the m1-components differ by the "
       "claimed exact rational (hkproof's eps: half the time step).",
       claimed={"commute": "no",
                "difference_m1": "-24056552791507520886873984228237120482025360/"
                                 "6373907870547081326057869926502922773491157"})
def prove_commutation(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f1, f2 = kahan_map(FLOW1), kahan_map(FLOW2)
    answer = claimed["commute"].strip()
    if answer not in ("yes", "no"):
        raise ParseError(f"'commute' must be yes or no, got {answer!r}")
    with cert.step("commutator at a rational point", f"f1(f2(x)) - f2(f1(x)) by exact solves over Q at "
                   f"{point_text(WITNESS)}", WITNESS_RING) as s:
        diff = commutator_at(f1, f2, WITNESS)
        differs = any(d != 0 for d in diff.values())
        if answer == "no":
            s.require(differs, "the maps agree at the witness: commutativity is not refuted there")
        else:
            s.require(not differs, f"the maps differ at {point_text(WITNESS)}: they do not commute")
            s.evidence(Status.EVIDENCE_EXACT, 1)
        want = Frac.parse(f1.ring, claimed["difference_m1"])
        s.require(want.is_polynomial() and want.num.is_constant() and diff["m1"] == want.evaluate(WITNESS),
                  f"the m1-component of f1(f2(x)) - f2(f1(x)) is {diff['m1']}, not {claimed['difference_m1']}")
        s.note("differences: " + ", ".join(f"{v}: {d}" for v, d in diff.items()))
        s.note("one point where f1 o f2 and f2 o f1 differ refutes the identity f1 o f2 = f2 o f1 in "
               "Q(m, p, eps, w): a verified negative statement (and for generic eps, w, since it fails on an open set)")
        cert.formula("witness", point_text(WITNESS))
        for v, d in diff.items():
            cert.formula(f"difference_{v}", str(d))


def _integrals(cert: Certificate, sources: Mapping[str, tuple[str, ...]], kmap: KahanMap) -> dict[str, Frac]:
    out = {}
    for claim_id, names in sources.items():
        dep = require_proven(cert, claim_id)
        for n in names:
            out[n] = recall(dep, n, kmap.ring)
    return out


def _names(text: str, known: Mapping[str, Frac]) -> list[str]:
    """The names in a claimed list 'c1, d7' (or 'none'), each one of the integrals compared."""
    names = [] if text.strip() == "none" else split_list(text, "list of integrals")
    unknown = [n for n in names if n not in known]
    if unknown:
        raise ParseError(f"{unknown} are not among the integrals compared ({sorted(known)}); write 'none' or names")
    return sorted(names)


@claim("flows-shared-integrals", GROUP, "The Kahan maps of the two Clebsch flows share none of the integrals proven "
       "here", "sec. 7, Conclusions (commutativity of the discrete flows)",
       "None of the first-flow integrals c1, c2, c3 (dc-basis1-even), d7, d8, d9 (dc-basis2), g1..g6 (dc-theta), "
       "A, B, C, D (dc345-abcd) is an integral of the second flow's Kahan map, and the second-flow integral L "
       "(flow-second-theorem) is not an integral of the first flow's Kahan map (same eps and w for both maps; eps is half "
       "the time step).",
       claimed={"shared_by_second_flow": "none", "shared_by_first_flow": "none"},
       uses=[*FIRST_FLOW_INTEGRALS, *SECOND_FLOW_INTEGRALS])
def prove_shared_integrals(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f1, f2 = kahan_map(FLOW1), kahan_map(FLOW2)
    first = _integrals(cert, FIRST_FLOW_INTEGRALS, f1)
    second = _integrals(cert, SECOND_FLOW_INTEGRALS, f2)
    claim_12 = _names(claimed["shared_by_second_flow"], first)
    claim_21 = _names(claimed["shared_by_first_flow"], second)
    found_12 = sorted(shared_integrals(cert, first, f2, "first-flow integrals under the second flow's map", WITNESS,
                                       WITNESS_RING, SYMBOLIC_LIMIT))
    found_21 = sorted(shared_integrals(cert, second, f1, "second-flow integral L under the first flow's map", WITNESS,
                                       WITNESS_RING, SYMBOLIC_LIMIT))
    with cert.step("the claimed lists", "comparison", "-") as s:
        s.require(found_12 == claim_12, f"first-flow integrals preserved by f2: {found_12 or 'none'}, claimed "
                  f"{claim_12 or 'none'}")
        s.require(found_21 == claim_21, f"second-flow integrals preserved by f1: {found_21 or 'none'}, claimed "
                  f"{claim_21 or 'none'}")
    cert.formula("shared_by_second_flow", ", ".join(found_12) or "none")
    cert.formula("shared_by_first_flow", ", ".join(found_21) or "none")
