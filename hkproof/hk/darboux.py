"""Darboux polynomials P o f = K P of a Kahan map, the prover's half: the cofactor candidates (products of the
irreducible factors of det Df) and the exact checks P(N/Delta) = K P in Q(x, eps, params).

The search that produces candidates P (mod p, then reconstructed) is hkproof.pipelines.darboux.
"""
from __future__ import annotations

import itertools
import random
from dataclasses import dataclass
from typing import Mapping, Sequence

import flint

from hkproof.algebra.sampling import random_point
from hkproof.algebra.fraction import Frac, homogenized_compose
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, ResourceLimitError
from hkproof.dynamics.field import EPS
from hkproof.hk.jacobian import jacobian_determinant
from hkproof.hk.row_check import Route, RouteCosts, RowCheck, decide_identity, phase_coefficients
from hkproof.proof.certificate import Certificate, Step, describe_ring
from hkproof.proof.status import Status

__all__ = ["Atom", "Cofactor", "DarbouxPolynomial", "candidate_cofactors", "check_at_points", "check_darboux",
           "cofactor_value", "darboux_identity_checks", "IDENTITY", "jacobian_atoms"]


@dataclass(frozen=True)
class Atom:
    """An irreducible factor q(x, eps, params) of det Df; `pulled` atoms stand for q(f(x)) (too big to expand)."""

    name: str
    poly: flint.fmpz_mpoly
    pulled: bool = False


@dataclass
class Cofactor:
    """K = prod atom^exponent."""

    exponents: tuple[int, ...]

    def text(self, atoms: Sequence[Atom]) -> str:
        parts = [(a.name if e == 1 else f"{a.name}^{e}", e) for a, e in zip(atoms, self.exponents, strict=True) if e]
        num = [t for t, e in parts if e > 0]
        den = [(a.name if e == -1 else f"{a.name}^{-e}") for a, e in zip(atoms, self.exponents, strict=True) if e < 0]
        top = " * ".join(num) or "1"
        return top if not den else f"{top} / ({' * '.join(den)})"


@dataclass
class DarbouxPolynomial:
    """P with P o f = K P and the certificate of that identity (verified when checked exactly with everything
    symbolic, evidence(exact) when checked at points)."""

    poly: flint.fmpz_mpoly
    cofactor: Cofactor
    certificate: Certificate

    @property
    def status(self) -> Status:
        return self.certificate.status

    @property
    def detail(self) -> str:
        """How the identity was checked."""
        return self.certificate.steps[-1].method


def darboux_certificate(kmap: KahanMap, p: flint.fmpz_mpoly, cofactor: str, status: Status, how: str, seconds: float,
                        fixed: Mapping[str, object] | None = None) -> Certificate:
    """The certificate of one Darboux polynomial: the step P o f = K P as it was checked."""
    ring = describe_ring(kmap.ring, fixed)
    return Certificate(f"darboux:{kmap.field.name}", f"a Darboux polynomial of the Kahan map of {kmap.field.name}",
                       "Celledoni et al. 2019; docs/geometry.md", f"P o f = K P with P = {p}, K = {cofactor}",
                       [Step("P o f = K P", how, ring, status, seconds)],
                       fixed={k: str(v) for k, v in (fixed or {}).items()})


# ---- atoms: the factors of det Df ----------------------------------------------------------------------------------
def jacobian_atoms(kmap: KahanMap, expand_limit: int = 4) -> tuple[list[Atom], Cofactor]:
    """The irreducible factors (in the phase variables) of numerator and denominator of det Df = det M(f(x), -eps) /
    det M(x, eps), and det Df as a product of them. With more than `expand_limit` phase variables the numerator is not
    expanded: det M(x, -eps) o f is one atom."""
    num, den, pulled = jacobian_determinant(kmap, expand=len(kmap.variables) <= expand_limit)
    atoms: list[Atom] = []
    exps: list[int] = []
    for sign, poly, letter in ((1, num, "A"), (-1, den, "B")):
        content = poly
        for q, e in _phase_factors(kmap, poly):
            atoms.append(Atom(f"{letter}{sum(1 for a in atoms if a.name[0] == letter) + 1}", q))
            exps.append(sign * e)
            content = content / q ** e
        if content != 1:        # the part free of x (eps, parameters, a number): an atom of its own
            atoms.append(Atom(f"c{letter}", content))
            exps.append(sign)
    if pulled is not None:
        atoms.append(Atom("detM(f(x),-eps)", pulled, pulled=True))
        exps.append(1)
    return atoms, Cofactor(tuple(exps))


def _phase_factors(kmap: KahanMap, poly: flint.fmpz_mpoly) -> list[tuple[flint.fmpz_mpoly, int]]:
    """Irreducible factors of poly over Z that involve a phase variable, with multiplicities (sign normalized)."""
    idx = [kmap.ring.index(v) for v in kmap.variables]
    out = []
    for q, e in poly.factor()[1]:
        if any(q.degrees()[i] > 0 for i in idx):
            if q.coefficient(len(q) - 1) < 0:
                q = -q
            out.append((q, int(e)))
    return out


def candidate_cofactors(jac: Cofactor, limit: int = 400) -> list[Cofactor]:
    """Products of the atoms with exponents between 0 and their exponent in det Df (1 and det Df included)."""
    ranges = [range(0, e + 1) if e >= 0 else range(e, 1) for e in jac.exponents]
    out = [Cofactor(tuple(c)) for c in itertools.product(*ranges)]
    if len(out) > limit:
        raise ResourceLimitError(f"{len(out)} candidate cofactors (products of the factors of det Df with their "
                                 f"multiplicities): more than the limit of {limit}; the Darboux search is too large "
                                 "for this system (no option raises this limit)", limit=f"{limit} candidate cofactors",
                                 raise_with="no option raises it")
    return out


# ---- the exact checks ---------------------------------------------------------------------------------------------
COMPOSE_WEIGHT = 0.5   # one compose of P against Horner's scheme in (N, Delta): dc-invariant-measures, 11.7 s / 22.8 s
IDENTITY = ("P o f = K P with f = N/Delta, cleared of the powers of Delta and of the denominator atoms: a polynomial "
            "identity in Z[x, eps, params]")
"""How darboux_identity_checks checks (the certificate's wording)."""


def cofactor_value(kmap: KahanMap, atoms: Sequence[Atom], cofactor: Cofactor) -> Frac:
    """K as an element of Q(x, eps, params) (a pulled atom is composed with f: costly for large maps)."""
    out = Frac(kmap.ring, 1)
    for a, e in zip(atoms, cofactor.exponents, strict=True):
        if e:
            q = Frac(kmap.ring, a.poly)
            out = out * (kmap.pullback(q) if a.pulled else q) ** e
    return out


def check_at_points(kmap: KahanMap, atoms: Sequence[Atom], cofactor: Cofactor, p: flint.fmpz_mpoly,
                    rng: random.Random, points: int = 3, fixed: dict[str, flint.fmpq] | None = None) -> bool:
    """P(f(x)) = K(x) P(x) at random rational x, eps and parameters (those in `fixed` kept), exactly (evidence)."""
    ring = kmap.ring
    done = 0
    while done < points:
        pt = random_point(rng, ring.names, 9, denominator=7)
        pt.update(fixed or {})
        try:
            fx = kmap.step_exact(pt)
        except HKProofError:
            continue
        at_f = {**pt, **fx}
        k = flint.fmpq(1)
        for a, e in zip(atoms, cofactor.exponents, strict=True):
            if e:
                v = ring.evaluate(a.poly, at_f if a.pulled else pt)
                if v == 0:
                    break
                k *= v ** e
        else:
            if ring.evaluate(p, at_f) != k * ring.evaluate(p, pt):
                return False
            done += 1
    return True


def darboux_identity_checks(kmap: KahanMap, atoms: Sequence[Atom], cofactor: Cofactor,
                            polys: Sequence[flint.fmpz_mpoly], route: Route = "auto") -> list[RowCheck]:
    """P o f = K P for each P, as polynomial identities in Z[x, eps, params] with no gcd and no pulled atom composed on
    its own. With K = (A / B) (Q+ o f) / (Q- o f) (A, B the products of the plain atoms, Q+ and Q- of the pulled
    ones) and f = N / Delta, the identity is (P Q-) o f B = A P (Q+ o f); with G1 = P Q- = sum_m c_m x^m of degree
    d1 and Q+ = sum_m s_m x^m of degree d2, times Delta^max(d1, d2) it reads
        R = sum_m (c_m B - s_m A P) N^m Delta^(max(d1, d2) - |m|) = 0,
    one sum over the factors (N_1, ..., N_n, Delta). Route "horner" composes G1 (and Q+, once for all P) and
    multiplies both sides out; "lattice" and "modular" take R to `row_check.decide_identity`; "auto" the cheapest by
    `RouteCosts`, the composes at COMPOSE_WEIGHT of Horner's scheme. Each result names its route and is true iff the
    identity holds."""
    ring, moved = kmap.ring, kmap.variables
    nums, delta = kmap.explicit
    plain_top, plain_below, pulled_top, pulled_below = (ring.constant(1) for _ in range(4))
    for a, e in zip(atoms, cofactor.exponents, strict=True):
        if e > 0:
            if a.pulled:
                pulled_top *= a.poly ** e
            else:
                plain_top *= a.poly ** e
        elif e < 0:
            if a.pulled:
                pulled_below *= a.poly ** -e
            else:
                plain_below *= a.poly ** -e
    right = phase_coefficients(kmap, pulled_top)
    d2 = max(sum(m) for m in right)
    composed_right: flint.fmpz_mpoly | None = None      # Q+(N/Delta) Delta^d2, composed once when needed
    out = []
    for p in polys:
        left = phase_coefficients(kmap, p * pulled_below)
        d1 = max((sum(m) for m in left), default=0)
        d = max(d1, d2)
        chosen, terms = route, {}
        if route != "horner":           # the folded sum: the other routes take it, and "auto" prices it
            folded: dict[tuple[int, ...], flint.fmpz_mpoly] = {m: c * plain_below for m, c in left.items()}
            for m, s in right.items():
                folded[m] = folded.get(m, ring.constant(0)) - s * plain_top * p
            terms = {(*m, d - sum(m)): t for m, t in folded.items() if not t.is_zero()}
            if not terms:
                out.append(RowCheck(True, "P o f = K P: every coefficient of the folded identity is zero", "horner"))
                continue
        factors, free = [*nums, delta], (EPS, *kmap.field.parameters)
        if route == "auto":
            costs = RouteCosts(terms, factors, ring.names, free)
            costs.costs["horner"] *= COMPOSE_WEIGHT
            chosen = costs.cheapest
        if chosen == "horner":
            if composed_right is None:
                composed_right = homogenized_compose(ring, pulled_top, moved, nums, delta)[0]
            g1, _ = homogenized_compose(ring, p * pulled_below, moved, nums, delta)
            holds = g1 * plain_below * delta ** (d - d1) == plain_top * p * composed_right * delta ** (d - d2)
            out.append(RowCheck(holds, "P o f = K P by one compose of P (and of the pulled atoms), both sides expanded",
                                "horner"))
        else:
            out.append(decide_identity(terms, factors, ring.names, free, chosen, "P o f = K P",
                                       "the numerators of f"))
    return out


def check_darboux(kmap: KahanMap, atoms: Sequence[Atom], cofactor: Cofactor, p: flint.fmpz_mpoly,
                  exact: bool = True, rng: random.Random | None = None,
                  fixed: Mapping[str, flint.fmpq] | None = None) -> tuple[Status, str]:
    """Is P o f = K P? Verified (or refuted) exactly in Z[x, eps, params] (darboux_identity_checks); with
    exact=False, evidence(exact) (or refuted) at three random exact points (eps and parameters random too, except
    those `fixed`)."""
    if exact:
        check = darboux_identity_checks(kmap, atoms, cofactor, [p])[0]
        return (Status.VERIFIED if check else Status.REFUTED), f"{IDENTITY}; {check.route}"
    ok = check_at_points(kmap, atoms, cofactor, p, rng or random.Random(0), fixed=dict(fixed or {}))
    where = (f"at {', '.join(f'{k} = {v}' for k, v in fixed.items())} only: P(f(x)) = K(x) P(x) at 3 random exact "
             "points x") if fixed else "P(f(x)) = K(x) P(x) at 3 random exact points (x, eps, params)"
    return (Status.EVIDENCE_EXACT if ok else Status.REFUTED), where
