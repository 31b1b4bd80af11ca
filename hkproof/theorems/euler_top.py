"""Section 5: the Hirota-Kimura discretization of the Euler top, its HK-bases and integrals."""
from __future__ import annotations

from typing import Mapping

from hkproof.algebra.formula import cycled, indexed
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import rank_over_fraction_field
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import EPS
from hkproof.experiments.profiles import parse_basis
from hkproof.hk.independence import jacobian_rank_at, sample_point
from hkproof.hk.integrals import lie_derivative
from hkproof.hk.matrix_form import require_matrix_form
from hkproof.hk.reduced import prove_by_evenness
from hkproof.orchestration.registry import claim, proven, require_proven
from hkproof.proof.certificate import Certificate
from hkproof.theorems._common import parse, parse_matrix

__all__ = ["CYCLE", "DELTA", "GROUP", "PRODUCT", "prove_et_continuous", "prove_et_explicit", "prove_et_first",
           "prove_et_full", "prove_et_reversibility", "prove_et_second", "prove_et_symmetric", "X"]

GROUP = "euler-top"
X = ("x1", "x2", "x3")
CYCLE = {"x1": "x2", "x2": "x3", "x3": "x1", "a1": "a2", "a2": "a3", "a3": "a1"}
PRODUCT = "(x1 + eps*a1*x2*x3)*(x2 + eps*a2*x3*x1)*(x3 + eps*a3*x1*x2)"
DELTA = "1 - eps**2*(a2*a3*x1**2 + a3*a1*x2**2 + a1*a2*x3**2) - 2*eps**3*a1*a2*a3*x1*x2*x3"


@claim("et-continuous-integrals", GROUP, "Quadratic integrals of the Euler top",
       "sec. 5.1, eq. \"ET x\"",
       "gamma_1 x1^2 + gamma_2 x2^2 + gamma_3 x3^2 is an integral iff <gamma, alpha> = 0; H1, H2, H3 are integrals "
       "with a1 H1 + a2 H2 + a3 H3 = 0.",
       claimed={"H1": "a3*x2**2 - a2*x3**2", "H2": "a1*x3**2 - a3*x1**2", "H3": "a2*x1**2 - a1*x2**2",
                "relation": "a1*H1 + a2*H2 + a3*H3"})
def prove_et_continuous(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    field, r = f.field, f.ring
    with cert.step("condition on gamma", "Lie derivative along the flow", r) as s:
        g = r.extend(["g1", "g2", "g3"])
        field_g = Frac.parse(g, "g1*x1**2 + g2*x2**2 + g3*x3**2")
        rhs = [fc.to_ring(g) for fc in field.rhs]
        deriv = sum((field_g.derivative(v) * fc for v, fc in zip(X, rhs, strict=True)), Frac(g, 0))
        expected = Frac.parse(g, "2*(g1*a1 + g2*a2 + g3*a3)*x1*x2*x3")
        s.require_equal(deriv, expected, "dH/dt")
        s.note("dH/dt = 2 <gamma, alpha> x1 x2 x3")
        cert.correction("sec. 5.1 prints <gamma, alpha> = gamma1 alpha1 + gamma2 alpha2 + gamma2 alpha2; the last "
                        "term must be gamma3 alpha3 (dH/dt = 2(gamma1 alpha1 + gamma2 alpha2 + gamma3 alpha3) x1 x2 x3).")
    with cert.step("H1, H2, H3 are integrals; a1 H1 + a2 H2 + a3 H3 = 0", "Lie derivative; expansion", r) as s:
        hs = {k: parse(f, claimed[k]) for k in ("H1", "H2", "H3")}
        for k, h in hs.items():
            s.require(lie_derivative(field, h).is_zero(), f"{k} is not an integral of the Euler top")
        rel = Frac.parse(r, claimed["relation"], hs)
        s.require(rel.is_zero(), f"{claimed['relation']} = {rel}, not 0")


@claim("et-explicit-map", GROUP, "Explicit HK map of the Euler top and its denominator",
       "sec. 5.2, eqs. \"dET x\", \"dET map\", \"dET expl\"",
       "The map is x~ = A(x, eps)^-1 x with the printed A, given explicitly by the printed formulas with "
       "Delta = det A.",
       claimed={
           "A": "[[1, -eps*a1*x3, -eps*a1*x2], [-eps*a2*x3, 1, -eps*a2*x1], [-eps*a3*x2, -eps*a3*x1, 1]]",
           "x1_tilde": f"(x1 + 2*eps*a1*x2*x3 + eps**2*x1*(-a2*a3*x1**2 + a3*a1*x2**2 + a1*a2*x3**2))/({DELTA})",
           "x2_tilde": f"(x2 + 2*eps*a2*x3*x1 + eps**2*x2*(a2*a3*x1**2 - a3*a1*x2**2 + a1*a2*x3**2))/({DELTA})",
           "x3_tilde": f"(x3 + 2*eps*a3*x1*x2 + eps**2*x3*(a2*a3*x1**2 + a3*a1*x2**2 - a1*a2*x3**2))/({DELTA})",
           "Delta": DELTA,
       })
def prove_et_explicit(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    r = f.ring
    with cert.step("matrix form A x~ = x", "coefficients of x~ in E(x, x~, eps)", r) as s:
        require_matrix_form(s, f, parse_matrix(f, claimed["A"]))
    with cert.step("explicit map and Delta = det A", "Cramer's rule, gcd cancelled", r) as s:
        s.require_equal(Frac(r, f.denominator), parse(f, claimed["Delta"]), "Delta")
        for v, comp in zip(X, f.components(), strict=True):
            s.require_equal(comp, parse(f, claimed[f"{v}_tilde"]), f"{v}~")
            cert.formula(f"{v}_tilde", comp)
        cert.formula("Delta", Frac(r, f.denominator))


@claim("et-reversibility", GROUP, "Reversibility of the Euler top map", "sec. 5.2, f^-1(x, eps) = f(x, -eps)",
       "f(f(x, eps), -eps) = x identically.")
def prove_et_reversibility(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    r = f.ring
    with cert.step("E(x~, x, -eps) = -E(x, x~, eps)", "symmetry of the Kahan equations", f.field.tilde_ring) as s:
        s.require(f.equations_reversible(), "the equations are not symmetric under x <-> x~, eps -> -eps")
    with cert.step("f(., -eps) o f(., eps) = id", "composition by homogenized compose", r) as s:
        nums, delta = f.explicit
        inv_nums, inv_delta = f.inverse_explicit
        for k, v in enumerate(X):
            inverse_component = Frac(r, inv_nums[k], inv_delta)
            s.require_equal(inverse_component.pullback(nums, delta, X), Frac(r, r.gen(v)), f"{v} after f then f(-eps)")


@claim("et-first-hk-basis", GROUP, "Prop. \"dET first HK basis\": Phi0 = (x1^2, x2^2, x3^2), integrals c1, c2",
       "sec. 5.3, Prop. \"dET first HK basis\", eqs. \"dET c1 c2\", \"dET for cancel\"",
       "Solving (c1 x1^2 + c2 x2^2) o f^i = x3^2 o f^i, i = 0, 1 gives the printed c1, c2; they are eps-free, hence "
       "integrals by recipe (D); the 2x2 determinants factor as in eq. \"dET for cancel\"; a1 c1 + a2 c2 = a3.",
       claimed={
           "c1": "(a3*x2**2 - a2*x3**2)/(a1*x2**2 - a2*x1**2)",
           "c2": "(a1*x3**2 - a3*x1**2)/(a1*x2**2 - a2*x1**2)",
           "kernel": "[a3*x2**2 - a2*x3**2, a1*x3**2 - a3*x1**2, a2*x1**2 - a1*x2**2]",
           "det_factorization": f"4*eps*(a_j*x_i**2 - a_i*x_j**2)*{PRODUCT}/Delta**2",
           "relation": "a1*c1 + a2*c2 - a3",
       })
def prove_et_first(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    r = f.ring
    basis = parse_basis(r, "x1**2, x2**2")
    c1, c2 = prove_by_evenness(cert, f, basis, parse(f, "x3**2"), ("c1", "c2"))
    with cert.step("solution is eps-free and equals the printed c1, c2", "exact comparison", r) as s:
        s.require(EPS not in c1.variables() | c2.variables(), "the solution depends on eps")
        s.require_equal(c1, parse(f, claimed["c1"]), "c1")
        s.require_equal(c2, parse(f, claimed["c2"]), "c2")
        kernel = parse_matrix(f, "[" + claimed["kernel"] + "]")[0]
        s.require(rank_over_fraction_field([[c1, c2, Frac(r, -1)], kernel]) == 1,
                  "the printed kernel vector is not proportional to (c1, c2, -1)")
    with cert.step("c1, c2 are integrals (direct check)", "substitution c o f - c", r) as s:
        s.require((f.pullback(c1) - c1).is_zero() and (f.pullback(c2) - c2).is_zero(), "c o f != c")
        s.note("confirms recipe (D) independently")
    with cert.step("determinant factorization, eq. \"dET for cancel\"", "exact expansion for all pairs (i, j)", r) as s:
        delta = Frac(r, f.denominator)
        for i, j in ((1, 2), (2, 3), (1, 3)):
            xi, xj = parse(f, f"x{i}**2"), parse(f, f"x{j}**2")
            d = xi * f.pullback(xj) - xj * f.pullback(xi)
            text = indexed(claimed["det_factorization"], i=i, j=j)
            s.require_equal(d, Frac.parse(r, text, {"Delta": parse(f, DELTA)}), f"det for (i, j) = ({i}, {j})")
        s.note(f"Delta = {delta}")
    with cert.step("linear relation a1 c1 + a2 c2 = a3", "exact", r) as s:
        s.require(Frac.parse(r, claimed["relation"], {"c1": c1, "c2": c2}).is_zero(),
                  f"{claimed['relation']} is not 0")


@claim("et-second-hk-basis", GROUP, "Prop. \"dET second HK basis\": Phi1 = (x1^2, x2^2, 1), integrals d1, d2",
       "sec. 5.3, Prop. \"dET second HK basis\", eq. \"dET c4 c5\"",
       "Solving (d1 x1^2 + d2 x2^2) o f^i = 1, i = 0, 1 gives the printed d1, d2; they are even in eps, hence "
       "integrals; the printed determinant |1 x_i^2; 1 x~_i^2| holds; a1 d1 + a2 d2 = eps^2 a1 a2 a3; d1 is "
       "functionally independent of c1.",
       claimed={
           "d1": "a2*(1 - eps**2*a3*a1*x2**2)/(a2*x1**2 - a1*x2**2)",
           "d2": "a1*(1 - eps**2*a2*a3*x1**2)/(a1*x2**2 - a2*x1**2)",
           "det_factorization": f"4*eps*a_i*(1 - eps**2*a_j*a_k*x_i**2)*{PRODUCT}/Delta**2",
           "relation": "a1*d1 + a2*d2 - eps**2*a1*a2*a3",
       }, uses=["et-first-hk-basis"])
def prove_et_second(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    r = f.ring
    d1, d2 = prove_by_evenness(cert, f, parse_basis(r, "x1**2, x2**2"), Frac(r, 1), ("d1", "d2"))
    with cert.step("solution equals the printed d1, d2", "exact comparison", r) as s:
        s.require_equal(d1, parse(f, claimed["d1"]), "d1")
        s.require_equal(d2, parse(f, claimed["d2"]), "d2")
    with cert.step("determinant |1 x_i^2; 1 x~_i^2|", "exact expansion for i = 1, 2, 3", r) as s:
        for i, j, k in ((1, 2, 3), (2, 3, 1), (3, 1, 2)):
            xi = parse(f, f"x{i}**2")
            d = f.pullback(xi) - xi
            text = indexed(claimed["det_factorization"], i=i, j=j, k=k)
            s.require_equal(d, Frac.parse(r, text, {"Delta": parse(f, DELTA)}), f"det for i = {i}")
    with cert.step("linear relation a1 d1 + a2 d2 = eps^2 a1 a2 a3", "exact", r) as s:
        s.require(Frac.parse(r, claimed["relation"], {"d1": d1, "d2": d2}).is_zero(),
                  f"{claimed['relation']} is not 0")
    c1 = Frac.parse(r, proven("et-first-hk-basis").formulas["c1"])
    point = sample_point(r.names)
    with cert.step("d1 independent of c1", "exact Jacobian rank at a rational point", r) as s:
        rank = jacobian_rank_at([c1, d1], X, point)
        s.require(rank == 2, f"Jacobian of (c1, d1) has rank {rank} at {point}")
        s.note("rank 2 at one point, so the 2x2 minors are non-zero rational functions: independent over "
               "Q(eps, a1, a2, a3)")


@claim("et-symmetric-bases", GROUP, "Phi2 = (x2^2, x3^2, 1) and Phi3 = (x1^2, x3^2, 1) are HK-bases",
       "sec. 5.3, remark after Prop. \"dET second HK basis\"",
       "By the cyclic symmetry of the system, the reduced systems for Phi2 and Phi3 have even solutions, the "
       "cyclic images of d1, d2, hence integrals and 1-dimensional null-spaces.",
       claimed={"d1": "a2*(1 - eps**2*a3*a1*x2**2)/(a2*x1**2 - a1*x2**2)",
                "d2": "a1*(1 - eps**2*a2*a3*x1**2)/(a1*x2**2 - a2*x1**2)"})
def prove_et_symmetric(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    for shift, pair, label in ((1, ("x2", "x3"), "Phi2"), (2, ("x3", "x1"), "Phi3")):
        names = (f"{label}_{pair[0]}", f"{label}_{pair[1]}")
        sol = prove_by_evenness(cert, f, parse_basis(f.ring, [f"{v}**2" for v in pair]), Frac(f.ring, 1), names)
        with cert.step(f"{label}: solution is the cyclic image of (d1, d2)", "exact comparison", f.ring) as s:
            for got, key in zip(sol, ("d1", "d2"), strict=True):
                s.require_equal(got, parse(f, cycled(claimed[key], CYCLE, shift)), f"{label} coefficient")


@claim("et-full-basis", GROUP, "Th. \"dET full basis\": Phi = (x1^2, x2^2, x3^2, 1) has dim K = 2",
       "sec. 5.3, Th. \"dET full basis\"",
       "The 1-dimensional null-spaces of Phi1, Phi2 lie in K_Phi and are independent, and rank X_[0,1] = 2, so "
       "dim K_Phi = 2 (generic x); K_Phi0 lies in K_Phi1 + K_Phi2; any two of the four null-spaces span K_Phi.",
       claimed={"dimension": "2"}, uses=["et-first-hk-basis", "et-second-hk-basis", "et-symmetric-bases"])
def prove_et_full(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    r = f.ring
    first = require_proven(cert, "et-first-hk-basis")
    second = require_proven(cert, "et-second-hk-basis")
    sym = require_proven(cert, "et-symmetric-bases")
    g = {k: Frac.parse(r, v) for k, v in {**first.formulas, **second.formulas, **sym.formulas}.items()}
    zero, minus = Frac(r, 0), Frac(r, -1)
    # null vectors in coordinates (x1^2, x2^2, x3^2, 1)
    k0 = [g["c1"], g["c2"], minus, zero]
    k1 = [g["d1"], g["d2"], zero, minus]
    k2 = [zero, g["Phi2_x2"], g["Phi2_x3"], minus]
    k3 = [g["Phi3_x1"], zero, g["Phi3_x3"], minus]
    with cert.step("upper bound: rank X_[0,1] = 2", "exact 2x2 minor of X_[0,1] is non-zero", r) as s:
        phis = parse_basis(r, "x1**2, x2**2, x3**2, 1")
        rows = [phis, [f.pullback(p) for p in phis]]
        s.require(rank_over_fraction_field(rows) == 2, "X_[0,1] does not have rank 2")
        s.note("K_Phi(x) lies in ker X_[0,1](x), of dimension 4 - 2 = 2")
    with cert.step("lower bound and spans", "exact ranks over Q(x, eps, a)", r) as s:
        vectors = {"K_Phi0": k0, "K_Phi1": k1, "K_Phi2": k2, "K_Phi3": k3}
        names = list(vectors)
        for a in range(4):
            for b in range(a + 1, 4):
                rank = rank_over_fraction_field([vectors[names[a]], vectors[names[b]]])
                s.require(rank == 2, f"{names[a]} and {names[b]} are not independent")
        s.require(rank_over_fraction_field(list(vectors.values())) == 2, "the four null-spaces span more than 2")
        s.require(parse(f, claimed["dimension"]) == 2, f"claimed dimension {claimed['dimension']}, found 2")
        s.note("any two of the four 1-dimensional null-spaces are independent and all four span a 2-dimensional "
               "space; with the upper bound, dim K_Phi = 2 and K_Phi0 lies in K_Phi1 + K_Phi2")
