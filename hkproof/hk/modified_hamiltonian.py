"""The modified Hamiltonian and invariant measure of Kahan's method for a cubic H and a constant Poisson matrix J
(Celledoni, McLachlan, Owren, Quispel 2013): with F = J grad H and h = 2 eps (hkproof's eps is half the step),
    H~ = H + (h/3) grad H^T (I - (h/2) F')^(-1) F      and      dx / det(I - (h/2) F')
are preserved by the Kahan map.  Both are constructed here and checked exactly."""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Sequence

from hkproof.algebra import formula
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import cramer, det, lcm
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import NotHamiltonianError, ParseError
from hkproof.hk.integrals import check_integral
from hkproof.hk.jacobian import jacobian_determinant, matrix_identity_holds
from hkproof.proof.certificate import Certificate, Step, describe_ring
from hkproof.proof.status import Status

__all__ = ["check_inputs", "field_jacobian", "measure_denominator", "modified_hamiltonian", "ModifiedHamiltonianResult", "parse_matrix", "verify"]

CMOQ = "Celledoni, McLachlan, Owren, Quispel, J. Phys. A 46 (2013) 025201; docs/geometry.md"



def parse_matrix(kmap: KahanMap, text: str) -> list[list[Frac]]:
    """A square matrix written '[[a, b], [c, d]]' or 'a, b; c, d', entries read by Frac.parse."""
    body = text.strip()
    if body.startswith("["):
        rows = formula.parse_matrix(kmap.ring, body)
    elif "[" in body or "]" in body:
        raise ParseError(f"cannot read the matrix {text!r}: write it as [[a, b], [c, d]] or 'a, b; c, d'")
    else:
        rows = [[Frac.parse(kmap.ring, e) for e in formula.split_list(row, "row")] for row in body.split(";")]
    n = len(kmap.variables)
    if len(rows) != n or any(len(r) != n for r in rows):
        raise NotHamiltonianError(f"the Poisson matrix must be {n} x {n} for {kmap.field.name} "
                                  f"(variables {list(kmap.variables)}), got {[len(r) for r in rows]}")
    return rows


def check_inputs(kmap: KahanMap, h: Frac, j: Sequence[Sequence[Frac]]) -> None:
    """J constant (no phase variable, no eps) and skew; H a polynomial of degree <= 3 free of eps; F = J grad H."""
    xs = set(kmap.variables)
    for a, row in enumerate(j):
        for b, e in enumerate(row):
            if e.variables() & (xs | {EPS}):
                raise NotHamiltonianError(f"J[{a + 1},{b + 1}] = {e} is not constant: this construction needs a "
                                          "constant Poisson matrix (no phase variables, no eps)")
            if e != -j[b][a]:
                raise NotHamiltonianError(f"J is not skew: J[{a + 1},{b + 1}] = {e} but J[{b + 1},{a + 1}] = {j[b][a]}")
    if EPS in h.variables():
        raise NotHamiltonianError(f"H = {h} must not involve eps")
    if h.den_variables_in(kmap.variables) or h.degrees_in(kmap.variables)[0] > 3:
        raise NotHamiltonianError(f"H = {h} must be a polynomial of degree <= 3 in {list(kmap.variables)}")
    grad = [h.derivative(v) for v in kmap.variables]
    for i, (v, f) in enumerate(zip(kmap.variables, kmap.field.rhs, strict=True)):
        jg = sum((j[i][k] * grad[k] for k in range(len(grad))), Frac(kmap.ring, 0))
        if jg != f:
            raise NotHamiltonianError(f"H does not generate the field: (J grad H)_{v} = {jg} but {v}' = {f} "
                                      f"(difference {jg - f})")


def field_jacobian(kmap: KahanMap) -> list[list[Frac]]:
    """F'(x) = (dF_i / dx_j)."""
    return [[f.derivative(v) for v in kmap.variables] for f in kmap.field.rhs]


def modified_hamiltonian(kmap: KahanMap, h: Frac) -> Frac:
    """H~ = H + (2 eps / 3) grad H^T y with (I - eps F') y = F (Cramer's rule over Q(x, eps, params))."""
    r = kmap.ring
    eps = Frac(r, r.gen(EPS))
    y, _ = cramer(_i_minus_eps_jacobian(kmap), list(kmap.field.rhs))
    grad = [h.derivative(v) for v in kmap.variables]
    return h + Frac(r, 2) / 3 * eps * sum((g * c for g, c in zip(grad, y, strict=True)), Frac(r, 0))


def measure_denominator(kmap: KahanMap) -> Frac:
    """det(I - (h/2) F'(x)) = det(I - eps F'(x)): each row cleared of denominators, one polynomial determinant."""
    r = kmap.ring
    total, scale = [], Frac(r, 1)
    for row in _i_minus_eps_jacobian(kmap):
        common = lcm([f.den for f in row])
        total.append([f.num * (common / f.den) for f in row])
        scale = scale * Frac(r, common)
    return Frac(r, det(total)) / scale


def _i_minus_eps_jacobian(kmap: KahanMap) -> list[list[Frac]]:
    """I - eps F'(x)."""
    r = kmap.ring
    eps = Frac(r, r.gen(EPS))
    jac = field_jacobian(kmap)
    n = len(kmap.variables)
    return [[Frac(r, int(a == b)) - eps * jac[a][b] for b in range(n)] for a in range(n)]


@dataclass
class ModifiedHamiltonianResult:
    """H~ and the density, each with the certificate of its exact verdict."""

    h_tilde: Frac
    density_denominator: Frac
    integral_certificate: Certificate
    measure_certificate: Certificate
    jacobian_identity: bool
    jacobian: Frac          # det Df, the cofactor of det(I - eps F') (a Darboux polynomial)

    @property
    def integral(self) -> Status:
        return self.integral_certificate.status

    @property
    def measure(self) -> Status:
        return self.measure_certificate.status


def verify(kmap: KahanMap, h: Frac, j: Sequence[Sequence[Frac]]) -> ModifiedHamiltonianResult:
    """Check the inputs, construct H~ and det(I - eps F'), and decide exactly H~ o f = H~ and
    rho(f(x)) det Df(x) = rho(x) for rho = 1 / det(I - eps F') (det Df from M(x, eps) Df = M(f(x), -eps))."""
    check_inputs(kmap, h, j)
    name, ring = kmap.field.name, describe_ring(kmap.ring)
    start = time.perf_counter()
    ht = modified_hamiltonian(kmap, h)
    verdict = check_integral(kmap, ht)
    integral = Certificate(f"hamiltonian:{name}", f"the modified Hamiltonian of the Kahan map of {name}", CMOQ,
                           f"H~ o f = H~ for H~ = {ht}", [Step("H~ o f = H~", verdict.method, ring, verdict.status,
                                                                time.perf_counter() - start)])
    start = time.perf_counter()
    p = measure_denominator(kmap)
    num, den, _ = jacobian_determinant(kmap)
    lemma = matrix_identity_holds(kmap)
    ok = kmap.pullback(p) == Frac(kmap.ring, num, den) * p
    status = (Status.VERIFIED if lemma else Status.UNKNOWN) if ok else Status.REFUTED
    measure = Certificate(f"hamiltonian-measure:{name}", f"the invariant measure of the Kahan map of {name}", CMOQ,
                          f"rho(f(x)) det Df(x) = rho(x) for rho = 1/({p})",
                          [Step("rho(f(x)) det Df(x) = rho(x)", "P(N/Delta) = det Df P exactly, det Df = det M(f(x), "
                                "-eps)/det M(x, eps) by the matrix identity M(x, eps) Df = M(f(x), -eps)", ring, status,
                                time.perf_counter() - start, "" if lemma else "the matrix identity does not hold")])
    return ModifiedHamiltonianResult(ht, p, integral, measure, lemma, Frac(kmap.ring, num, den))
