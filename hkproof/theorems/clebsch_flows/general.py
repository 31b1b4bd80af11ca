"""Section 6, end: the general flow of the Clebsch system, the second-flow theorem and the Phi0 claim for all flows."""
from __future__ import annotations

import itertools
import random
from typing import Mapping, Sequence

import flint

from hkproof.algebra.sampling import random_point
from hkproof.algebra.formula import indexed, rename
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import cramer, nullspace_q, rank_over_fraction_field
from hkproof.algebra.ring import Rational, Ring
from hkproof.dynamics.catalogue import get_system, kahan_map
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import SingularPointError
from hkproof.experiments.relations import find_relations
from hkproof.hk.balance import orbit_matrix
from hkproof.hk.independence import jacobian_rank_at
from hkproof.hk.integrals import check_integral, lie_derivative
from hkproof.hk.linear_relations import parse_relation, relation_rank
from hkproof.hk.matrix_form import require_matrix_form
from hkproof.hk.recipe_g import WHAT_IT_PROVES, recipe_g
from hkproof.hk.reduced import (
    Relation,
    block_rows_at,
    det_at_point,
    kernel_coordinates,
    linear_combination_equals,
    system_at,
)
from hkproof.hk.equivariant_solution import prove_by_symmetry
from hkproof.hk.translation import ParameterTranslation
from hkproof.hk.transport import Substitution, map_mismatches, require_transport
from hkproof.orchestration.registry import claim, require_proven
from hkproof.proof.certificate import Certificate, StepRecorder
from hkproof.proof.export import substitution_step
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import CYCLIC_SHIFT, H, named, recall, record
from hkproof.theorems._common import parse_matrix
from hkproof.theorems.clebsch_flows.data import (
    B_OF_YZ,
    C_OF_YZ,
    CYCLIC,
    GENERAL,
    PHI0,
    REDUCTION,
    REDUCTION_Z0,
    e_names,
    field_under,
    substitution,
    yz_map,
    yz_map_at_z0,
)
from hkproof.theorems.clebsch_bases_345.data import REL18, relation_rows
from hkproof.theorems.clebsch_bases_345.data import UNKNOWNS as ABC_NAMES
from hkproof.theorems.clebsch_bases_345.data import bases as phi_bases

__all__ = ["C_THRU_B", "DC2", "DIFFERENCES", "E_PAPER", "FIRST", "FLOW2", "GENERAL_CLAIM", "GENERAL_NAMES", "GROUP",
           "L_SAMPLE", "M_PAPER", "PHI_MAX_TEXT", "prove_general_map", "prove_general_phi0", "prove_reduction",
           "prove_second_flow", "prove_second_flow_recipe_g", "prove_second_relations_found", "prove_second_theta",
           "prove_theta_all_flows", "RANK_POINT", "REDUCTION_CLAIM", "reduction_substitutions", "SECOND",
           "SECOND_REL18", "SECOND_REL18_RANKS", "SUB_BASES", "THETA_NAMES", "THETA_RELATION", "TILDE", "YZ_SHIFT"]

GROUP = "clebsch-flows"
FLOW2 = "clebsch-flow2"
E_PAPER = {"E1": "w3*w1 + w1*w2 - w2*w3", "E2": "w1*w2 + w2*w3 - w3*w1", "E3": "w2*w3 + w3*w1 - w1*w2"}
C_THRU_B = {"c1": "(b2 - b3)/(w2 - w3)", "c2": "(b3 - b1)/(w3 - w1)", "c3": "(b1 - b2)/(w1 - w2)"}
TILDE = {f"{v}": f"{v}_t" for v in ("m1", "m2", "m3", "p1", "p2", "p3")}
RANK_POINT: dict[str, Rational] = {"m1": 3, "m2": -2, "m3": 5, "p1": 1, "p2": 4, "p3": -3, "eps": flint.fmpq(1, 7), "w1": 2, "w2": -3,
              "w3": 5, "y": 3, "z": -2}


def _dc2(i: int, j: int, k: int) -> str:
    """Component i of eq. "dC2" as 'm~_i - m_i - rhs' and 'p~_i - p_i - rhs' (paper's form, c_k as names)."""
    a, b, c = i + 1, j + 1, k + 1
    m = (f"m{a}_t - m{a} - eps*(c{c} - c{b})*(m{b}_t*m{c} + m{b}*m{c}_t) "
         f"- eps*(b{c} - b{b})*(p{b}_t*p{c} + p{b}*p{c}_t)")
    p = f"p{a}_t - p{a} - eps*c{c}*(m{c}_t*p{b} + m{c}*p{b}_t) + eps*c{b}*(m{b}_t*p{c} + m{b}*p{c}_t)"
    return f"{m} ; {p}"


DC2 = " ; ".join(_dc2(*ijk) for ijk in CYCLIC)
M_PAPER = ("[[1, eps*c23*m3, eps*c23*m2, 0, eps*b23*p3, eps*b23*p2],"
           " [eps*c31*m3, 1, eps*c31*m1, eps*b31*p3, 0, eps*b31*p1],"
           " [eps*c12*m2, eps*c12*m1, 1, eps*b12*p2, eps*b12*p1, 0],"
           " [0, eps*c2*p3, -eps*c3*p2, 1, -eps*c3*m3, eps*c2*m2],"
           " [-eps*c1*p3, 0, eps*c3*p1, eps*c3*m3, 1, -eps*c1*m1],"
           " [eps*c1*p2, -eps*c2*p1, 0, -eps*c2*m2, eps*c1*m1, 1]]")


DIFFERENCES = {f"{x}{i}{j}": f"({x}{i} - {x}{j})" for x in "cb" for i in "123" for j in "123"}   # c_ij, b_ij


def _with_c(text: str) -> str:
    """Replace c_ij, b_ij and c_k by their expressions through b and w (eq. "c thru b")."""
    return rename(rename(text, DIFFERENCES), {k: f"({v})" for k, v in C_THRU_B.items()})


@claim("flow-general-map", GROUP, "The general Clebsch flow: Kahan map, eq. \"dC2\", matrix M, flows 1 and 2",
       "sec. 6, eqs. \"gcl\", \"c thru b\", \"dC2\", \"dC2 map\", \"Clebsch 2 b\", \"Clebsch 2 c\"",
       "The catalogue's general-flow Kahan map (b, w symbolic, c_k from eq. \"c thru b\") has the component equations "
       "\"dC2\" and the printed matrix M with M (m~, p~) = (m, p); b = w gives c = 1 and the first flow, b = "
       "(-w2 w3, -w3 w1, -w1 w2) gives c = w and the second flow (explicit maps equal exactly); with b_k = s + y w_k "
       "- z w_i w_j the map is the polynomial family c_k = y + z w_k and does not depend on s.",
       claimed={"dC2": DC2, "M": M_PAPER, "flow1_b": "[w1, w2, w3]", "flow1_c": "[1, 1, 1]",
                "flow2_b": "[-w2*w3, -w3*w1, -w1*w2]", "flow2_c": "[w1, w2, w3]"})
def prove_general_map(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GENERAL)
    r, t = f.ring, f.field.tilde_ring
    with cert.step("component equations \"dC2\"", "E_i / (coefficient of x~_i), exact comparison", t) as s:
        parts = [p.strip() for p in claimed["dC2"].split(";")]
        s.require(len(parts) == 6, f"eq. \"dC2\" needs six components, got {len(parts)}")
        order = [0, 3, 1, 4, 2, 5]      # dC2 text lists (m1, p1, m2, p2, m3, p3); equations are (m1, m2, m3, p1, ...)
        for k, text in zip(order, parts, strict=True):
            e = f.equations[k]
            lead = e.derivative(t.index(f.field.tilde_variables[k]))
            s.require_equal(Frac(t, e, lead), Frac.parse(t, _with_c(text)), f"component {f.variables[k]}")
    with cert.step("matrix form M (m~, p~) = (m, p)", "rows of M and b scaled by the diagonal, exact", r) as s:
        require_matrix_form(s, f, parse_matrix(f, _with_c(claimed["M"])), normalize_rows=True)
    for flow, name in (("flow1", "clebsch"), ("flow2", FLOW2)):
        target = kahan_map(name)
        with cert.step(f"{name} is the general map at b = {claimed[flow + '_b']}",
                       "eq. \"c thru b\" at b; the vector field at b compared exactly, lowest terms: equal fields "
                       "give equal Kahan equations and (Delta of the target non-zero) equal explicit maps",
                       target.ring) as s:
            bs = parse_matrix(target, f"[{claimed[flow + '_b']}]")[0]
            cs = parse_matrix(target, f"[{claimed[flow + '_c']}]")[0]
            s.require(len(bs) == 3 and len(cs) == 3, f"b and c of {flow} need three entries each, got "
                      f"{len(bs)} and {len(cs)}")
            for k, c_k in enumerate(_c_through_b(target.ring, {f"b{j + 1}": bs[j] for j in range(3)})):
                s.require_equal(c_k, cs[k], f"c{k + 1} at the {flow} values of b")
            images = {f"b{k + 1}": str(bs[k]) for k in range(3)}
            for got, want, v in zip(field_under(f, images, target.ring), target.field.rhs, f.variables, strict=True):
                s.require_equal(got, want.to_ring(target.ring), f"d{v}/dt of the general field at the {flow} b")
            s.require(not target.explicit[1].is_zero(), f"the Kahan map of {name} has Delta = 0")
    g = yz_map()
    with cert.step("b = s + y w + z (-w_j w_k): the polynomial family c_k = y + z w_k, independent of s",
                   "eq. \"c thru b\" at b; the vector field at b compared exactly (equal fields, equal Kahan "
                   "maps); Vandermonde det of (1, w_k, -w_i w_j) non-zero",
                   g.ring.extend(["s"])) as s:
        ts = g.ring.extend(["s"])
        for k, c_k in enumerate(_c_through_b(ts, {b: Frac.parse(ts, text) for b, text in B_OF_YZ.items()})):
            s.require_equal(c_k, Frac.parse(ts, C_OF_YZ[k]), f"c{k + 1} under b = s + y w - z w_i w_j")
        for got, want, v in zip(field_under(f, B_OF_YZ, ts), g.field.rhs, f.variables, strict=True):
            s.require_equal(got, want.to_ring(ts), f"d{v}/dt under b = s + y w - z w_i w_j")
        s.require(not g.explicit[1].is_zero(), "the Kahan map of the (y, z) family has Delta = 0")
        vdm = Frac.parse(g.ring, "(w1 - w2)*(w2 - w3)*(w3 - w1)")
        rows = [[Frac(g.ring, 1), Frac.parse(g.ring, f"w{i + 1}"), Frac.parse(g.ring, f"-w{j + 1}*w{k + 1}")]
                for i, j, k in CYCLIC]
        s.require(rank_over_fraction_field(rows) == 3 and not vdm.is_zero(), "(s, y, z) -> b is not invertible")
        s.note("(s, y, z) -> b is a linear bijection over Q(w) (w distinct), so identities proven with y, z, w "
               "symbolic hold with b symbolic; s (a multiple of the Casimir H3 in H) does not enter the map")


def _c_through_b(ring: Ring, b: Mapping[str, Frac]) -> list[Frac]:
    """c_1, c_2, c_3 by eq. "c thru b" at the given b_1, b_2, b_3."""
    return [Frac.parse(ring, C_THRU_B[f"c{k + 1}"], dict(b)) for k in range(3)]


# ---------------------------------------------------------------- the flow reduction -----------------------------
FIRST = "clebsch"
REDUCTION_CLAIM = {**{f"{k}_prime": v for k, v in REDUCTION.items()},
                   **{f"{k}_prime_z0": v for k, v in REDUCTION_Z0.items()}}


def reduction_substitutions(claimed: Mapping[str, str]) -> tuple[Substitution, Substitution]:
    """(sigma, sigma0): the second flow's map -> the (y, z) family (z != 0) and the first flow's map -> its
    hyperplane z = 0, read from the claimed images."""
    images = {k: claimed[f"{k}_prime"] for k in REDUCTION}
    images0 = {k: claimed[f"{k}_prime_z0"] for k in REDUCTION_Z0}
    return (substitution(kahan_map(FLOW2), yz_map(), images),
            substitution(kahan_map(FIRST), yz_map_at_z0(), images0))


def _field_identity(s: StepRecorder, sigma: Substitution, source: KahanMap, target: KahanMap, factor: str) -> None:
    """target's field = factor * sigma(source's field), component by component (eps does not occur in a field)."""
    lam = Frac.parse(target.ring, factor)
    for v, a, b in zip(source.variables, source.field.rhs, target.field.rhs, strict=True):
        s.require_equal(b, lam * sigma.apply(a), f"{v}' of the field")


@claim("flow-reduction", GROUP, "Every flow's Kahan map is the second flow's (z != 0) or the first flow's (z = 0)",
       "sec. 6, eqs. \"gcl\", \"dC2\", \"dC2 map\", \"Clebsch 2 b\"; the conjecture after eq. \"dC2 map\"",
       "With b_k = s + y w_k - z w_i w_j (c_k = y + z w_k; every flow): for z != 0 the Kahan map of the (y, z) flow "
       "with step eps equals the Kahan map of the second flow with w' = w + (y/z)(1, 1, 1) and eps' = z eps, as an "
       "identity in Q(x, eps, w, y, z) (denominators powers of z); for z = 0 it is the first flow's map with "
       "eps' = y eps (for y = z = 0 the field is 0 and the map the identity). Both substitutions are injective "
       "homomorphisms of fields, so every rational identity about the second (first) flow's map carries over.",
       claimed=REDUCTION_CLAIM)
def prove_reduction(cert: Certificate, claimed: Mapping[str, str]) -> None:
    sigma, sigma0 = reduction_substitutions(claimed)
    for k in REDUCTION_CLAIM:
        cert.formula(k, claimed[k])
    flow2, first, g, g0 = kahan_map(FLOW2), kahan_map(FIRST), yz_map(), yz_map_at_z0()
    with cert.step("the fields: F_(y,z)(x; w) = z F_2(x; w'), F_(y,0)(x; w) = y F_1(x; w)",
                   f"exact, componentwise; sigma: {sigma}", g.ring) as s:
        _field_identity(s, sigma, flow2, g, "z")
        _field_identity(s, sigma0, first, g0, "y")
        s.note("Kahan's scheme of lambda F with step eps is that of F with step lambda eps (the equations are linear "
               "in eps F): the next steps check this for the maps themselves")
    with cert.step("z != 0: the second flow's map at (w', eps') is the (y, z) map", "Kahan matrices M, b (rows "
                   "divided by their diagonal) and explicit components N_j / Delta, exact in Q(x, eps, w, y, z)",
                   g.ring) as s:
        bad = map_mismatches(sigma, flow2, g)
        s.require(not bad, f"sigma(second flow) != (y, z) flow at {bad}")
    with cert.step("z = 0: the first flow's map at eps' is the (y, 0) map", "Kahan matrices and explicit "
                   "components, exact in Q(x, eps, w, y); the (y, z) components restrict to z = 0", g0.ring) as s:
        bad = map_mismatches(sigma0, first, g0)
        s.require(not bad, f"sigma0(first flow) != (y, 0) flow at {bad}")
        for v, a, b in zip(g.variables, g.components(), g0.components(), strict=True):
            s.require_equal(a.specialize({"z": 0}, g0.ring), b, f"{v}~ of the (y, z) map at z = 0")
        s.note("the lowest-terms components of the (y, z) map have denominators not divisible by z: the family's "
               "map at z = 0 is the map of the field at z = 0")
    with cert.step("both substitutions are injective", "Jacobian of the images at a rational point (full rank: "
                   "the images are algebraically independent)", g.ring) as s:
        point = {k: v for k, v in RANK_POINT.items() if k in g.ring.names}
        s.require(sigma.is_injective_at(("eps", "w1", "w2", "w3"), point), "sigma is not injective")
        s.require(sigma0.is_injective_at(("eps",), point), "sigma0 is not injective")
        s.note("so sigma (sigma0) embeds Q(x, eps', w') into Q(x, eps, w, y, z)[1/z] (Q(x, eps, w, y)[1/y]): a "
               "rational identity h o f_2 = h, a parity in eps' (eps' -> -eps' is eps -> -eps) or a non-zero "
               "determinant about the second (first) flow holds for the image under sigma (sigma0) and the (y, z) "
               "map; the exceptional parameters are z = 0 (then sigma0) and y = z = 0 (the zero field)")


# ---------------------------------------------------------------- the second flow --------------------------------
SECOND = {
    "rel1": "w1*e1 - w2*w3*e4 = 0",
    "rel2": "w2*e2 - w3*w1*e5 = 0",
    "rel3": "w3*e3 - w1*w2*e6 = 0",
    "rel4": "e1 - e2 - (w1 - w2)*e6 = eps**2*w3**2*(w1 - w2)",
    "rel5": "e3 - e1 - (w3 - w1)*e5 = eps**2*w2**2*(w3 - w1)",
    "rel6": "e2 - e3 - (w2 - w3)*e4 = eps**2*w1**2*(w2 - w3)",
    "L": "(E1*(w1*m1**2 + w2*w3*p1**2) + E2*(w2*m2**2 + w3*w1*p2**2) + E3*(w3*m3**2 + w1*w2*p3**2))"
         "/(1 + eps**2*w1*(w1*m1**2 + w2*w3*p1**2) + eps**2*w2*(w2*m2**2 + w3*w1*p2**2)"
         " + eps**2*w3*(w3*m3**2 + w1*w2*p3**2))",
    "e1": "w2*w3*(E1/L - eps**2*w1)", "e2": "w3*w1*(E2/L - eps**2*w2)", "e3": "w1*w2*(E3/L - eps**2*w3)",
    "e4": "w1*(E1/L - eps**2*w1)", "e5": "w2*(E2/L - eps**2*w2)", "e6": "w3*(E3/L - eps**2*w3)",
    "g1": "(E1 + eps**2*(w1 - w2)*E3*(w2*m2**2 + w3*w1*p2**2) + eps**2*(w1 - w3)*E2*(w3*m3**2 + w1*w2*p3**2))/L0",
    "g2": "(E2 + eps**2*(w2 - w3)*E1*(w3*m3**2 + w1*w2*p3**2) + eps**2*(w2 - w1)*E3*(w1*m1**2 + w2*w3*p1**2))/L0",
    "g3": "(E3 + eps**2*(w3 - w1)*E2*(w1*m1**2 + w2*w3*p1**2) + eps**2*(w3 - w2)*E1*(w2*m2**2 + w3*w1*p2**2))/L0",
    "L0": "E1*(w1*m1**2 + w2*w3*p1**2) + E2*(w2*m2**2 + w3*w1*p2**2) + E3*(w3*m3**2 + w1*w2*p3**2)",
    "identity": "w_j*E_i - w_i*E_j - (w_i - w_j)*E_k",
    "b_of_L0": "w_j*w_k*E_j", "c_of_L0": "w_i*E_i",
}




def _e_as_functions_of_l(cert: Certificate, s: StepRecorder, f: KahanMap, rels: Sequence, names: Sequence[str],
                         claimed: Mapping[str, str], known: Mapping[str, Frac]) -> list[Frac]:
    """e_1..e_6 by Cramer from sum e_k phi_k = 1 and relations 1-5, each checked against its claimed form in L."""
    e = _solve_phi0(f, rels[:5])
    for n, a in zip(names, e, strict=True):
        cert.formula(n, a)
        s.require_equal(a, named(f, claimed[n], known), f"{n} as a function of L")
    return e

def _solve_phi0(kmap: KahanMap, relations: Sequence[Relation]) -> list[Frac]:
    """e from the six equations without iterates: (sum e_k phi_k)(x) = 1 and five relations (Cramer)."""
    r = kmap.ring
    rows = [[Frac.parse(r, phi) for phi in PHI0]] + [list(rel.coefficients) for rel in relations]
    rhs = [Frac(r, 1)] + [rel.rhs for rel in relations]
    return cramer(rows, rhs)[0]


def _kernel_rank_bound(cert: Certificate, kmap: KahanMap, e: Sequence[Frac]) -> None:
    """dim K_Phi0(x) <= 1 for generic x and parameters: X_[0,6] has rank 6 at one rational point (exact Q)."""
    r = kmap.ring
    with cert.step("dim K_Phi0 = 1 (upper bound)", "exact rank of X_[0,6] (fmpq_mat) at one rational point, and the "
                   "kernel there equals (e, -1)", r) as s:
        point = {k: v for k, v in RANK_POINT.items() if k in r.names}
        mat = orbit_matrix(kmap, [Frac.parse(r, phi) for phi in PHI0] + [Frac(r, 1)], point, 7)
        rows = [[mat[i, j] for j in range(7)] for i in range(7)]
        s.require(mat.rank() == 6, f"rank X_[0,6] = {mat.rank()} at {point}, not 6")
        ev = [a.evaluate(point) for a in e] + [flint.fmpq(-1)]
        s.require(all(sum((row[k] * ev[k] for k in range(7)), flint.fmpq(0)) == 0 for row in rows),
                  "(e, -1) at the point is not in ker X_[0,6]")
        s.note("a 6x6 minor of X_[0,6] is a rational function of (x, eps, parameters) that is non-zero at this point, "
               "hence not identically zero: rank X_[0,6] = 6 and dim ker X_[0,6](x) = 1 for generic x and parameters; "
               "K_Phi0(x) lies in that kernel and contains (e(x), -1)")


def _kernel_lower_bound(cert: Certificate, kmap: KahanMap, e: Sequence[Frac], integral: str) -> None:
    """(e, -1) is in K_Phi0(x): the e_k are integrals and (sum e_k phi_k)(x) = 1, so the same holds along the orbit."""
    r = kmap.ring
    with cert.step("(e, -1) lies in K_Phi0(x)", f"e_k are functions of the integral {integral}; row i = 0 holds",
                   r) as s:
        total = sum((a * Frac.parse(r, phi) for a, phi in zip(e, PHI0, strict=True)), Frac(r, 0))
        s.require(total == 1, f"sum e_k phi_k = {total}, not 1")
        s.note(f"e o f = e (functions of {integral}), so (sum e_k phi_k) o f^i = 1 for every i: a non-zero kernel "
               "vector of X_(-inf, inf). The six equations involve no iterate, so this, and not Prop. \"prop: even\", "
               "is what makes the e_k integrals")


@claim("flow-second-theorem", GROUP, "Second flow: K_Phi0 = [e1 : ... : e6 : -1], e_k functions of the integral L",
       "sec. 6, theorem on the second flow, eqs. \"Clebsch2 first basis\", \"E\", \"dCS2 linrel 1\"-\"dCS2 linrel 5\"",
       "For the second flow, Phi0 = (p^2, m^2, 1) is an HK-basis with dim K = 1; the five relations hold, the sixth is "
       "their consequence; the six equations give the printed e_k = functions of L; L is an integral (substitution "
       "and recipe (G)); L(x, 0) is a combination of H1, H2, H3; w_j E_i - w_i E_j = (w_i - w_j) E_k; L(x, 0) = "
       "sum c_i m_i^2 + b_i p_i^2 with b, c satisfying eq. \"c thru b\".",
       claimed=SECOND)
def prove_second_flow(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(FLOW2)
    r = f.ring
    names = e_names()
    known = {k: Frac.parse(r, v) for k, v in E_PAPER.items()}
    big_l = named(f, claimed["L"], known)
    rels = [parse_relation(r, claimed[f"rel{k}"], names) for k in range(1, 7)]
    with cert.step("the sixth relation follows from the first five", "ranks of augmented rows over Q(eps, w)",
                   r) as s:
        s.require(relation_rank(rels[:5]) == 5, "relations 1-5 are not independent")
        s.require(relation_rank(rels) == 5, "relation 6 is not a consequence of relations 1-5")
    with cert.step("e from the six equations", "Cramer's rule: sum e_k phi_k = 1 and relations 1-5 (no iterates)",
                   r) as s:
        e = _e_as_functions_of_l(cert, s, f, rels, names, claimed, {**known, "L": big_l})
        l0 = named(f, claimed["L0"], known)
        for k, (i, j, kk) in enumerate(CYCLIC):
            g = e[3 + i] / Frac.parse(r, f"w{i + 1}")
            s.require_equal(g, named(f, claimed[f"g{k + 1}"], {**known, "L0": l0}), f"e{i + 4}/w{i + 1}, explicit")
        cert.formula("L", big_l)
    _continuous_limit(cert, f, claimed, known, big_l)
    with cert.step("L is an integral (substitution)", "L(N/Delta) - L = 0 in Q(x, eps, w)", r) as s:
        s.require(check_integral(f, big_l).status is Status.VERIFIED, "L o f != L")
        s.note("confirmed independently by recipe (G) in flow-second-recipe-g")
    cert.checks.append(substitution_step(f.field, "L", big_l))
    _kernel_lower_bound(cert, f, e, "L")
    _kernel_rank_bound(cert, f, e)


@claim("flow-second-recipe-g", GROUP, "Second flow: L is an integral by recipe (G), with a cofactor certificate",
       "sec. 6, theorem on the second flow; sec. 4, recipe (G)",
       "delta = L_num(x~) L_den(x) - L_num(x) L_den(x~) satisfies det M^2 delta = sum lambda_i E_i in "
       "Z[x, x~, eps, w] with explicit cofactors lambda = adj(M)^T q, so L o f = L where det M != 0.",
       claimed={"L": SECOND["L"]}, uses=["flow-second-theorem"])
def prove_second_flow_recipe_g(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(FLOW2)
    big_l = named(f, claimed["L"], {k: Frac.parse(f.ring, v) for k, v in E_PAPER.items()})
    theorem = require_proven(cert, "flow-second-theorem")
    with cert.step("L is the L of the second-flow theorem", "exact comparison", f.ring) as s:
        s.require_equal(big_l, Frac.parse(f.ring, theorem.formulas["L"]), "L")
    with cert.step("L is an integral (recipe (G))", "elimination of x~ with adj M; Delta^k delta = sum lambda_i E_i "
                   "checked by expansion", f.field.tilde_ring) as s:
        res = recipe_g(f, big_l)
        s.require(res.status is Status.VERIFIED, "delta(x, x~) for L is not in the Kahan ideal (times det M^k)")
        s.note(f"det M^{res.power} delta = sum lambda_i E_i, lambda = adj(M)^T q, with {res.certificate_terms} terms "
               f"in q and adj(M); {WHAT_IT_PROVES}")


def _continuous_limit(cert: Certificate, f: KahanMap, claimed: Mapping[str, str], known: dict[str, Frac],
                      big_l: Frac) -> None:
    """L(x, 0), the identity for E_k, and eq. "c thru b" for the b_i, c_i of L(x, 0) (with the index corrected)."""
    r = f.ring
    l0 = named(f, claimed["L0"], known)
    with cert.step("L(x, 0) is a combination of H1, H2, H3", "eps -> 0 in lowest terms; linear solve; Lie derivative",
                   r) as s:
        s.require_equal(big_l.specialize({"eps": 0}, r.drop(["eps"])).to_ring(r), l0, "L(x, 0)")
        hs = [Frac.parse(r, H[k]) for k in ("H1", "H2", "H3")]
        coeffs = parse_matrix(f, "[[-2*w1*w2*w3, w1*w2 + w2*w3 + w3*w1, 2*w1*w2*w3*(w1 + w2 + w3)]]")[0]
        combo = sum((a * h for a, h in zip(coeffs, hs, strict=True)), Frac(r, 0))
        s.require_equal(l0, combo, "L(x, 0) = -2 w1 w2 w3 H1 + (w1 w2 + w2 w3 + w3 w1) H2 "
                                   "+ 2 w1 w2 w3 (w1 + w2 + w3) H3")
        s.require(lie_derivative(get_system(FLOW2), l0).is_zero(), "L(x, 0) is not an integral of the second flow")
        cert.formula("L(x,0)", "-2*w1*w2*w3*H1 + (w1*w2 + w2*w3 + w3*w1)*H2 + 2*w1*w2*w3*(w1 + w2 + w3)*H3")
    with cert.step("w_j E_i - w_i E_j = (w_i - w_j) E_k", "exact, all six permutations (i, j, k)", r) as s:
        for i, j, k in itertools.permutations((1, 2, 3)):
            s.require(named(f, indexed(claimed["identity"], i=i, j=j, k=k), known).is_zero(), f"identity fails for {(i, j, k)}")
    with cert.step("eq. \"c thru b\" for the coefficients of L(x, 0)", "exact; printed and corrected b_i", r) as s:
        def holds(b_text: str) -> bool:
            bs = {f"b{i}": named(f, indexed(b_text, i=i, j=j, k=k), known) for i, j, k in ((1, 2, 3), (2, 3, 1), (3, 1, 2))}
            cs = {i: named(f, indexed(claimed["c_of_L0"], i=i, j=j, k=k), known)
                  for i, j, k in ((1, 2, 3), (2, 3, 1), (3, 1, 2))}
            return all(cs[i] == named(f, C_THRU_B[f"c{i}"], bs) for i in (1, 2, 3))
        corrected = rename(claimed["b_of_L0"], {"E_j": "E_i"})     # the one wrong index of the printed b_i
        readings = (claimed["b_of_L0"], rename(claimed["b_of_L0"], {"E_j": "E_k"}))    # (i, j, k) cyclic or not
        printed_ok = any(holds(b_text) for b_text in readings)
        s.require(holds(corrected), f"eq. \"c thru b\" fails for b_i = {corrected}, c_i = {claimed['c_of_L0']}")
        parts = {i: named(f, indexed(f"{claimed['c_of_L0']}*m_i**2 + ({corrected})*p_i**2", i=i, j=j, k=k), known)
                 for i, j, k in ((1, 2, 3), (2, 3, 1), (3, 1, 2))}
        s.require_equal(sum(parts.values(), Frac(r, 0)), l0, "L(x, 0) = sum c_i m_i^2 + b_i p_i^2")
        if not printed_ok:
            cert.correction("end of sec. 6 (proof of the second-flow theorem): the conditions \"c thru b\" are to be "
                            "checked for b_i = w_j w_k E_i (not w_j w_k E_j) and c_i = w_i E_i, (i, j, k) cyclic; "
                            "these are the coefficients of L(x, 0) = sum (c_i m_i^2 + b_i p_i^2). With the printed "
                            "b_i = w_j w_k E_j the conditions fail.")
        s.note("printed b_i (either order of j, k): conditions " + ("hold" if printed_ok else "fail") +
               f"; with the index corrected, b_i = {corrected}: conditions hold")


# ---------------------------------------------------------------- every flow: b symbolic ------------------------
def _cyc(text: str) -> dict[str, str]:
    """Three cyclic instances of a template with indices _i, _j, _k and _l = _i + 3 (keys 1, 2, 3)."""
    return {str(i + 1): indexed(text, i=i + 1, j=j + 1, k=k + 1, l=i + 4) for i, j, k in CYCLIC}


GENERAL_CLAIM = {
    **{f"rel{n}": f"{v} = 0" for n, v in _cyc("z*c_i*e_i - c_j*c_k*e_l").items()},
    "rel4": "e1 - e2 - (w1 - w2)*e6 = eps**2*c3**2*(w1 - w2)",
    "rel5": "e3 - e1 - (w3 - w1)*e5 = eps**2*c2**2*(w3 - w1)",
    "rel6": "e2 - e3 - (w2 - w3)*e4 = eps**2*c1**2*(w2 - w3)",
    "A": " + ".join(_cyc("E_i*(c_j*c_k*p_i**2 + z*c_i*m_i**2)").values()),
    "D": "z + eps**2*(c1*c2*c3*(p1**2 + p2**2 + p3**2) + z*(c1**2*m1**2 + c2**2*m2**2 + c3**2*m3**2))",
    "L": "A/D",
    **{f"e{i}": v for i, v in _cyc("c_j*c_k*(E_i/L - eps**2*c_i)/z").items()},
    **{f"e{int(i) + 3}": v for i, v in _cyc("c_i*(E_i/L - eps**2*c_i)").items()},
}
GENERAL_NAMES = {"c1": C_OF_YZ[0], "c2": C_OF_YZ[1], "c3": C_OF_YZ[2],
                 **{f"E{i}": v for i, v in _cyc("(c_i*c_j + c_i*c_k - c_j*c_k)").items()}}


@claim("flow-general-phi0", GROUP, "Every Clebsch flow: Phi0 = (p^2, m^2, 1) is an HK-basis, dim K = 1, integral L_b",
       "sec. 6, conjecture after eq. \"dC2 map\", claim on eq. \"Clebsch2 first basis\" (\"proven symbolically\")",
       "With b_k = s + y w_k - z w_i w_j (any b, w distinct; c_k = y + z w_k): the kernel coordinates satisfy "
       "z c_i e_i = c_j c_k e_(i+3) and e_i - e_j - (w_i - w_j) e_(k+3) = eps^2 c_k^2 (w_i - w_j); they are the "
       "printed functions of L = A/D, an integral of the map with A = sum E_i (c_j c_k p_i^2 + z c_i m_i^2), "
       "E_i = c_i c_j + c_i c_k - c_j c_k, D = z + eps^2 (c1 c2 c3 H3 + z sum c_i^2 m_i^2); dim K_Phi0 = 1. "
       "At (y, z) = (0, 1) this is the second-flow theorem; at z = 0 the e_k are those of Th. \"dC basis 1\" (J).",
       claimed=GENERAL_CLAIM, uses=["flow-reduction", "flow-second-theorem"])
def prove_general_phi0(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = yz_map()
    r = f.ring
    names = e_names()
    known = {k: named(f, v, {}) for k, v in GENERAL_NAMES.items() if k.startswith("c")}
    known.update({k: named(f, v, known) for k, v in GENERAL_NAMES.items() if k.startswith("E")})
    with cert.step("parametrization covers every b", "citation: flow-general-map, step (s, y, z)", "-") as s:
        s.note("flow-general-map proves that the general map at b_k = s + y w_k - z w_i w_j is this map, and that "
               "(s, y, z) -> b is invertible over Q(w); so y, z, w symbolic here means b, w symbolic")
    rels = [parse_relation(r, _substitute_c(claimed[f"rel{k}"]), names) for k in range(1, 7)]
    with cert.step("the sixth relation follows from the first five", "ranks over Q(eps, w, y, z)", r) as s:
        s.require(relation_rank(rels[:5]) == 5, "relations 1-5 are not independent")
        s.require(relation_rank(rels) == 5, "relation 6 is not a consequence of relations 1-5")
    a_poly = named(f, claimed["A"], known)
    d_poly = named(f, claimed["D"], known)
    big_l = named(f, claimed["L"], {**known, "A": a_poly, "D": d_poly})
    with cert.step("e from the six equations", "Cramer's rule: sum e_k phi_k = 1 and relations 1-5 (no iterates)",
                   r) as s:
        e = _e_as_functions_of_l(cert, s, f, rels, names, claimed, {**known, "L": big_l})
        cert.formula("L", big_l)
    with cert.step("L is an integral (transport of the second flow's L)", "L = z^3 sigma(L_2), exact in "
                   "Q(x, eps, w, y, z); sigma(f_2) = f (flow-reduction), L_2 o f_2 = L_2 (flow-second-theorem)", r) as s:
        sigma, _ = reduction_substitutions(require_proven(cert, "flow-reduction").formulas)
        l2 = _cite_l(cert, kahan_map(FLOW2), "flow-second-theorem")
        s.require_equal(big_l, Frac(r, r.gen("z") ** 3) * sigma.apply(l2), "L = z^3 sigma(L_2)")
        s.note("sigma is an injective homomorphism of fields fixing x with sigma(f_2) = f, so L o f = L follows from "
               "L_2 o f_2 = L_2 (z^3 is a constant of the map); the substitution L(N/Delta) - L took 32 s")
    _kernel_lower_bound(cert, f, e, "L")
    _kernel_rank_bound(cert, f, e)
    with cert.step("L(x, 0) = A / z is an integral of the continuous flow", "Lie derivative along eq. \"gcl\"; "
                   "A = sum_k E_k c_i c_j I_k (eq. \"Clebsch I\")", r) as s:
        s.require(lie_derivative(f.field, a_poly).is_zero(), "A is not an integral of the continuous general flow")
        combo = named(f, " + ".join(_cyc("E_i*c_j*c_k*I_i").values()), known)
        s.require_equal(a_poly, combo, "A = sum_k E_k c_i c_j I_k")
    flow2 = kahan_map(FLOW2)
    with cert.step("(y, z) = (0, 1): the second-flow L", "specialization, exact", flow2.ring) as s:
        s.require_equal(big_l.specialize({"y": 0, "z": 1}, flow2.ring),
                        named(flow2, SECOND["L"], {k: Frac.parse(flow2.ring, v) for k, v in E_PAPER.items()}),
                        "L at (y, z) = (0, 1)")
    first = kahan_map("clebsch")
    with cert.step("(y, z) = (1, 0): the first flow, e_k = 1/J + eps^2 w_k, e_(k+3) = 0",
                   "specialization of the lowest-terms e_k, exact", first.ring) as s:
        j = Frac.parse(first.ring, "(p1**2 + p2**2 + p3**2)/(1 - eps**2*(w1*p1**2 + w2*p2**2 + w3*p3**2))")
        for k, a in enumerate(e):
            want = j.inverse() + Frac.parse(first.ring, f"eps**2*w{k + 1}") if k < 3 else Frac(first.ring, 0)
            s.require_equal(a.specialize({"y": 1, "z": 0}, first.ring), want, f"e{k + 1} at (y, z) = (1, 0)")
        s.note("e o f = e holds in Q(x, eps, w, y, z) and the e_k have no pole along z = 0, so it specializes")


def _substitute_c(text: str) -> str:
    """c_k -> (y + z w_k) in a relation's text (E_k do not occur in relations)."""
    return rename(text, {f"c{k + 1}": c for k, c in enumerate(C_OF_YZ)})


# ---------------------------------------------------------------- the second flow's Phi1, Phi2, Phi3: discovery ---
# Found by hkproof (recipe (E), `find_relations`, 17 exact samples, degree 2 in w, eps-free); printed as found.
SECOND_REL18 = {
    "rel2_1": "b2*w2 - b5*w1*w3 - c3*w3 + c6*w1*w2 = 0",
    "rel2_2": "a1*w1 - a4*w2*w3 - b2*w2 + b5*w1*w3 = 0",
    "rel2_3": "a2*w2*(w1 - w3) - a3*w3*(w1 - w2) - a5*w1*w3*(w1 - w3) + a6*w1*w2*(w1 - w2) = 0",
    "rel2_4": "b1*w1*(w2 - w3) + b3*w3*(w1 - w2) - b4*w2*w3*(w2 - w3) - b6*w1*w2*(w1 - w2) = 0",
    "rel2_5": "c1*w1*(w2 - w3) - c2*w2*(w1 - w3) - c4*w2*w3*(w2 - w3) + c5*w1*w3*(w1 - w3) = 0",
    "rel2_6": "a2 - a3 - (w2 - w3)*a4 + b2 - b3 - (w2 - w3)*b4 + c2 - c3 - (w2 - w3)*c4 = 0",
    "rel2_7": "a1 - a3 - (w1 - w3)*a5 + b1 - b3 - (w1 - w3)*b5 + c1 - c3 - (w1 - w3)*c5 = 0",
    "rel2_8": "(w1 - w3)*(a2 - a3 - (w2 - w3)*a4) + (w2 - w3)*(b2 - b3 - (w2 - w3)*b4) = 0",
    "rel2_9": "a1*w3 + a3*(w1 - w3) - a4*w2*w3 + a5*(w1 - w3)**2 + b1*(w3 - w2) - b2*w2 + b3*(w2 - w3) "
              "+ b5*(w1*w2 - w2*w3 + w3**2) = 0",
}
SECOND_REL18_RANKS = {"rows01": "15", "rows01_theta": "16", "symmetric": "18", "L_relations": "5",
                      "rows0_L": "17", "rows01_L": "18"}
L_SAMPLE: dict[str, Rational] = {"eps": flint.fmpq(1, 3), "w1": 2, "w2": -3, "w3": 5}


@claim("flow-second-relations-found", GROUP, "Second flow: nine linear relations among the kernel coordinates of "
       "Phi1, Phi2, Phi3, found by recipe (E)", "sec. 6, conjecture after eq. \"dC2 map\"; analog of eqs. "
       "\"rel18_1\" ... \"rel18_8\" (not in the paper)",
       "For the second flow, exact relation finding (kernels of Phi_k = (p^2, m^2, m_k p_k) at rational points, "
       "interpolation in eps and w) finds a nine-dimensional space of linear relations among alpha_j, beta_j, "
       "gamma_j, spanned by the claimed relations (eps-free, coefficients in Z[w]). At a rational point the rows "
       "i = 0, 1 and the relations have rank `rows01`, with the Theta relations alpha_j + beta_j + gamma_j = g_j "
       "`rows01_theta` (two short of 18: the analogs of 'dC Psi add lin rel' are missing), and the symmetric rows "
       "i = -1, 0, 1 with the relations `symmetric`. The first flow's chains rel18_6 and rel18_8 lie in this space "
       "(so they hold for the second flow too); rel18_1 ... rel18_4 (the structure of eq. \"M2\") do not. At fixed "
       "rational eps, w there are `L_relations` more relations with coefficients linear in the integral L; with them "
       "the rows i = 0 have rank `rows0_L` and the rows i = 0, 1 rank `rows01_L`: one row with an iterate would "
       "suffice. Evidence, not proof.",
       claimed={**SECOND_REL18, **SECOND_REL18_RANKS, "rel18_6": REL18["rel18_6"], "rel18_8": REL18["rel18_8"]},
       expected=Status.EVIDENCE_EXACT, uses=["flow-second-theorem"])
def prove_second_relations_found(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(FLOW2)
    r = f.ring
    phis = phi_bases(f)
    with cert.step("the claimed relations are nine independent relations", "rank over Q(eps, w) of the augmented "
                   "rows", r) as s:
        claimed_rels = [parse_relation(r, claimed[k], ABC_NAMES) for k in SECOND_REL18]
        s.require(relation_rank(claimed_rels) == 9, "the claimed relations are not nine independent ones")
    with cert.step("recipe (E): the relation space of (Phi1, Phi2, Phi3) is spanned by the claimed relations",
                   "exact kernels at rational points, interpolation in eps and w, fresh checks", r) as s:
        search = find_relations(f, phis, names=list(ABC_NAMES))
        found = [Relation(rel.coefficients, rel.rhs) for rel in search.relations]
        s.require(search.dimension == 9 and len(found) == 9,
                  f"relation space of dimension {search.dimension}, {len(found)} relations reconstructed")
        s.require(relation_rank(found + claimed_rels) == 9, "a claimed relation is not in the space found")
        for k, rel in enumerate(search.relations, start=1):
            cert.formula(f"found_{k}", rel.text())
        s.evidence(Status.EVIDENCE_EXACT, points=search.samples)
        s.note(f"{search.samples} exact samples; every relation checked at fresh samples")
    with cert.step("the first flow's relations: rel18_6, rel18_8 shared, rel18_1 ... rel18_4 not",
                   "ranks over Q(eps, w) with the claimed relations", r) as s:
        for key in ("rel18_6", "rel18_8"):
            s.require(relation_rank(claimed_rels + relation_rows(f, claimed[key])) == 9,
                      f"{key} is not in the second flow's relation space")
        for key in ("rel18_1", "rel18_2", "rel18_3", "rel18_4"):
            s.require(relation_rank(claimed_rels + relation_rows(f, REL18[key])) > 9,
                      f"{key} unexpectedly holds for the second flow")
    with cert.step("how far the relations go: exact ranks at a rational point", "fmpq_mat ranks of the rows "
                   "(values of Phi_k o f^i) and the relations at the point", "Q at one rational point") as s:
        point = {k: v for k, v in RANK_POINT.items() if k in r.names}
        theta_rows = [[flint.fmpq(int(k % 6 == j)) for k in range(18)] for j in range(6)]

        def rank(iterates: Sequence[int], extra: Sequence[Sequence[flint.fmpq]]) -> int:
            rows, _ = system_at(f, phis, iterates, claimed_rels, point)
            return flint.fmpq_mat(rows + list(extra)).rank()

        for key, got in (("rows01", rank((0, 1), [])), ("rows01_theta", rank((0, 1), theta_rows)),
                         ("symmetric", rank((-1, 0, 1), []))):
            s.require(str(got) == claimed[key].strip(), f"rank {key} = {got}, claimed {claimed[key]}")
        s.evidence(Status.EVIDENCE_EXACT, points=1)
        s.note("rows i = 0, 1 and the nine relations leave a 2-dimensional family, the Theta relations (right-hand "
               "sides the proven integrals g_j of flow-second-theta) one more condition: two relations with "
               "integral right-hand sides are still to be found before Prop. \"prop: even\" applies; the symmetric "
               "system determines alpha, beta, gamma (the paper's Step 2 route, which proves nothing by itself)")
    _l_relations(cert, f, phis, claimed)


def _l_relations(cert: Certificate, f: KahanMap, phis: Sequence[Sequence[Frac]], claimed: Mapping[str, str]) -> None:
    """Relations sum (c_k + d_k L) a_k + c_0 + d_0 L = 0 at fixed eps, w: null space of samples (a, L a, 1, L)."""
    with cert.step("relations with coefficients linear in L (fixed eps, w)", "null space of exact samples of "
                   "(alpha, beta, gamma, 1) and L times them; ranks with the rows at a fresh point",
                   f"Q at eps, w = {L_SAMPLE}") as s:
        big_l = _cite_l(cert, f, "flow-second-theorem")
        rng = random.Random(1)
        samples: list[list[flint.fmpq]] = []
        while len(samples) < 60:
            point = {**L_SAMPLE, **random_point(rng, f.variables, 9, denominator=5, zero=True)}
            try:
                a = kernel_coordinates(f, phis, point)
            except SingularPointError:
                continue
            if a is not None:
                samples.append([c * big_l.evaluate(point) ** d for d in (0, 1) for c in (*a, flint.fmpq(1))])
        space = nullspace_q(samples)
        s.require(str(len(space) - 18) == claimed["L_relations"].strip(),
                  f"{len(space)} relations linear in L, i.e. {len(space) - 18} beyond the nine and their L-multiples")
        point = {**L_SAMPLE, **random_point(rng, f.variables, 9, denominator=5, zero=True)}
        l0 = big_l.evaluate(point)
        rel_rows = [[v[k] + v[19 + k] * l0 for k in range(18)] for v in space]
        orbit = f.orbit_exact(point, 1)
        hk = {i: block_rows_at(phis, [{**point, **orbit[i]}])[0] for i in (0, 1)}
        for key, rows in (("rows0_L", hk[0]), ("rows01_L", hk[0] + hk[1])):
            got = flint.fmpq_mat(rows + rel_rows).rank()
            s.require(str(got) == claimed[key].strip(), f"rank {key} = {got}, claimed {claimed[key]}")
        s.evidence(Status.EVIDENCE_EXACT, points=len(samples))
        s.note("the relations in L are known only at this (eps, w): their symbolic reconstruction (interpolation in "
               "eps and w, as recipe (E) does for constant relations) is the missing step; then the 18 unknowns "
               "follow from rows i = 0, 1 and relations with even integral coefficients (L), Prop. \"prop: even\"")


# ---------------------------------------------------------------- the ten monomials of Th. "dClebsch max basis" ---
PHI_MAX_TEXT = "p1**2, p2**2, p3**2, m1**2, m2**2, m3**2, m1*p1, m2*p2, m3*p3, 1"
SUB_BASES = {"Phi0": (0, 1, 2, 3, 4, 5, 9), "Phi1": (0, 1, 2, 3, 4, 5, 6), "Phi2": (0, 1, 2, 3, 4, 5, 7),
             "Phi3": (0, 1, 2, 3, 4, 5, 8)}


# ---------------------------------------------------------------- towards the conjecture: Theta for every flow ---
THETA_RELATION = ("(w2 - w3)*c1*(eps**2*L - c1)*g1 + (w3 - w1)*c2*(eps**2*L - c2)*g2 "
                  "+ (w1 - w2)*c3*(eps**2*L - c3)*g3 = 0")
# c_k = y + z w_k and b_k - b_j are unchanged by w -> w + c, y -> y - z c: the flow of the family does not move
YZ_SHIFT = ParameterTranslation(("w1", "w2", "w3"), "w3", (("y", "-z"),))
THETA_NAMES = ("g1", "g2", "g3")


@claim("flow-second-theta", GROUP, "Second flow: Theta = (p^2, m^2, H4) is an HK-basis; L, g1, g2 independent",
       "sec. 6, Th. \"dC Theta\" for the second flow; eqs. \"Theta rels\", \"clebsch_ansatz_3a\"",
       "For the second flow (w, eps symbolic): (g1, g2, g3) from (sum g_k I_k) o f^i = H4 o f^i, i = 0, 1, and the "
       "relation with coefficients in the integral L are even in eps, hence integrals (Prop. \"prop: even\"); "
       "[g1 : ... : g6 : -1] with eq. \"Theta rels\" spans K_Theta (dim 1); L, g1, g2 are functionally independent.",
       claimed={"relation": THETA_RELATION}, uses=["flow-second-theorem"])
def prove_second_theta(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(FLOW2)
    big_l = _cite_l(cert, f, "flow-second-theorem")
    rel = _theta_relation(cert, f, ("w1", "w2", "w3"), big_l, claimed["relation"])
    basis, h4 = _theta_basis(f)
    point = {k: v for k, v in RANK_POINT.items() if k in f.ring.names}
    sol = prove_by_symmetry(cert, f, basis, h4, THETA_NAMES, CYCLIC_SHIFT, point, (0, 1), [rel])
    for k, v in zip(THETA_NAMES, sol, strict=True):
        record(cert, k, v)
    _theta_kernel(cert, f, basis, h4)
    _independent(cert, f, [big_l, *sol], "L, g1, g2")


@claim("flow-theta-all", GROUP, "Theta = (p^2, m^2, H4) is an HK-basis of every flow; three integrals",
       "sec. 6, Th. \"dC Theta\" and the conjecture after eq. \"dC2 map\"",
       "With w, y, z, eps symbolic (b_k = s + y w_k - z w_i w_j, c_k = y + z w_k: every flow), z != 0: the second "
       "flow's Theta kernel (flow-second-theta) carried by the substitution of flow-reduction is the unique solution "
       "(g1, g2, g3) of (sum g_k I_k) o f^i = H4 o f^i, i = 0, 1, and the claimed relation in L = L_b (the integral "
       "of flow-general-phi0, = z^3 sigma(L) for the second flow's L); the g_k are even in eps and integrals; with "
       "g4..g6 by eq. \"Theta rels\" they span K_Theta (dim 1); L_b, g1, g2 are functionally independent. z = 0: "
       "the first flow's Theta kernel (dc-theta) at eps' = y eps.",
       claimed={"relation": THETA_RELATION}, uses=["flow-reduction", "flow-second-theta", "flow-second-theorem", "dc-theta"])
def prove_theta_all_flows(cert: Certificate, claimed: Mapping[str, str]) -> None:
    sigma, sigma0 = reduction_substitutions(require_proven(cert, "flow-reduction").formulas)
    g, g0 = yz_map(), yz_map_at_z0()
    second, flow2 = require_proven(cert, "flow-second-theta"), kahan_map(FLOW2)
    l2 = _cite_l(cert, flow2, "flow-second-theorem")
    source_sol = [recall(second, k, flow2.ring) for k in THETA_NAMES]
    with cert.step("z != 0: L_b = z^3 sigma(L) and the Theta kernel carried by sigma", "the substitution of "
                   "flow-reduction applied exactly (one homogenized compose each); L_b = A/D as in flow-general-phi0",
                   g.ring) as s:
        big_l = Frac(g.ring, g.ring.gen("z") ** 3) * sigma.apply(l2)
        known = {k: named(g, v, {}) for k, v in GENERAL_NAMES.items() if k.startswith("c")}
        known.update({k: named(g, v, known) for k, v in GENERAL_NAMES.items() if k.startswith("E")})
        a_poly, d_poly = named(g, GENERAL_CLAIM["A"], known), named(g, GENERAL_CLAIM["D"], known)
        s.require_equal(big_l, a_poly / d_poly, "z^3 sigma(L) = A/D")
        sol = [sigma.apply(v) for v in source_sol]
        s.note("sigma(f_2) = f_(y,z) (flow-reduction) and sigma is an injective homomorphism of fields fixing x: "
               "the identities proven for the second flow -- rows i = 0, 1, L o f = L, g_k o f = g_k -- hold for "
               "their images; the next step checks that sigma carries each equation of the system to this map's")
        for k, v in zip(THETA_NAMES, sol, strict=True):
            record(cert, k, v)
    source_rel = _theta_relation(cert, flow2, ("w1", "w2", "w3"), l2, claimed["relation"])
    rel = _theta_relation(cert, g, C_OF_YZ, big_l, claimed["relation"])
    _transported_solution(cert, sigma, (*_theta_basis(flow2), [source_rel]), g, (*_theta_basis(g), [rel]),
                          source_sol, "z != 0")
    basis, h4 = _theta_basis(g)
    _theta_kernel(cert, g, basis, h4)
    _independent(cert, g, [big_l, *sol], "L_b, g1, g2")
    first = kahan_map(FIRST)
    theta1 = require_proven(cert, "dc-theta")
    source0 = [recall(theta1, k, first.ring) for k in THETA_NAMES]
    with cert.step("z = 0: the first flow's Theta kernel at eps' = y eps", "sigma0 of flow-reduction applied "
                   "exactly", g0.ring) as s:
        sol0 = [sigma0.apply(v) for v in source0]
        s.note("sigma0(f_1) = f_(y,0) (flow-reduction): dc-theta's identities carry over")
    _transported_solution(cert, sigma0, (*_theta_basis(first), []), g0, (*_theta_basis(g0), []), source0, "z = 0")
    basis0, h40 = _theta_basis(g0)
    _theta_kernel(cert, g0, basis0, h40)


def _cite_l(cert: Certificate, kmap: KahanMap, claim_id: str) -> Frac:
    """The integral L proven in `claim_id` (its certificate must be verified), as a function on `kmap`."""
    return Frac.parse(kmap.ring, require_proven(cert, claim_id).formulas["L"])


def _theta_basis(f: KahanMap) -> tuple[list[Frac], Frac]:
    """Eq. "clebsch_ansatz_3a": the reduced basis (I1, I2, I3) and the target H4."""
    return [named(f, i) for i in ("I1", "I2", "I3")], named(f, "H4")


def _theta_relation(cert: Certificate, f: KahanMap, c_of: Sequence[str], big_l: Frac, relation: str) -> Relation:
    """The claimed relation among g1, g2, g3 with coefficients polynomials in the even integral L."""
    r = f.ring
    with cert.step("the relation in L", "coefficients polynomials in L (an even integral); parameters symbolic",
                   r) as s:
        s.require(big_l.is_even_in("eps"), "L is not even in eps")
        lhs = rename(relation.split("=")[0], {f"c{k + 1}": c for k, c in enumerate(c_of)})
        unit = {n: Frac(r, 0) for n in THETA_NAMES}
        coefficients = [named(f, lhs, {"L": big_l, **unit, k: Frac(r, 1)}) for k in THETA_NAMES]
        s.require(named(f, relation.split("=")[1], {"L": big_l}).is_zero(), "the relation is not homogeneous")
    return Relation(coefficients, Frac(r, 0), source="L is an even integral (flow-second-theorem)")


def _transported_solution(cert: Certificate, sigma: Substitution,
                          source: tuple[Sequence[Frac], Frac, Sequence[Relation]], f: KahanMap,
                          target: tuple[Sequence[Frac], Frac, Sequence[Relation]], sol: Sequence[Frac],
                          case: str) -> None:
    """What the image under sigma of a source solution `sol` of rows i = 0, 1 (+ relations) must satisfy on the new
    map f, read on the source: sigma fixes x and commutes with eps -> -eps, and carries each equation of the source
    system (basis, target, relations) to the new map's up to a non-zero factor (checked on the small functions), so
    parity, row i = 0 and the relations of sigma(sol) follow from those of sol; the images are not expanded."""
    (basis_s, target_s, rels_s), (basis_t, target_t, rels_t) = source, target
    r = f.ring
    with cert.step(f"{case}: the transported (g1, g2, g3) is the unique solution, even in eps",
                   "transport: sigma fixes x and commutes with eps -> -eps, and maps each equation of the source "
                   "system to this map's times a non-zero factor (exact, on the basis functions and the relations' "
                   "coefficients); exact parity, row i = 0 and the relations by substitution on the source; row i = 1 "
                   "by transport; det of the system at a rational point", r) as s:
        require_transport(s, sigma, f)
        for k, v in zip(THETA_NAMES, sol, strict=True):
            s.require(v.is_even_in(EPS), f"the source's {k} is not even in eps")
        s.require(linear_combination_equals(basis_s, sol, target_s), "row i = 0 fails for the source solution")
        s.require(_proportional([sigma.apply(h) for h in (*basis_s, target_s)], [*basis_t, target_t]),
                  "sigma does not carry the source's row i = 0 to this map's")
        s.require(len(rels_s) == len(rels_t), "the source and this map have different relations")
        for rel_s, rel_t in zip(rels_s, rels_t, strict=True):
            s.require(rel_s.rhs.is_zero() and rel_t.rhs.is_zero(), "a relation is not homogeneous")
            s.require(linear_combination_equals(rel_s.coefficients, sol, rel_s.rhs), "the relation fails on the source")
            s.require(_proportional([sigma.apply(c) for c in rel_s.coefficients], rel_t.coefficients),
                      "sigma does not carry the source's relation to this map's")
        point = {k: v for k, v in RANK_POINT.items() if k in r.names}
        iterates = (0, 1) if rels_t else (0, 1, 2)
        det = det_at_point(f, basis_t, iterates, rels_t, point)
        s.require(det != 0, "the transported system is singular at the sample point")
        s.note(f"det = {det} at a rational point: the solution is unique; its image is even in eps and satisfies "
               "rows i = 0, 1 and the relations (images of the source's identities), so Prop. \"prop: even\" makes "
               "g1, g2, g3 integrals -- as does the transport of g_k o f = g_k itself")


def _proportional(images: Sequence[Frac], wanted: Sequence[Frac]) -> bool:
    """images = lambda * wanted for one non-zero lambda (exact; a zero entry only against a zero entry)."""
    pivot = next((k for k, h in enumerate(wanted) if not h.is_zero()), None)
    if pivot is None or images[pivot].is_zero():
        return False
    lam = images[pivot] / wanted[pivot]
    return all(a == lam * b for a, b in zip(images, wanted, strict=True))


def _theta_kernel(cert: Certificate, f: KahanMap, basis: Sequence[Frac], h4: Frac) -> None:
    """K_Theta = [g1 : ... : g6 : -1] with eq. "Theta rels", dim 1 (exact rank of X_[0,6] at a rational point)."""
    r = f.ring
    with cert.step("K_Theta = [g1 : ... : g6 : -1], dim 1", "eq. \"Theta rels\" expands sum g_k I_k in monomials "
                   "(identity for symbolic g_k); exact rank of X_[0,6] at a rational point", r) as s:
        sym = r.extend(THETA_NAMES)
        gk = [Frac.parse(sym, n) for n in THETA_NAMES]
        wk = [named(f, n).to_ring(sym) for n in ("w1", "w2", "w3")]
        full = gk + [(gk[1] - gk[2]) / (wk[1] - wk[2]), (gk[2] - gk[0]) / (wk[2] - wk[0]),
                     (gk[0] - gk[1]) / (wk[0] - wk[1])]
        mono = [Frac.parse(sym, phi) for phi in PHI0]
        s.require_equal(sum((a * m for a, m in zip(full, mono, strict=True)), Frac(sym, 0)),
                        sum((a * b.to_ring(sym) for a, b in zip(gk, basis, strict=True)), Frac(sym, 0)), "sum g_k phi_k")
        point = {k: v for k, v in RANK_POINT.items() if k in r.names}
        rows = [[Frac.parse(r, phi).evaluate({**point, **x}) for phi in PHI0] + [h4.evaluate({**point, **x})]
                for x in f.orbit_exact(point, 6)]
        s.require(flint.fmpq_mat(rows).rank() == 6, "rank X_[0,6] != 6 for Theta at the sample point")


def _independent(cert: Certificate, f: KahanMap, funcs: Sequence[Frac], names: str) -> None:
    """The first three of `funcs` are functionally independent: exact Jacobian rank 3 at a rational point."""
    r = f.ring
    with cert.step(f"{names} functionally independent", "exact Jacobian rank at a rational point (parameters and "
                   "eps set first, then derivatives in x)", r) as s:
        point = {k: v for k, v in RANK_POINT.items() if k in r.names}
        params = {k: v for k, v in point.items() if k not in f.variables}
        small = r.drop(params)
        small_funcs = [h.specialize(params, small) for h in funcs]
        xs = {k: point[k] for k in f.variables}
        rank = jacobian_rank_at(small_funcs[:3], f.variables, xs)
        s.require(rank == 3, f"{names} have Jacobian rank {rank} at the point")
        s.note(f"rank of the Jacobian of all {len(funcs)}: {jacobian_rank_at(small_funcs, f.variables, xs)}; full "
               "rank at one point proves independence over the field of the symbolic parameters")
