"""Section 2: Kahan's discretization of the Lotka-Volterra system (eqs. "Kahan LV", "Kahan LV explicit")."""
from __future__ import annotations

from typing import Mapping

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.hk.matrix_form import require_matrix_form
from hkproof.orchestration.registry import claim
from hkproof.proof.certificate import Certificate
from hkproof.theorems._common import parse, parse_matrix

__all__ = ["GROUP", "prove_lv_explicit", "prove_lv_poisson"]

GROUP = "lotka-volterra"


@claim("lv-explicit-map", GROUP, "Explicit Kahan map of the Lotka-Volterra system",
       "sec. 2, eqs. \"Kahan LV\", \"Kahan LV explicit\"",
       "The Kahan equations are M(x, y, eps) (x~, y~) = b with the printed M and b, and their solution is the "
       "printed rational map.",
       claimed={
           "M": "[[1 - eps + eps*y, eps*x], [-eps*y, 1 + eps - eps*x]]",
           "b": "[[(1 + eps)*x], [(1 - eps)*y]]",
           "x_tilde": "x*((1+eps)**2 - eps*(1+eps)*x - eps*(1-eps)*y)/(1 - eps**2 - eps*(1-eps)*x + eps*(1+eps)*y)",
           "y_tilde": "y*((1-eps)**2 + eps*(1+eps)*x + eps*(1-eps)*y)/(1 - eps**2 - eps*(1-eps)*x + eps*(1+eps)*y)",
       })
def prove_lv_explicit(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    r = f.ring
    with cert.step("matrix form of the Kahan equations", "coefficients of x~ in E(x, x~, eps)", r) as s:
        require_matrix_form(s, f, parse_matrix(f, claimed["M"]), [row[0] for row in parse_matrix(f, claimed["b"])])
    with cert.step("explicit map", "Cramer's rule, gcd cancelled", r) as s:
        for name, comp in zip(("x_tilde", "y_tilde"), f.components(), strict=True):
            s.require_equal(comp, parse(f, claimed[name]), name)
            cert.formula(name, comp)
        cert.formula("Delta", Frac(r, f.denominator))


@claim("lv-poisson", GROUP, "The Kahan Lotka-Volterra map is Poisson for {x, y} = xy",
       "sec. 2, eq. \"LV PB\"",
       "The map preserves the bracket {x, y} = B(x, y) with B = xy: det(df) * B(x, y) = B(x~, y~).",
       claimed={"bracket": "x*y"})
def prove_lv_poisson(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(GROUP)
    r = f.ring
    with cert.step("Poisson property", "exact Jacobian determinant of f times B, against B o f", r) as s:
        xt, yt = f.components()
        jac = xt.derivative("x") * yt.derivative("y") - xt.derivative("y") * yt.derivative("x")
        bracket = parse(f, claimed["bracket"])
        s.require_equal(jac * bracket, f.pullback(bracket), "{x~, y~} against B(x~, y~)")
        cert.formula("jacobian_determinant", jac)
