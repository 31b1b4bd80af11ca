"""Section 6.7, proof of Th. "dC bases 345", Steps 2-5 with eps and w symbolic, and Th. "dClebsch max basis"."""
from __future__ import annotations

from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import rank_q
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import EPS
from hkproof.errors import ParseError
from hkproof.hk.block_system import BlockSystem, check_block, prove_block
from hkproof.hk.expansion import homogeneous_eps_pieces
from hkproof.hk.independence import sample_point
from hkproof.hk.reduced import OverCommonDenominator, Relation, linear_combination_equals
from hkproof.orchestration.registry import claim, require_proven
from hkproof.proof.certificate import Certificate
from hkproof.theorems._clebsch import SYSTEM, TRANSLATION, X, named, recall, record
from hkproof.theorems.clebsch_bases_345.data import BLOCK, F_TEXT, GROUP, REL18, UNKNOWNS, bases, relation_rows
from hkproof.theorems.clebsch_kernels import POINTS, phi_max_profiles

__all__ = ["ALPHA123", "F_VIA_ABCD", "kernel_vectors", "part_two", "prove_alpha", "prove_max_basis", "prove_step5",
           "SYMMETRIC"]

ALPHA123 = {"a1": "H3 - I1", "a2": "-I1", "a3": "-I1", "b1": "-I2", "b2": "H3 - I2", "b3": "-I2",
            "c1": "-I3", "c2": "-I3", "c3": "H3 - I3"}
F_VIA_ABCD = "((w2 - w3)*(A*D + 1/4) - A*(B - C))/D"
SYMMETRIC = (-1, 0, 1)


def _block(c: str) -> list[str]:
    return [f"{c}{j}" for j in range(1, 7)]


def _m2_rows(abcd: Certificate, r) -> list[Relation]:
    """The rows a4 = ..., ..., c6 = ... of eq. "M2" (integrals A, B, C, D of dc345-abcd) over all 18 unknowns."""
    zero, one = Frac(r, 0), Frac(r, 1)
    return [Relation([one if u == name else zero for u in UNKNOWNS], recall(abcd, name, r), "dc345-abcd")
            for name in (f"{c}{j}" for c in "abc" for j in (4, 5, 6))]


def part_two(f, abcd: Certificate, relations: Sequence[Relation]) -> tuple[BlockSystem, BlockSystem]:
    """Phi1, Phi2, Phi3 with the rows i = 0, 1, eq. "M2" and further `relations` (the systems of Steps 3-5), and
    with the rows i = -1, 0, 1 and eq. "M2" alone (the symmetric systems of Step 2)."""
    m2 = _m2_rows(abcd, f.ring)
    system = BlockSystem(f, tuple(tuple(b) for b in bases(f)), (*m2, *relations), (0, 1))
    return system, system.with_(relations=m2, iterates=SYMMETRIC)


def _bigint_form(s, f, h: Frac, name: str, leading: str, delta: Frac) -> None:
    """Eq. "bigint_form": 2 eps^2 H3 Delta h = h^(2) + eps^2 h^(4) + ... + eps^10 h^(12), h^(2) as in "alpha123"."""
    r = f.ring
    top = h * Frac(r, 2 * r.gen(EPS) ** 2) * named(f, "H3") * delta
    pieces = homogeneous_eps_pieces(top, EPS, X, 6, 2, f"2 eps^2 H3 Delta {name}")
    s.require_equal(pieces[0], named(f, leading), f"{name}^(2)")


def _solve_block(cert: Certificate, system: BlockSystem, c: str, known: Mapping[int, Frac], source: str) -> list[Frac]:
    """Prop. "prop: even" for the rows i = 0, 1 of one block, the rows of eq. "M2" and one more relation."""
    sol = prove_block(cert, system, "abc".index(c), known, _block(c), source, TRANSLATION)
    for name, h in zip(_block(c), sol, strict=True):
        record(cert, name, h)
    return sol


def _symmetric_step(cert: Certificate, symmetric: BlockSystem, c: str, sol: Sequence[Frac], delta: Frac,
                    claimed: Mapping[str, str]) -> None:
    """Step 2: the solution also solves the symmetric system i = -1, 0, 1, uniquely; eqs. "bigint_form", "alpha123"."""
    f = symmetric.kmap
    r = f.ring
    b = "abc".index(c)
    with cert.step(f"Step 2 ({c}): the symmetric system i = -1, 0, 1 has this unique solution",
                   "substitution into the row i = -1 (f^-1(x, eps) = f(x, -eps)), on the slice w3 = 0 when "
                   "everything is invariant under w -> w + c; det at a rational point", r) as s:
        s.require(check_block(symmetric.with_(relations=(), iterates=(-1,)), b, {}, sol, TRANSLATION),
                  "the row i = -1 fails")
        det = symmetric.block_det_at(b, sample_point(r.names, seed=3))
        s.require(det != 0, "the symmetric system is singular at the sample point")
        s.note(f"det = {det} at a rational point: the symmetric system determines {c}1, {c}2, {c}3")
    with cert.step(f"eqs. \"bigint_form\" and \"alpha123\" for {c}1, {c}2, {c}3",
                   "eps-coefficients of 2 eps^2 H3 Delta h; homogeneity in (m, p)", r) as s:
        for j in range(3):
            name = f"{c}{j + 1}"
            _bigint_form(s, f, sol[j], name, claimed[f"{name}_2"], delta)


@claim("dc345-alpha", GROUP,
       "Proof of Th. \"dC bases 345\", Steps 3, 4 and 2: F, alpha_1, alpha_2, alpha_3, with eps and w symbolic",
       "sec. 6.7, proof of Th. \"dC bases 345\", Steps 2-4; eqs. \"eq:F\", \"bigint_form\", \"alpha123\"",
       "Step 3: F = ((w2 - w3)(A D + 1/4) - A (B - C))/D (a relation found by hkproof, not in the paper) is an "
       "integral, even in eps, with 2 eps^2 Delta F/(w2 - w3) = 1 + eps^2 F^(2) + ... + eps^8 F^(8). Step 4: the rows "
       "i = 0, 1 of eq. \"Psi1 iterates\", eq. \"M2\" and (w2 - w3) a1 + (w3 - w1) a2 + (w1 - w2) a3 = F have a unique "
       "solution, even in eps, so alpha_1, alpha_2, alpha_3 are integrals (Prop. \"prop: even\"). Step 2: it is the "
       "unique solution of the symmetric system i = -1, 0, 1, so F is the paper's F; alpha_j has the form of "
       "eq. \"bigint_form\" with the leading terms of eq. \"alpha123\".",
       claimed={"F": F_VIA_ABCD, "F_row": F_TEXT, "F_leading": "1",
                **{f"{u}_2": t for u, t in ALPHA123.items() if u[0] == "a"}}, uses=["dc-basis2", "dc345-abcd"])
def prove_alpha(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    abcd, b2 = require_proven(cert, "dc345-abcd"), require_proven(cert, "dc-basis2")
    delta = recall(b2, "Delta", r)
    with cert.step("Step 3: F is an integral, even in eps", "a rational function of the integrals A, B, C, D "
                   "(dc345-abcd) with coefficients in Q(w); exact parity", r) as s:
        F = named(f, claimed["F"], {k: recall(abcd, k, r) for k in "ABCD"})
        s.require(F.is_even_in(EPS), "F is not even in eps")
        s.note("F o f = F because A, B, C, D are integrals; the paper proved this by recipe (G), and checked the "
               "dependence of F on J, d7, d8 for numeric w only")
        record(cert, "F", F)
    with cert.step("Step 3: the form of F", "eps-coefficients of 2 eps^2 Delta F/(w2 - w3)", r) as s:
        w23 = named(f, "w2 - w3")
        pieces = homogeneous_eps_pieces(F * Frac(r, 2 * r.gen(EPS) ** 2) * delta / w23, EPS, X, 5, 0,
                                        "2 eps^2 Delta F/(w2 - w3)")
        s.require_equal(pieces[0], named(f, claimed["F_leading"]), "F^(0)")
    (frow,) = relation_rows(f, f"{claimed['F_row']} = 0")
    system, symmetric = part_two(f, abcd, [Relation(frow.coefficients, F + frow.rhs, "dc345-alpha, Step 3")])
    sol = _solve_block(cert, system, "a", {}, "")
    _symmetric_step(cert, symmetric, "a", sol, delta, claimed)


@claim("dc345-step5", GROUP, "Proof of Th. \"dC bases 345\", Step 5: beta_j and gamma_j, with eps and w symbolic",
       "sec. 6.7, proof of Th. \"dC bases 345\", Step 5; eqs. \"rel18_6\", \"bigint_form\", \"alpha123\"",
       "The rows i = 0, 1 of eq. \"Psi2 iterates\" (resp. \"Psi3 iterates\"), eq. \"M2\" and the first (resp. second) "
       "equality of eq. \"rel18_6\", with alpha (resp. beta) known, have a unique solution, even in eps: beta_j and "
       "gamma_j are integrals (Prop. \"prop: even\"); they solve the symmetric systems i = -1, 0, 1 and have the form "
       "of eq. \"bigint_form\" with the leading terms of eq. \"alpha123\".",
       claimed={"rel18_6": REL18["rel18_6"], **{f"{u}_2": t for u, t in ALPHA123.items() if u[0] != "a"}},
       uses=["dc-basis2", "dc345-abcd", "dc345-alpha"])
def prove_step5(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    abcd, b2, al = (require_proven(cert, k) for k in ("dc345-abcd", "dc-basis2", "dc345-alpha"))
    delta = recall(b2, "Delta", r)
    links = relation_rows(f, claimed["rel18_6"])
    if len(links) != 2:
        raise ParseError(f"eq. \"rel18_6\" must be a chain of three members, not {claimed['rel18_6']!r}")
    system, symmetric = part_two(f, abcd, links)
    known = {k: recall(al, UNKNOWNS[k], r) for k in BLOCK["a"]}
    for c, source in (("b", "dc345-alpha"), ("c", "dc345-step5 (beta)")):
        sol = _solve_block(cert, system, c, known, source)
        _symmetric_step(cert, symmetric, c, sol, delta, claimed)
        known.update(zip(BLOCK[c], sol, strict=True))


def kernel_vectors(cert: Certificate, r) -> dict[str, list[Frac]]:
    """The proven null-vectors of Phi0 ... Phi3 placed in R^10 (eq. after Th. "dClebsch 1dim bases")."""
    b1 = require_proven(cert, "dc-basis1-relations")
    al, b5 = require_proven(cert, "dc345-alpha"), require_proven(cert, "dc345-step5")
    zero, minus = Frac(r, 0), Frac(r, -1)
    out = {"Phi0": [recall(b1, f"c{k}", r) for k in (1, 2, 3)] + [zero] * 6 + [minus]}
    for k, c in enumerate("abc"):
        vec = [recall(al if c == "a" else b5, u, r) for u in _block(c)] + [zero] * 4
        vec[6 + k] = minus
        out[f"Phi{k + 1}"] = vec
    return out


@claim("dc345-max-basis", GROUP, "Th. \"dClebsch 1dim bases\" and Th. \"dClebsch max basis\": dim K_Phi = 4",
       "sec. 6.3, Th. \"dClebsch max basis\", Th. \"dClebsch 1dim bases\"; sec. 6.7, Th. \"dC bases 345\"",
       "Phi0, Phi1, Phi2, Phi3 are HK-bases with one-dimensional null-spaces spanned by the proven integral vectors "
       "(c_k; alpha_j; beta_j; gamma_j); placed in R^10 they are independent and span K_Phi, so dim K_Phi = `dim`: "
       "every orbit lies on an intersection of four quadrics.",
       claimed={"dim": "4"}, uses=["dc-basis1-relations", "dc-basis2", "dc-theta", "dc345-alpha", "dc345-step5"])
def prove_max_basis(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    vectors = kernel_vectors(cert, r)
    values, x = POINTS[0]
    point = {**dict(zip(X, x, strict=True)), **values}
    with cert.step("the null-vectors lie in K_Phi and are independent", "integrals satisfying the rows i = 0 (and "
                   "so every row i); exact rank at a rational point", r) as s:
        rank = rank_q([[v.evaluate(point) for v in vec] for vec in vectors.values()])
        s.require(str(rank) == claimed["dim"].strip(), f"the four proven null-vectors have rank {rank}")
        s.note("each vector has integral components and annihilates its basis on the rows i = 0, 1 (dc-basis1-"
               "relations, dc345-alpha, dc345-step5), hence on every row; rank 4 at one point: independent over "
               "Q(m, p, eps, w)")
    with cert.step("the null-vectors of Psi and Theta in this span", "exact identities: g_j = alpha_j + beta_j + "
                   "gamma_j and d7 alpha_j + d8 beta_j + d9 gamma_j = 1 (j <= 3), 0 (j >= 4)", r) as s:
        b2, th = require_proven(cert, "dc-basis2"), require_proven(cert, "dc-theta")
        d = [recall(b2, k, r) for k in ("d7", "d8", "d9")]
        for j in range(6):
            column = [vectors[name][j] for name in ("Phi1", "Phi2", "Phi3")]
            common = OverCommonDenominator.of(column)
            s.require(linear_combination_equals([Frac(r, 1)] * 3, column, recall(th, f"g{j + 1}", r), common),
                      f"g{j + 1} != alpha_{j + 1} + beta_{j + 1} + gamma_{j + 1}")
            s.require(linear_combination_equals(d, column, Frac(r, int(j < 3)), common),
                      f"(d7, d8, d9) misses the column {j + 1} of (M1 | M2)")
        s.note("Theta's vector = the sum of the Phi1, Phi2, Phi3 vectors; Psi's = -(d7, d8, d9) combination of them "
               "(the normalization (d7, d8, d9) M1 = (1, 1, 1) and (d7, d8, d9) M2 = 0 of the paper)")
    with cert.step("upper bounds: dim K_Phi <= 4, dim K_Phi_j <= 1", "exact kernel of the rows i = 0 ... 5 at a "
                   "rational point (a non-zero maximal minor)", r) as s:
        (full,) = phi_max_profiles(range(10), POINTS[:1])
        s.require(str(full.dims[5]) == claimed["dim"].strip(), f"dim ker X_[0,5] = {full.dims[5]} for Phi")
        for name, idx in (("Phi1", (0, 1, 2, 3, 4, 5, 6)), ("Phi2", (0, 1, 2, 3, 4, 5, 7)),
                          ("Phi3", (0, 1, 2, 3, 4, 5, 8))):
            (p,) = phi_max_profiles(idx, POINTS[:1])
            s.require(p.dims[5] == 1, f"dim ker X_[0,5] = {p.dims[5]} for {name}")
        s.note("a non-zero maximal minor at one point is a non-zero rational function: the bounds hold off a "
               "proper algebraic subset; with the lower bound, dim K_Phi = 4 = 1 + 1 + 1 + 1 and K_Phi is the sum "
               "of the four null-spaces")
