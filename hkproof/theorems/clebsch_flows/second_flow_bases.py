"""Section 6, the conjecture after eq. "dC2 map": the second flow's bases Phi1, Phi2, Phi3 (p^2, m^2, m_k p_k).

hkproof's own discovery (recipe (E) with the integral L as an extra column): the kernel coordinates alpha, beta,
gamma of the second flow satisfy 23 linear relations with coefficients in Z[eps^2, w] + L Z[eps^2, w] (nine with
constant coefficients, their L-multiples, and five new ones). Recorded as evidence with the exact facts that make
them a proof route: with the rows i = 0 they leave one unknown, with the rows i = 0, 1 none.
"""
from __future__ import annotations

from typing import Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational, Ring
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.experiments.relations import find_relations
from hkproof.hk.balance import orbit_matrix
from hkproof.hk.block_system import BlockSymmetry, BlockSystem, verify_candidate
from hkproof.hk.completion import complete_coordinates
from hkproof.hk.independence import jacobian_rank_at
from hkproof.hk.linear_relations import parse_relation, relation_rank
from hkproof.hk.reduced import Relation, kernel_coordinates, system_at
from hkproof.hk.transport import Substitution
from hkproof.orchestration.registry import claim, require_proven
from hkproof.proof.certificate import Certificate, Refuted, StepRecorder
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import CYCLIC_SHIFT, recall, record, shift_frac
from hkproof.theorems.clebsch_bases_345.data import UNKNOWNS, bases
from hkproof.theorems.clebsch_flows.general import (
    FLOW2,
    GROUP,
    PHI_MAX_TEXT,
    RANK_POINT,
    SUB_BASES,
)

__all__ = ["embedded_vectors", "INDEX_SHIFT", "L_NAMES", "lifted_relations", "max_basis_facts", "PERM",
           "prove_l_relations_found", "prove_second_bases", "RANKS", "SAMPLES", "screen_at_samples",
           "SECOND_PHI_RELATIONS"]

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


SAMPLES: tuple[dict[str, Rational], ...] = ({"eps": flint.fmpq(1, 3), "w1": 2, "w2": -3, "w3": 5, "m1": 1, "m2": 2, "m3": -1, "p1": 3, "p2": -2,
             "p3": 1}, {"eps": flint.fmpq(2, 5), "w1": -1, "w2": 4, "w3": 7, "m1": 2, "m2": -3, "m3": 1, "p1": 1,
                        "p2": 5, "p3": -4})


def screen_at_samples(s: StepRecorder, f: KahanMap, claimed: Mapping[str, str], big_l: Frac) -> None:
    """Each claimed relation holds for the exact kernel coordinates at two rational points: a fast refutation
    before any symbolic work (passing proves nothing by itself)."""
    general = f.ring.extend([*UNKNOWNS, *L_NAMES])
    for point in SAMPLES:
        coords = kernel_coordinates(f, bases(f), point)
        if coords is None:
            raise Refuted(f"a kernel is not one-dimensional at {point}")
        l0 = big_l.evaluate(point)
        values = {**point, **dict(zip(UNKNOWNS, coords, strict=True)),
                  **dict(zip(L_NAMES, (l0 * c for c in coords), strict=True))}
        for key in SECOND_PHI_RELATIONS:
            s.require(claimed[key].count("=") == 1, f"{key} is not an equation")
            lhs, rhs = claimed[key].split("=")
            value = Frac.parse(general, f"({lhs}) - ({rhs})").evaluate(values)
            s.require(value == 0, f"{key} fails at the rational point {point} ({value})")


@claim("flow-second-l-relations-found", GROUP, "Second flow: 23 relations among alpha, beta, gamma with "
       "coefficients linear in the integral L, found by recipe (E)",
       "sec. 6, conjecture after eq. \"dC2 map\" (not in the paper)",
       "Recipe (E) on the bases Phi_k = (p^2, m^2, m_k p_k) and Phi_k' = (p^2, m^2, L m_k p_k) of the second flow "
       "(whose kernel coordinates are alpha, ... and L alpha, ..., L being an integral) finds a 23-dimensional "
       "space of relations, spanned by the claimed ones; their coefficients are even in eps. Read as relations "
       "among alpha, beta, gamma with coefficients in Q(eps, w)[L] they have rank `relations`; at a rational point "
       "the rows i = 0 add up to rank `rows0` and the rows i = 0, 1 to `rows01` (so alpha, beta, gamma would follow "
       "from one row with an iterate, by Prop. \"prop: even\"). Evidence, not proof.",
       claimed={**SECOND_PHI_RELATIONS, **RANKS}, expected=Status.EVIDENCE_EXACT, uses=["flow-second-theorem"])
def prove_l_relations_found(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(FLOW2)
    r = f.ring
    big_l = Frac.parse(r, require_proven(cert, "flow-second-theorem").formulas["L"])
    names = [*UNKNOWNS, *L_NAMES]
    phis = bases(f)
    with cert.step("the claimed relations: coefficients even in eps", "exact parity, Q(eps, w)", r) as s:
        rels = [parse_relation(r, claimed[k], names) for k in SECOND_PHI_RELATIONS]
        for k, rel in zip(SECOND_PHI_RELATIONS, rels, strict=True):
            s.require(all(c.is_even_in(EPS) for c in (*rel.coefficients, rel.rhs)), f"{k} is not even in eps")
        s.require(relation_rank(rels) == len(rels), "the claimed relations are not independent")
    with cert.step("the claimed relations at two rational points", "exact kernels of X_[0,6] (fmpq_mat)", r,
                   fixed={"points": len(SAMPLES)}) as s:
        screen_at_samples(s, f, claimed, big_l)
    combined = [_combined(rel, big_l) for rel in rels]
    with cert.step("ranks: the relations, with rows i = 0, with rows i = 0, 1", "exact ranks at a rational point "
                   "(values of Phi_k o f^i and of the relations' coefficients)", "Q at one rational point") as s:
        point = {k: v for k, v in RANK_POINT.items() if k in r.names}
        rel_rows = [[c.evaluate(point) for c in rel.coefficients] for rel in combined]
        for key, rows in (("relations", rel_rows), ("rows0", system_at(f, phis, (0,), combined, point)[0]),
                          ("rows01", system_at(f, phis, (0, 1), combined, point)[0])):
            got = flint.fmpq_mat(rows).rank()
            s.require(str(got) == claimed[key].strip(), f"rank {key} = {got}, claimed {claimed[key]}")
        s.evidence(Status.EVIDENCE_EXACT, points=1)
        s.note("rank 18 with rows i = 0, 1 only and relations whose coefficients are even integrals: the hypotheses of "
               "Prop. \"prop: even\" hold; what remains for a proof is the symbolic solve (one row with an iterate "
               "after eliminating 17 unknowns) and the substitution of the solution into the rows i = 1")
    with cert.step("recipe (E) with the columns L alpha, L beta, L gamma: the space is spanned by the claimed "
                   "relations", "exact kernels at rational points (those of (p^2, m^2, L m_k p_k) as L times those of "
                   "Phi_k, L being an integral), interpolation in eps and w, fresh checks", r) as s:
        search = find_relations(f, [*phis, *[b[:6] + [big_l * b[6]] for b in phis]], names=names,
                                integrals=[big_l])
        found = [Relation(rel.coefficients, rel.rhs) for rel in search.relations]
        s.require(search.dimension == len(rels) == len(found),
                  f"relation space of dimension {search.dimension}, {len(found)} reconstructed, {len(rels)} claimed")
        s.require(relation_rank(found + rels) == len(rels), "a claimed relation is not in the space found")
        s.evidence(Status.EVIDENCE_EXACT, points=search.samples)


# ---------------------------------------------------------------- Phi1, Phi2, Phi3 with w symbolic: Prop. "prop: even" ---
# The index shift tau (1 -> 2 -> 3 in m, p, w) carries Phi1 to Phi2 and Phi2 to Phi3: tau(Phi_k[PERM[j]]) = Phi_k+1[j]
PERM = (2, 0, 1, 5, 3, 4, 6)
INDEX_SHIFT = BlockSymmetry(shift_frac, CYCLIC_SHIFT.commutes, ((0, 1, PERM), (1, 2, PERM)))


def lifted_relations(claimed: Mapping[str, str], ring: Ring) -> list[Relation]:
    """The claimed relations over Q(eps, w)[L], L a symbol (`_combined`); each must be homogeneous."""
    lifted = ring.extend(["L"])
    out = []
    for key in SECOND_PHI_RELATIONS:
        rel = parse_relation(lifted, claimed[key], [*UNKNOWNS, *L_NAMES])
        if not rel.rhs.is_zero():
            raise Refuted(f"{key} is not homogeneous")
        out.append(_combined(rel, Frac(lifted, lifted.gen("L"))))
    return out


@claim("flow-second-bases-345", GROUP, "Second flow, w symbolic: Phi1, Phi2, Phi3 are HK-bases with 1-dim null-spaces, "
       "alpha, beta, gamma integrals; dim K_Phi = 4 (the conjecture for the second flow)",
       "sec. 6, conjecture after eq. \"dC2 map\" for the second flow; analog of Th. \"dC bases 345\"",
       "For the second flow with w and eps symbolic: the rows i = 0, 1 of eqs. \"Psi1 iterates\" ... \"Psi3 iterates\" "
       "and the claimed relations (coefficients even in eps, polynomials in the integral L) have a unique solution "
       "a1..a6, b1..b6, c1..c6 (coefficient of m_k p_k normalized to -1), even in eps, hence integrals "
       "(Prop. \"prop: even\"); K_Phi_k = [block k : -1], dim 1; with e (flow-second-theorem) the four vectors span "
       "K_Phi, dim 4; L, a1, b1, c1 are functionally independent.",
       claimed=dict(SECOND_PHI_RELATIONS), slow=True, uses=["flow-second-theorem", "flow-second-theta"])
def prove_second_bases(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(FLOW2)
    r = f.ring
    second = require_proven(cert, "flow-second-theorem")
    big_l = Frac.parse(r, second.formulas["L"])
    phis = bases(f)
    with cert.step("the relations: coefficients even in eps, polynomials in L", "exact parity over Q(eps, w)[L] "
                   "(after a screen: each relation at two rational points, for a fast refutation)",
                   r.extend(["L"])) as s:
        screen_at_samples(s, f, claimed, big_l)
        lifted = lifted_relations(claimed, r)
        s.require(all(c.is_even_in(EPS) for rel in lifted for c in rel.coefficients),
                  "a coefficient is not even in eps")
        s.note("their coefficients are in Q(eps^2, w)[L], L an even integral (flow-second-theorem)")
    with cert.step("candidate: alpha from the relations, the rows i = 0 and a1 + b1 + c1 = g1; beta, gamma by the "
                   "cyclic symmetry", "hk.completion: Cramer over Q(eps, w)[L], L and g1 (flow-second-theta) "
                   "substituted last over factored denominators; index shift 1 -> 2 -> 3", r) as s:
        g1 = recall(require_proven(cert, "flow-second-theta"), "g1", r)
        alpha = complete_coordinates(f, phis, lifted, {"L": big_l}, ((0, 6, 12), g1), range(6), INDEX_SHIFT)
        beta = INDEX_SHIFT.image(alpha, PERM)
        sol = [*alpha, *beta, *INDEX_SHIFT.image(beta, PERM)]
        s.note(f"numerators up to {max(len(h.num) for h in sol)} terms, denominators {max(len(h.den) for h in sol)}; "
               "only a candidate (g1 is not cited as a fact): the next steps prove it")
    relations = [_combined(parse_relation(r, claimed[key], [*UNKNOWNS, *L_NAMES]), big_l)
                 for key in SECOND_PHI_RELATIONS]
    system = BlockSystem(f, tuple(tuple(b) for b in phis), tuple(relations), (0, 1))
    point = {k: v for k, v in RANK_POINT.items() if k in r.names}
    sol = verify_candidate(cert, system, UNKNOWNS, sol, point, INDEX_SHIFT)
    for name, h in zip(UNKNOWNS, sol, strict=True):
        record(cert, name, h)
    e = [Frac.parse(r, second.formulas[f"e{k}"]) for k in range(1, 7)]
    vectors = embedded_vectors(e, [sol[:6], sol[6:12], sol[12:]])
    max_basis_facts(cert, f, vectors, [big_l, sol[0], sol[6], sol[12]], "L, a1, b1, c1")


def embedded_vectors(phi0: Sequence[Frac], blocks: Sequence[Sequence[Frac]]) -> list[list[Frac]]:
    """The null-vectors of Phi0 (e, -1) and of Phi1..Phi3 (block k, -1) placed in R^10 (the monomials of
    PHI_MAX_TEXT)."""
    r = phi0[0].ring
    zero, minus = Frac(r, 0), Frac(r, -1)
    vectors = [list(phi0) + [zero] * 3 + [minus]]
    for b, block in enumerate(blocks):
        vec = list(block) + [zero] * 4
        vec[6 + b] = minus
        vectors.append(vec)
    return vectors


def max_basis_facts(cert: Certificate, f: KahanMap, vectors: Sequence[Sequence[Frac]], integrals: Sequence[Frac],
                    names: str, case: str = "", dim: str = "4", sigma: Substitution | None = None) -> None:
    """For null-vectors of Phi0..Phi3 with integral components (placed in R^10): dim K_Phi_k = 1, dim K_Phi = `dim`
    = 4, the span of the four; the four `integrals` functionally independent (exact ranks at a rational point).
    With `sigma` (fixing x), the vectors and integrals are functions on its source that stand for their images on
    f: each is evaluated at the pulled-back point, sigma(h)(P) = h(sigma*(P)), never carried over itself."""
    r = f.ring
    point = {k: v for k, v in RANK_POINT.items() if k in r.names}
    at = sigma.pullback(point) if sigma is not None else point
    monomials = [Frac.parse(r, m) for m in PHI_MAX_TEXT.split(", ")]
    with cert.step(f"{case}K_Phi_k = [block k : -1] (dim 1) and K_Phi = span of the four vectors (dim 4)",
                   "exact kernels of X_[0,5] and X_[0,6] at a rational point; rank of the four vectors", r) as s:
        matrix = orbit_matrix(f, monomials, point, 7)
        values = [[matrix[i, j] for j in range(matrix.ncols())] for i in range(matrix.nrows())]
        found = 10 - flint.fmpq_mat(values[:6]).rank()
        s.require(str(found) == dim.strip() == "4", f"dim ker X_[0,5] = {found} for the ten monomials, claimed {dim}")
        for name, slots in SUB_BASES.items():
            got = flint.fmpq_mat([[row[k] for k in slots] for row in values]).rank()
            s.require(got == 6, f"rank X_[0,6] = {got} for {name}, not 6")
        vals = [[h.evaluate(at) for h in vec] for vec in vectors]
        s.require(flint.fmpq_mat(vals).rank() == 4, "the four kernel vectors are dependent at the point")
        s.require(all(sum((a * b for a, b in zip(vec, row, strict=True)), flint.fmpq(0)) == 0
                      for vec in vals for row in values),
                  "a vector misses a row i = 0 ... 6 at the point")
        s.note("the four vectors have integral components and satisfy the rows i = 0 (cited and previous steps), "
               "hence every row: they lie in K_Phi; independent at one point; a non-zero maximal minor of X_[0,5] "
               "at one point bounds dim K_Phi by 4 and dim K_Phi_k by 1 off a proper algebraic subset")
    with cert.step(f"{case}{names} functionally independent", "exact Jacobian rank at a rational point", r) as s:
        params = {k: v for k, v in at.items() if k not in f.variables}
        ring_x = (sigma.source if sigma is not None else r).drop(params)
        funcs = [h.specialize(params, ring_x) for h in integrals]
        rank = jacobian_rank_at(funcs, f.variables, {k: point[k] for k in f.variables})
        s.require(rank == 4, f"Jacobian rank {rank}, not 4")
