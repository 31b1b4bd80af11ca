"""Section 6.1-6.2: the Clebsch system, its integrals, and its Hirota-Kimura map (eqs. "dC", "dC map", "dC reverse")."""
from __future__ import annotations

from typing import Mapping

from hkproof.algebra.fraction import Frac, homogenized_compose
from hkproof.algebra.linalg import det
from hkproof.checker import DET_DF
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import EPS
from hkproof.hk.expansion import support_stats, weighted_degrees
from hkproof.hk.independence import jacobian_rank_at, sample_point
from hkproof.hk.integrals import lie_derivative
from hkproof.hk.jacobian import matrix_identity_holds
from hkproof.hk.matrix_form import require_matrix_form
from hkproof.hk.nambu import prove_nambu, require_claimed
from hkproof.orchestration.registry import claim, require_proven
from hkproof.pipelines.darboux import search_darboux
from hkproof.pipelines.discover import discover
from hkproof.proof.certificate import Certificate
from hkproof.proof.export import darboux_step
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import SYSTEM, H, X, cycled, named, number, recall, shift
from hkproof.theorems._common import nambu_checks, parse, parse_matrix

__all__ = ["GROUP", "MATRIX", "prove_complexity", "prove_continuous", "prove_equations", "prove_explicit",
           "prove_invariant_measures", "prove_nambu_poisson", "prove_reversibility", "prove_symmetries", "TILDE_EQUATIONS"]

GROUP = "clebsch-map"
TILDE_EQUATIONS = {
    "m1": "m1_t - m1 - eps*(w3 - w2)*(p2_t*p3 + p2*p3_t)",
    "m2": "m2_t - m2 - eps*(w1 - w3)*(p3_t*p1 + p3*p1_t)",
    "m3": "m3_t - m3 - eps*(w2 - w1)*(p1_t*p2 + p1*p2_t)",
    "p1": "p1_t - p1 - eps*(m3_t*p2 + m3*p2_t) + eps*(m2_t*p3 + m2*p3_t)",
    "p2": "p2_t - p2 - eps*(m1_t*p3 + m1*p3_t) + eps*(m3_t*p1 + m3*p1_t)",
    "p3": "p3_t - p3 - eps*(m2_t*p1 + m2*p1_t) + eps*(m1_t*p2 + m1*p2_t)",
}
MATRIX = ("[[1, 0, 0, 0, eps*(w2 - w3)*p3, eps*(w2 - w3)*p2],"
          " [0, 1, 0, eps*(w3 - w1)*p3, 0, eps*(w3 - w1)*p1],"
          " [0, 0, 1, eps*(w1 - w2)*p2, eps*(w1 - w2)*p1, 0],"
          " [0, eps*p3, -eps*p2, 1, -eps*m3, eps*m2],"
          " [-eps*p3, 0, eps*p1, eps*m3, 1, -eps*m1],"
          " [eps*p2, -eps*p1, 0, -eps*m2, eps*m1, 1]]")


@claim("dc-continuous-integrals", GROUP, "Integrals H1..H4 and I1..I3 of the Clebsch system",
       "sec. 6.1, eqs. \"Clebsch H1\", \"Clebsch H2\", \"Clebsch C1\", \"Clebsch C2\", \"Clebsch I\"",
       "The Clebsch flow m' = p x Omega p, p' = p x m has the four functionally independent integrals H1..H4; "
       "I1, I2, I3 span the same space as H1, H2, H3, with H1 = w1 I1 + w2 I2 + w3 I3, "
       "H2 = -w2 w3 I1 - w3 w1 I2 - w1 w2 I3 (printed with left-hand side H1) and H3 = I1 + I2 + I3.",
       claimed={
           "rhs": "[(w3 - w2)*p2*p3, (w1 - w3)*p3*p1, (w2 - w1)*p1*p2, m3*p2 - m2*p3, m1*p3 - m3*p1, m2*p1 - m1*p2]",
           **H,
           "combination_1": "H1 = w1*I1 + w2*I2 + w3*I3",
           "combination_2": "H1 = -w2*w3*I1 - w3*w1*I2 - w1*w2*I3",
           "combination_3": "H3 = I1 + I2 + I3",
           "change_of_basis_det": "(w1 - w2)*(w2 - w3)*(w1 - w3)",
       })
def prove_continuous(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    field, r = f.field, f.ring
    with cert.step("the catalogue system is the printed Clebsch flow", "exact comparison of right-hand sides", r) as s:
        for v, got, want in zip(X, field.rhs, parse_matrix(f, "[" + claimed["rhs"] + "]")[0], strict=True):
            s.require_equal(got, want, f"{v}'")
    hs = {k: named(f, claimed[k]) for k in H}
    with cert.step("H1, H2, H3, H4 are quadratic integrals", "Lie derivative along the flow is 0; degrees", r) as s:
        for k, h in hs.items():
            quadratic = h.is_polynomial() and weighted_degrees(r, h.num, {v: 1 for v in X}) == {2}
            s.require(quadratic, f"{k} = {h} is not a quadratic form")
            s.require(lie_derivative(field, h).is_zero(), f"{k} = {h} is not an integral of the Clebsch flow")
    with cert.step("H1..H4 functionally independent", "exact Jacobian rank 4 at a rational point", r) as s:
        rank = jacobian_rank_at(list(hs.values()), X, sample_point(r.names))
        s.require(rank == 4, f"Jacobian of H1..H4 has rank {rank}")
        s.note("a non-zero 4x4 minor at one point is a non-zero rational function of (m, p, w)")
    with cert.step("printed identities between H and I", "exact identity in Q(m, p, w)", r) as s:
        for key in ("combination_1", "combination_2", "combination_3"):
            lhs, rhs = (t.strip() for t in claimed[key].split("="))
            value = named(f, rhs, {k: claimed[k] for k in H})
            matches = [k for k, h in hs.items() if value == h]
            s.require(bool(matches), f"{claimed[key]}: the right-hand side is none of H1..H4 ({value})")
            if lhs not in matches:
                cert.correction(f"sec. 6.1 prints '{claimed[key]}'; the right-hand side equals {matches[0]}, "
                                f"not {lhs}: the identity is {matches[0]} = {rhs}.")
            s.note(f"{matches[0]} = {rhs}")
    with cert.step("span(H1, H2, H3) = span(I1, I2, I3)", "determinant of the change of basis over Q(w)", r) as s:
        change = parse_matrix(f, "[[w1, w2, w3], [-w2*w3, -w3*w1, -w1*w2], [1, 1, 1]]")
        d = det([[e.num for e in row] for row in change])
        s.require_equal(Frac(r, d), parse(f, claimed["change_of_basis_det"]), "det of the change of basis")
        s.note(f"det = {claimed['change_of_basis_det']}, non-zero for distinct w_k")


@claim("dc-map-equations", GROUP, "Discrete Clebsch equations and their matrix form",
       "sec. 6.2, eq. \"dC\" and the matrix M(m, p, eps)",
       "Kahan's discretization of the Clebsch flow is the printed system eq. \"dC\", linear in (m~, p~), "
       "M(m, p, eps) (m~, p~) = (m, p) with the printed M (w_ij = w_i - w_j).",
       claimed={**{f"eq_{v}": e for v, e in TILDE_EQUATIONS.items()}, "M": MATRIX})
def prove_equations(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    t, r = f.field.tilde_ring, f.ring
    with cert.step("Kahan equations = eq. \"dC\"", "exact comparison in Z[m, p, m~, p~, eps, w]", t) as s:
        for v, e in zip(X, f.equations, strict=True):
            s.require_equal(Frac(t, e), Frac.parse(t, claimed[f"eq_{v}"]), f"equation for {v}~")
    with cert.step("matrix form M (m~, p~) = (m, p)", "coefficients of (m~, p~) in eq. \"dC\"", r) as s:
        require_matrix_form(s, f, parse_matrix(f, claimed["M"]))


@claim("dc-explicit-map", GROUP, "The discrete Clebsch map f = M^-1 (m, p) and its denominator",
       "sec. 6.2, eq. \"dC map\"",
       "f = N/Delta with Delta = det M(m, p, eps) and N the Cramer numerators, with no common factor; "
       "each component N_i/Delta is in lowest terms; f solves eq. \"dC\"; Delta(m, p, 0) = 1 and f(m, p, 0) = (m, p).")
def prove_explicit(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    nums, delta = f.explicit
    m, _ = f.matrix
    with cert.step("Delta = det M, no common factor cancelled", "fraction-free determinant; gcd", r) as s:
        d = det(m)
        s.require(d == delta, "the common denominator is not det M")
        g = delta
        for p in nums:
            g = g.gcd(p)
        s.require(g.is_one(), f"N and Delta have the common factor {g}")
        s.require(all(p.gcd(delta).is_one() for p in nums), "a component N_i/Delta is not in lowest terms")
        s.note("each component N_i/Delta is in lowest terms, so Delta is the common denominator of every component")
    with cert.step("f solves the equations: M N = Delta (m, p)", "exact polynomial identity", r) as s:
        for i, v in enumerate(X):
            row = sum((m[i][j] * nums[j] for j in range(6)), r.constant(0))
            s.require(row == delta * r.gen(v), f"row {i + 1} of M N differs from Delta {v}")
    with cert.step("Delta(m, p, 0) = 1, f(m, p, 0) = (m, p)", "substitution eps = 0", r) as s:
        s.require(delta.subs({EPS: 0}) == 1, "Delta(m, p, 0) != 1")
        s.require(all(p.subs({EPS: 0}) == r.gen(v) for p, v in zip(nums, X, strict=True)), "N(m, p, 0) != (m, p)")
    cert.formula("Delta_f", Frac(r, delta))
    for v, p in zip(X, nums, strict=True):
        cert.formula(f"N_{v}", Frac(r, p))


@claim("dc-map-symmetries", GROUP, "Symmetries of the discrete Clebsch map (used to shorten the f^2 computation)",
       "sec. 6.2 (structure of eq. \"dC map\")",
       "f commutes with the cyclic shift of indices (m1, m2, m3, p1, p2, p3, w1, w2, w3) -> (m2, m3, m1, ...); "
       "Delta and N are weighted homogeneous: invariant under (m, p, eps) -> (l m, l p, eps/l) up to the factor l "
       "on N, and under (m, w, eps) -> (l m, l^2 w, eps/l).")
def prove_symmetries(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    nums, delta = f.explicit
    with cert.step("cyclic equivariance", "exact: N_{s(i)}(s x) = s(N_i(x)), Delta(s x) = s(Delta(x))", r) as s:
        s.require(shift(r, delta) == delta, "Delta is not invariant under the cyclic shift")
        for k, v in enumerate(X):
            s.require(shift(r, nums[k]) == nums[X.index(cycled(v))], f"N_{v} after the cyclic shift")
    with cert.step("weighted homogeneity", "weighted degrees of every term", r) as s:
        w1 = {**{v: 1 for v in X}, EPS: -1}
        w2 = {"m1": 1, "m2": 1, "m3": 1, "w1": 2, "w2": 2, "w3": 2, EPS: -1}
        for p, name in [(delta, "Delta")] + [(n, f"N_{v}") for n, v in zip(nums, X, strict=True)]:
            wants = (0 if p is delta else 1, 0 if p is delta or name.startswith("N_p") else 1)
            for weights, want in zip((w1, w2), wants, strict=True):
                got = weighted_degrees(r, p, weights)
                s.require(got == {want}, f"{name} has weighted degrees {got} for {weights}, expected {{{want}}}")
        s.note("Delta has weight 0 and N_i weight 1 for (m, p, eps) ~ (1, 1, -1); for (m, w, eps) ~ (1, 2, -1) "
               "Delta and N_p have weight 0, N_m weight 1")


@claim("dc-reversibility", GROUP, "Reversibility of the discrete Clebsch map", "sec. 6.2, eq. \"dC reverse\"",
       "f^-1(m, p, eps) = f(m, p, -eps): with x~ = f(x, eps), M(x~, -eps) x = x~, so f(x~, -eps) = x.")
def prove_reversibility(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    nums, delta = f.explicit
    with cert.step("Delta M(N/Delta, -eps) (m, p) = N", "exact polynomial identity (entries of M are affine in x)",
                   r) as s:
        m, _ = f.matrix
        for i, v in enumerate(X):
            row = r.constant(0)
            for j, w in enumerate(X):
                entry, d = homogenized_compose(r, f.negate_eps(m[i][j]), X, nums, delta)
                row += entry * delta ** (1 - d) * r.gen(w)
            s.require(row == nums[i], f"row {i + 1}: Delta M(x~, -eps) x != Delta x~")
        s.note("M(x~, -eps) x = x~, and det M(x~, -eps) = Delta(x~, -eps) is not identically 0 (it is 1 at eps = 0, "
               "where x~ = x), so x = M(x~, -eps)^-1 x~ = f(x~, -eps); with eps -> -eps also f(f(x, -eps), eps) = x")


@claim("dc-complexity", GROUP, "Complexity remark: sizes of the numerators and the denominator of f",
       "sec. 6.2, remark after eq. \"dC reverse\"",
       "As polynomials in (m, p): the numerators of m~_k have total degree 6 and 41 monomials, the numerators of "
       "p~_k total degree 5 and 31 monomials, the common denominator Delta total degree 5 and 28 monomials. "
       "The paper says 'total degree 6' for all of them, which holds only for the m~ numerators "
       "(6 is the maximum).",
       claimed={"deg_m_numerators": "6", "deg_p_numerators": "5", "deg_denominator": "5",
                "monomials_m_numerators": "41", "monomials_p_numerators": "31", "monomials_denominator": "28",
                "printed_total_degree": "6"})
def prove_complexity(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    nums, delta = f.explicit
    stats = {"m": [support_stats(r, p, X) for p in nums[:3]], "p": [support_stats(r, p, X) for p in nums[3:]],
             "denominator": [support_stats(r, delta, X)]}
    with cert.step("degrees and numbers of monomials in (m, p)", "support of N and Delta", r) as s:
        for key, label in (("m", "m_numerators"), ("p", "p_numerators"), ("denominator", "denominator")):
            for st in stats[key]:
                s.require(st["degree"] == number(claimed[f"deg_{label}"]),
                          f"{label}: total degree {st['degree']}, claimed {claimed[f'deg_{label}']}")
                s.require(st["monomials"] == number(claimed[f"monomials_{label}"]),
                          f"{label}: {st['monomials']} monomials, claimed {claimed[f'monomials_{label}']}")
            s.note(f"{label}: degree {stats[key][0]['degree']}, {stats[key][0]['monomials']} monomials in (m, p), "
                   f"{stats[key][0]['terms']} terms in (m, p, eps, w)")
        top = max(st["degree"] for group in stats.values() for st in group)
        s.require(top == number(claimed["printed_total_degree"]),
                  f"the largest total degree is {top}, not {claimed['printed_total_degree']}")
        low = [k for k, g in stats.items() if g[0]["degree"] != top]
        if low:
            cert.correction(f"sec. 6.2 says every numerator and the denominator of f have total degree {top} in "
                            f"(m, p); only the m~ numerators do: the p~ numerators and the common denominator "
                            f"Delta have total degree {stats['p'][0]['degree']} (e.g. the eps^5 terms "
                            "m1 p2^3 p3 of Delta). The monomial counts 41, 31, 28 are right.")


@claim("dc-invariant-measures", GROUP, "Invariant measures of the discrete Clebsch map (beyond the paper)",
       "sec. 7 names invariant measures of the discrete Clebsch system as unknown; docs/geometry.md, "
       "`hkproof measure clebsch --degree 6`",
       "The Darboux polynomials P of degree <= 6 in (m, p) with cofactor det Df (P o f = det Df P) found mod p are "
       "two, P1 and P2; with eps and w symbolic both satisfy P o f = det Df P exactly, so dm dp / P1 and dm dp / P2 "
       "are invariant measures of the discrete Clebsch map and P2 / P1 is an integral.",
       claimed={"degree": "6", "densities": "2"}, slow=True)
def prove_invariant_measures(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    with cert.step("det Df = det M(f(x), -eps) / det M(x, eps)", "the matrix identity M(x, eps) Df(x) = "
                   "M(f(x), -eps) from the bilinear Kahan equations, exact", r) as s:
        s.require(matrix_identity_holds(f), "M(x, eps) Df(x) != M(f(x), -eps)")
    degree = int(claimed["degree"])
    with cert.step(f"the Darboux polynomials of degree <= {degree} with cofactor det Df",
                   "kernels mod p at random eps, w; coefficients rebuilt from kernels mod primes (docs/geometry.md); "
                   "P(N/Delta) = det Df P exactly, det M(x, -eps) o f composed unexpanded, on the slice w3 = 0 of the "
                   "translation w -> w + c and lifted (each P's certificate checks the invariance)", r) as s:
        found = search_darboux(f, degree)
        s.require(found.complete and not found.unverified, "the search did not reconstruct and prove every "
                  f"Darboux polynomial it found mod p: {found.unverified or found.stopped}")
        dens = [d for d in found.darboux if d.cofactor == found.jacobian]
        s.require(all(d.status is Status.VERIFIED for d in dens), "a Darboux polynomial is not verified")
        s.require(str(len(dens)) == claimed["densities"].strip(),
                  f"{len(dens)} Darboux polynomials with cofactor det Df, the claim says {claimed['densities']}")
        polys = [Frac(r, d.poly) for d in dens]
        s.note(", ".join(f"P{k + 1}: {len(p.num)} terms, degree {max(weighted_degrees(r, p.num, dict.fromkeys(X, 1)))} "
                         "in (m, p)" for k, p in enumerate(polys)))
    for k, p in enumerate(polys):
        cert.formula(f"P{k + 1}", p)
    ratios = [(f"I{k}", p / polys[0], f"(P{k + 1})/(P1)") for k, p in enumerate(polys[1:], start=1)]
    for name, value, _ in ratios:
        cert.formula(name, value)
    cert.checks.append(darboux_step(f.field, [f"P{k + 1}" for k in range(len(polys))], polys, DET_DF, ratios,
                                    [(f"rho{k + 1}", 1 / p, f"1/(P{k + 1})") for k, p in enumerate(polys)]))


@claim("dc-nambu-poisson", GROUP, "An invariant Poisson structure of the discrete Clebsch map (rank 2, beyond the paper)",
       "sec. 7 names invariant Poisson structures of the discrete Clebsch system as unknown; issue 38; docs/clebsch.md, "
       "docs/poisson.md (Nambu structures); Byrnes-Haggar-Quispel 1999",
       "With the four functionally independent integrals I1..I4 that `discover clebsch` proves and the invariant "
       "density 1/P1 of dc-invariant-measures, Pi = P1 W(grad I1, ..., grad I4) (W the dual of dI1 ^ ... ^ dI4 "
       "against dm dp) is an invariant Poisson structure of the discrete Clebsch map, eps and w symbolic, of rank 2 "
       "with the Casimirs I1..I4. It does not make the map Liouville-Arnold integrable: that needs a fifth "
       "independent integral (rank 2) or a structure of rank 4",
       claimed={"rank": "2", "casimirs": "4"}, slow=True, uses=["dc-invariant-measures"])
def prove_nambu_poisson(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    measures = require_proven(cert, "dc-invariant-measures")
    density = recall(measures, "P1", f.ring)
    with cert.step("the integrals of discover", "discover clebsch at degree 2: kernels mod p, sparse reconstruction "
                   "with eps and w symbolic, I o f = I by exact substitution", f.ring) as s:
        report = discover(f.field, 2)
        found = [(i.name, i.frac, i.status) for i in report.integrals if i.frac is not None]
        s.require(all(st.is_verified for _, _, st in found), "an integral of discover is not verified")
        s.note(", ".join(f"{name}: {len(h.num)} + {len(h.den)} terms" for name, h, _ in found))
    for name, h, _ in found:
        cert.formula(name, h)
    structure = prove_nambu(f, found, ("P1", density.num, Status.VERIFIED), cert=cert)
    require_claimed(cert, f.ring, structure, claimed)
    cert.checks += nambu_checks(f, report, structure)
