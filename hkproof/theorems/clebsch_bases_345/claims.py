"""Section 6.7: Th. "dC bases 345" (bases Phi1, Phi2, Phi3): relations rel18, M2 with A, B, C, D, Step 1."""
from __future__ import annotations

from typing import Mapping

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import rank_over_fraction_field, solve_by_inverse
from hkproof.algebra.ring import Ring
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import EPS
from hkproof.errors import ParseError
from hkproof.experiments.relations import find_relations
from hkproof.hk.block_system import BlockSystem, determined_components
from hkproof.hk.expansion import homogeneous_eps_pieces
from hkproof.hk.independence import jacobian_rank_at, sample_point
from hkproof.hk.linear_relations import relation_rank, same_relation
from hkproof.hk.reduced import Relation, linear_combination_equals
from hkproof.hk.transport import Substitution
from hkproof.orchestration.registry import claim, require_proven
from hkproof.proof.certificate import Certificate, Refuted
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import SYSTEM, X, named, recall, record
from hkproof.theorems.clebsch_bases_345.data import (ABCD_DEPENDENCE, ADD, ADD_ABCD, A_2, BLOCK, COMMON, D_4, GROUP, M2,
                                                     REL18, REL18_EXTRA, UNKNOWNS, bases, relation_rows)

__all__ = ["J456", "m2_entries", "prove_abcd", "prove_dependence", "prove_independence", "prove_relations",
           "prove_relations_found", "prove_step1", "proven_coordinates", "STEP1_RELATIONS", "step1_relations"]

# -- rel18: the nine relations, found again by recipe (E) ---------------------------------------------------------
@claim("dc345-relations", GROUP,
       "Eqs. \"rel18_1\" ... \"rel18_8\": nine independent linear relations among alpha_j, beta_j, gamma_j",
       "sec. 6.7, eqs. \"rel18_1\" ... \"rel18_8\" and the two dependent relations after them",
       "The printed relations rel18_1 ... rel18_8 are nine independent relations, the two further printed "
       "relations follow from them, and all hold for the kernel coordinates alpha_j, beta_j, gamma_j proven in "
       "dc345-alpha and dc345-step5 (so they are no longer hypothetical, as they were in the paper).",
       claimed={**REL18, "rel18_extra": REL18_EXTRA}, uses=["dc345-alpha", "dc345-step5"])
def prove_relations(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    with cert.step("the printed relations: nine independent, the extra two dependent",
                   "rank over Q(eps, w) of the augmented rows", r) as s:
        printed = [rel for k in REL18 for rel in relation_rows(f, claimed[k])]
        extra = relation_rows(f, claimed["rel18_extra"])
        s.require(len(printed) == 9 and relation_rank(printed) == 9,
                  "rel18_1 ... rel18_8 are not nine independent relations")
        s.require(relation_rank(printed + extra) == 9,
                  "the two further relations do not follow from rel18_1 ... rel18_8")
    values = proven_coordinates(cert, r)
    with cert.step("the relations hold for the proven kernel coordinates", "exact identities in Q(m, p, eps, w)",
                   r) as s:
        for k, rel in enumerate(printed + extra):
            s.require(linear_combination_equals(rel.coefficients, values, rel.rhs), f"relation row {k + 1} fails")


def proven_coordinates(cert: Certificate, r: Ring) -> list[Frac]:
    """alpha_j, beta_j, gamma_j (j = 1 ... 6) as proven in dc345-alpha and dc345-step5, in the order of UNKNOWNS."""
    al, b5 = require_proven(cert, "dc345-alpha"), require_proven(cert, "dc345-step5")
    return [recall(al if u[0] == "a" else b5, u, r) for u in UNKNOWNS]


@claim("dc345-relations-found", GROUP, "Eqs. \"rel18_1\" ... \"rel18_8\" found again by recipe (E)",
       "sec. 6.7, eqs. \"rel18_1\" ... \"rel18_8\" (found by PSLQ in the paper)",
       "Exact relation finding (recipe E, eps and w symbolic in the reconstruction) finds a nine-dimensional space of "
       "linear relations among the kernel coordinates of Phi1, Phi2, Phi3 that contains the printed ones.",
       claimed=dict(REL18), slow=True, expected=Status.EVIDENCE_EXACT)
def prove_relations_found(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    with cert.step("recipe (E): the relation space of (Phi1, Phi2, Phi3) contains the printed relations",
                   "exact kernels at rational points, interpolation in eps and w, fresh checks", r) as s:
        printed = [rel for k in REL18 for rel in relation_rows(f, claimed[k])]
        search = find_relations(f, bases(f), names=list(UNKNOWNS))
        found = [Relation(rel.coefficients, rel.rhs) for rel in search.relations]
        s.require(search.dimension == 9 and len(found) == 9,
                  f"relation space of dimension {search.dimension}, {len(found)} relations reconstructed")
        s.require(relation_rank(found + printed) == 9,
                  "a printed relation is not in the space found by recipe (E)")
        s.evidence(Status.EVIDENCE_EXACT, points=search.samples)
        s.note(f"{search.samples} exact samples; every relation checked at fresh samples (discovery; the proof is "
               "dc345-relations)")
        for k, rel in enumerate(search.relations, start=1):
            cert.formula(f"found_{k}", rel.text())


# -- M2, A, B, C, D: eqs. "M2", "ABCD dependence", "dC Psi add lin rel 1-6", "dC A" ... "dC D" -------------------
def m2_entries(f, text: str, abcd: Mapping[str, Frac]) -> dict[str, Frac]:
    """The printed eq. "M2" ('a4 = D, a5 = A/(w1 - w3), ...') evaluated at given A, B, C, D."""
    out = {}
    for item in text.split(","):
        name, value = item.split("=")
        out[name.strip()] = named(f, value, dict(abcd))
    return out


def _in_abcd(f, text: str, m2: str, known: Mapping[str, Frac]) -> Relation:
    """A relation among a_j, b_j, c_j (j = 4, 5, 6) rewritten as a relation among A, B, C, D via eq. "M2"."""
    (rel,) = relation_rows(f, text, UNKNOWNS, known)
    r = f.ring
    columns = []
    zero = {k: Frac(r, 0) for k in "ABCD"}
    base = m2_entries(f, m2, zero)
    for k in "ABCD":
        unit = m2_entries(f, m2, {**zero, k: Frac(r, 1)})
        columns.append(sum((c * (unit.get(u, Frac(r, 0)) - base.get(u, Frac(r, 0)))
                            for c, u in zip(rel.coefficients, UNKNOWNS, strict=True)), Frac(r, 0)))
    skipped = [u for c, u in zip(rel.coefficients, UNKNOWNS, strict=True) if not c.is_zero() and u not in base]
    if skipped:
        raise ParseError(f"{text!r} involves {skipped}, which eq. \"M2\" does not give")
    return Relation(columns, rel.rhs)


@claim("dc345-abcd", GROUP,
       "Eq. \"M2\": alpha_j, beta_j, gamma_j (j = 4, 5, 6) through A, B, C, D; eqs. \"ABCD dependence\", "
       "\"dC Psi add lin rel 1\" ... \"6\", \"dC A\" ... \"dC D\"",
       "sec. 6.7, eqs. \"M2\", \"ABCD dependence\", \"dC Psi add lin rel 1\"-\"6\", \"dC A\"-\"dC D\"",
       "With M2 = [[D, A/(w1 - w3), A/(w1 - w2)], [B/(w2 - w3), D, B/(w2 - w1)], [C/(w3 - w2), C/(w3 - w1), D]], "
       "the relations 'dC Psi add lin rel 1-6' (with the integrals d7, d8, d9 of Th. \"dC basis 2\" and g4, g5, g6 "
       "of Th. \"dC Theta\") and eq. \"ABCD dependence\" determine A, B, C, D uniquely; they are integrals, even "
       "in eps, A = (1 + eps^2 A^(2) + ... + eps^8 A^(8))/(2 eps^2 Delta) and likewise B, C with "
       "A^(2) = B^(2) = C^(2) as printed, D = (H3 + eps^2 D^(4) + eps^4 D^(6) + eps^6 D^(8))/(2 Delta) with "
       "D^(4) as printed; (d7, d8, d9) M2 = 0, det M2 = 0, and rel18_1 ... rel18_4 hold for M2.",
       claimed={"M2": M2, **ADD, **ADD_ABCD, "abcd_dependence": ABCD_DEPENDENCE, "A_2": A_2, "D_4": D_4,
                "A_leading": "1", "D_leading": "p1**2 + p2**2 + p3**2"}, uses=["dc-basis2", "dc-theta"])
def prove_abcd(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    b2, th = require_proven(cert, "dc-basis2"), require_proven(cert, "dc-theta")
    known = {k: recall(b2, k, r) for k in ("d7", "d8", "d9")} | {k: recall(th, k, r) for k in ("g4", "g5", "g6")}
    delta = recall(b2, "Delta", r)
    with cert.step("the relations 'dC Psi add lin rel 1-6': both printed forms agree through eq. \"M2\"",
                   "rows over Q(eps, w) in the unknowns A, B, C, D", r) as s:
        rows = []
        for k in range(1, 7):
            via_m2 = _in_abcd(f, claimed[f"add_{k}"], claimed["M2"], known)
            (direct,) = relation_rows(f, claimed[f"add_{k}_abcd"], tuple("ABCD"), known)
            s.require(same_relation(via_m2, direct), f"the two sides of 'dC Psi add lin rel {k}' differ")
            rows.append(direct)
        s.require(relation_rank(rows) == 3 and
                  rank_over_fraction_field([list(x.coefficients) for x in rows]) == 3,
                  "the six relations are not a consistent system of rank 3")
        one = [Frac(r, 1)] * 3 + [Frac(r, 0)]
        s.require(all(linear_combination_equals(x.coefficients, one, Frac(r, 0)) for x in rows),
                  "(1, 1, 1, 0) is not the direction the relations leave free")
        s.note("rank 3 and consistent (the integrals d_k, g_k satisfy the three compatibility identities); "
               "A + B + C is left free")
    with cert.step("A, B, C, D from eq. \"ABCD dependence\"", "the dependence is linear along (1, 1, 1, 0): "
                   "sum of 1/((w_i - w_j)(w_i - w_k)) = 0", r) as s:
        pick = rows[:1] + rows[3:5] + [Relation([Frac(r, 0)] * 2 + [Frac(r, 1), Frac(r, 0)], Frac(r, 0))]
        base = solve_by_inverse([list(x.coefficients) for x in pick], [x.rhs for x in pick])
        lhs, rhs = claimed["abcd_dependence"].split("=")
        r4 = r.extend(["A", "B", "C", "D"])
        q = Frac.parse(r4, f"({lhs}) - ({rhs})")
        rt = r4.extend(["t"])
        along = q.to_ring(rt).pullback([rt.gen(k) + rt.gen("t") for k in "ABC"] + [rt.gen("D")], rt.constant(1),
                                       ["A", "B", "C", "D"])
        s.require(along.derivative("t").derivative("t").is_zero(),
                  "eq. \"ABCD dependence\" is not linear along (1, 1, 1, 0)")
        at_base = Substitution(r4, r, dict(zip("ABCD", base, strict=True)))
        slope = at_base.apply(along.derivative("t").to_ring(r4))
        s.require(not slope.is_zero(), "eq. \"ABCD dependence\" does not fix A + B + C")
        t = -at_base.apply(q) / slope
        abcd = dict(zip("ABCD", [base[0] + t, base[1] + t, base[2] + t, base[3]], strict=True))
        s.require(all(linear_combination_equals(x.coefficients, list(abcd.values()), x.rhs) for x in rows),
                  "A, B, C, D do not satisfy the six relations")
        for name, v in abcd.items():
            record(cert, name, v)
    with cert.step("A, B, C, D are integrals, even in eps", "rational functions of the integrals d7, d8, g4, g5 "
                   "(dc-basis2, dc-theta); exact parity", r) as s:
        for name, v in abcd.items():
            s.require(v.is_even_in(EPS), f"{name} is not even in eps")
        s.note("A, B, C, D are built from d7, d8, g4, g5 by field operations with constant coefficients, so "
               "h o f = h for each of them")
    m2 = m2_entries(f, claimed["M2"], abcd)
    for name, v in m2.items():
        record(cert, name, v)
    with cert.step("eq. \"M2\": (d7, d8, d9) M2 = 0, det M2 = 0, rel18_1 ... rel18_4",
                   "exact identities in Q(m, p, eps, w)", r) as s:
        d = [known[k] for k in ("d7", "d8", "d9")]
        for col in "456":
            entries = [m2[f"{c}{col}"] for c in "abc"]
            s.require(linear_combination_equals(d, entries, Frac(r, 0)), f"(d7, d8, d9) M2 has column {col} != 0")
        values = [m2.get(u, Frac(r, 0)) for u in UNKNOWNS]
        for key in ("rel18_1", "rel18_2", "rel18_3", "rel18_4"):
            for rel in relation_rows(f, REL18[key]):
                s.require(linear_combination_equals(rel.coefficients, values, rel.rhs), f"{key} fails for M2")
        s.note("det M2 = 0 follows from the non-zero left null-vector (d7, d8, d9)")
    with cert.step("eqs. \"dC A\" ... \"dC D\": the eps-structure, A^(2) = B^(2) = C^(2), D^(4)",
                   "coefficients in eps of 2 eps^2 Delta A and 2 Delta D; homogeneity in (m, p)", r) as s:
        e2 = Frac(r, r.gen(EPS) ** 2)
        for name in "ABC":
            pieces = homogeneous_eps_pieces(abcd[name] * 2 * e2 * delta, EPS, X, 5, 0, f"2 eps^2 Delta {name}")
            s.require_equal(pieces[0], named(f, claimed["A_leading"]), f"{name}^(0)")
            s.require_equal(pieces[1], named(f, claimed["A_2"]), f"{name}^(2)")
        pieces = homogeneous_eps_pieces(abcd["D"] * 2 * delta, EPS, X, 4, 2, "2 Delta D")
        s.require_equal(pieces[0], named(f, claimed["D_leading"]), "D^(2)")
        s.require_equal(pieces[1], named(f, claimed["D_4"]), "D^(4)")
    with cert.step("eq. \"ABCD dependence\" for A, B, C, D, directly", "one homogenized compose of the quadric "
                   "over the common denominator of A, B, C, D (a check of the construction; last, being the costliest "
                   "when a claim is false)", r) as s:
        s.require(Substitution(r4, r, abcd).apply(q).is_zero(), "eq. \"ABCD dependence\" fails")


# -- Step 1: the 17 x 18 system ---------------------------------------------------------------------------------
STEP1_RELATIONS = ("rel18_1", "rel18_2", "rel18_3", "rel18_4", "rel18_6", "rel18_8")
J456 = [BLOCK[c][j] for c in "abc" for j in (3, 4, 5)]


def step1_relations(f, known: Mapping[str, Frac]) -> list[Relation]:
    """The relation rows of Step 1: rel18_1 ... rel18_8 and 'dC Psi add lin rel 1, 2'."""
    rels = [rel for k in STEP1_RELATIONS for rel in relation_rows(f, REL18[k])]
    return rels + [rel for k in ("add_1", "add_2") for rel in relation_rows(f, ADD[k], UNKNOWNS, known)]


@claim("dc345-step1", GROUP,
       "Proof of Th. \"dC bases 345\", Step 1: the 17 x 18 system fixes alpha_j, beta_j, gamma_j (j = 4, 5, 6)",
       "sec. 6.7, proof of Th. \"dC bases 345\", Step 1",
       "The 17 equations (eqs. \"Psi1 iterates\" ... \"Psi3 iterates\" with i = 0, 1, rel18_1 ... rel18_8, "
       "'dC Psi add lin rel 1, 2') in 18 unknowns have rank 17 and a kernel vector with zero j = 4, 5, 6 "
       "components, so those components are unique; they equal eq. \"M2\" with A, B, C, D of dc345-abcd.",
       claimed={"kernel_vector": "[(w2 - w3)*n, (w3 - w1)*n, (w1 - w2)*n]"},
       uses=["dc-basis2", "dc345-abcd", "dc345-alpha", "dc345-step5"])
def prove_step1(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    b2 = require_proven(cert, "dc-basis2")
    known = {k: recall(b2, k, r) for k in ("d7", "d8")}
    rels = step1_relations(f, known)
    p2 = [Frac.parse(r, t) for t in COMMON[:3]]
    p2f = [f.pullback(h) for h in p2]
    n = [p2[1] * p2f[2] - p2[2] * p2f[1], p2[2] * p2f[0] - p2[0] * p2f[2], p2[0] * p2f[1] - p2[1] * p2f[0]]
    weights = [named(f, w) for w in _kernel_weights(claimed["kernel_vector"])]
    shape = [*n, *[Frac(r, 0)] * 3]
    system = BlockSystem(f, tuple(tuple(b) for b in bases(f)), tuple(rels), (0, 1))
    determined = determined_components(cert, system, [shape] * 3, sample_point(r.names, seed=3), weights)
    if determined != J456:
        raise Refuted(f"the kernel direction vanishes at {[UNKNOWNS[k] for k in determined]}, not at the j = 4, 5, 6 "
                      "components")
    abcd = require_proven(cert, "dc345-abcd")
    values = proven_coordinates(cert, r)
    with cert.step("the proven kernel coordinates solve the system; their j = 4, 5, 6 components are eq. \"M2\"",
                   "substitution into the 17 equations (rows i = 0, 1 proven in dc345-alpha, dc345-step5)", r) as s:
        for k, rel in enumerate(rels):
            s.require(linear_combination_equals(rel.coefficients, values, rel.rhs), f"relation row {k + 1} fails")
        s.require(all(values[k] == recall(abcd, UNKNOWNS[k], r) for k in J456),
                  "a j = 4, 5, 6 component differs from eq. \"M2\"")
        s.note("rank 17 and a kernel vanishing in the j = 4, 5, 6 positions: every solution has these components")


def _kernel_weights(text: str) -> list[str]:
    """'[(w2 - w3)*n, ...]' -> the three weights of n."""
    items = text.strip().strip("[]").split(",")
    out = []
    for item in items:
        item = item.strip()
        if not item.endswith("*n"):
            raise ParseError(f"{item!r} is not of the form weight*n")
        out.append(item[:-2])
    return out


# -- Conclusions: functional independence --------------------------------------------------------------------------
@claim("dc345-independence", GROUP,
       "Th. \"dC bases 345\": J, alpha1, beta1, gamma1 functionally independent; A, B, C independent",
       "sec. 6.7, last sentence of Th. \"dC bases 345\"; remark after eq. \"ABCD dependence\"",
       "The Jacobian of (J, alpha1, beta1, gamma1) with respect to (m, p) has rank 4 at a rational point (alpha1, "
       "beta1, gamma1 the integrals of dc345-alpha and dc345-step5), and that of (A, B, C) has rank 3.",
       uses=["dc-basis1-relations", "dc345-abcd", "dc345-alpha", "dc345-step5"])
def prove_independence(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    abcd = require_proven(cert, "dc345-abcd")
    J = recall(require_proven(cert, "dc-basis1-relations"), "J", r)
    values = dict(zip(UNKNOWNS, proven_coordinates(cert, r), strict=True))
    point = sample_point(r.names, seed=3)
    with cert.step("J, alpha1, beta1, gamma1: Jacobian rank 4 at a rational point",
                   "exact derivatives of the proven integrals; exact rank", r) as s:
        s.require(jacobian_rank_at([J, values["a1"], values["b1"], values["c1"]], X, point) == 4,
                  "rank < 4 at the sample point")
        s.note("a non-zero 4 x 4 minor at one point: the four integrals are functionally independent")
    abc = [recall(abcd, k, r) for k in "ABC"]
    with cert.step("A, B, C: Jacobian rank 3", "exact rank at a rational point", r) as s:
        s.require(jacobian_rank_at(abc, X, point) == 3, "rank < 3 at the sample point")


@claim("dc345-dependence", GROUP,
       "Remark after eq. \"ABCD dependence\": J, d7, d8, d9, g1, g2, g3, D and F are functions of A, B, C",
       "sec. 6.7, remark after eqs. \"dC A\" ... \"dC D\"; Step 3 (F depends on J, d7, d8)",
       "J and g1, g2, g3 are rational functions of A, B, C, D (relations found by hkproof, dc-theta-dependence); "
       "d7, d8, d9 are linear in A, B, C, D (dc345-abcd), F is rational in them (dc345-alpha), and D lies on the "
       "quadric eq. \"ABCD dependence\" over Q(w)(A, B, C). So all of them depend functionally on A, B, C "
       "(locally, off D = 0), and, J, d7, d8 being independent (dc-basis2-independence), on J, d7, d8 -- with w "
       "symbolic, where the paper checked F for numeric w only.",
       uses=["dc-basis2-independence", "dc-theta-dependence", "dc345-alpha"])
def prove_dependence(cert: Certificate, claimed: Mapping[str, str]) -> None:
    r = kahan_map(SYSTEM).ring
    require_proven(cert, "dc-theta-dependence")
    require_proven(cert, "dc345-alpha")
    require_proven(cert, "dc-basis2-independence")
    with cert.step("functional dependence", "chain rule", r) as s:
        s.note("d7, d8, d9 = 2 D - 2 (B - C)/(w2 - w3), ... (dc345-abcd); D^2 is a quadratic form in A, B, C with "
               "coefficients in Q(w) (dc345-abcd): off D = 0, D and hence J, d_k, g_k, F are smooth functions of "
               "A, B, C. (J, d7, d8) = phi(A, B, C) with d phi invertible off a proper subset (rank 3 of "
               "d(J, d7, d8)/dx, dc-basis2-independence), so A, B, C, and with them every integral above, are "
               "locally functions of J, d7, d8")
