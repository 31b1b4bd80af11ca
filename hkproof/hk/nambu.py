"""Nambu bivectors of a Kahan map (issue 38, docs/poisson.md "Nambu structures").

With n - 2 integrals I_k of a map f in n phase variables and an invariant density 1/P (P o f = det Df P), the
bivector Pi = P W(grad I_1, ..., grad I_{n-2}), where W^ij = eps^(i j k_1 ... k_(n-2)) d_k1 I_1 ... d_k(n-2) I_(n-2)
(the Hodge dual of dI_1 ^ ... ^ dI_(n-2) against the volume), is an invariant Poisson structure of rank 2 whose
Casimirs are the I_k (the construction of Byrnes, Haggar and Quispel, Physica A 272 (1999), for measure-preserving
maps with n - 2 integrals).

The proof never composes Pi with the map (its entries have thousands of terms; Pi(N / Delta) is out of reach for the
Clebsch map). It combines exact identities:

1. I_k o f = I_k (proven by whoever hands the integrals over), hence grad I_k(x) = grad I_k(f(x)) Df(x) (the chain
   rule applied to an identity of rational functions);
2. P o f = det Df P (a Darboux identity with the Jacobian as cofactor, proven by `measure`);
3. A W(g_1 A, ..., g_(n-2) A) A^T = det(A) W(g_1, ..., g_(n-2)) in Z[A, g] (universal, checked here for the given n):
   with A = Df(x), g_k = grad I_k(f(x)), 1 and 2, Df Pi(x) Df^T = P(x) det Df W(grad I(f(x))) = Pi(f(x));
4. [phi W, phi W] = 0 in the ring of the 1-jet of phi and the 2-jets of the I_k, with total derivatives (universal:
   Jacobi holds whatever functions are substituted);
5. W(g) g_k = 0 (universal): the I_k are Casimirs, so rank Pi <= 2 when their gradients are independent, and rank
   Pi >= 2 where Pi != 0 at a point.
"""
from __future__ import annotations

import functools
import itertools
from contextlib import suppress
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import flint

from hkproof import budget
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import Element, lcm, maximal_minors
from hkproof.algebra.ring import Rational, Ring, get_ring
from hkproof.checker import DET_DF
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ShapeError, SingularPointError
from hkproof.hk.certified_integrals import jacobian_points
from hkproof.hk.independence import gradient_at, max_jacobian_rank
from hkproof.hk.poisson import Bivector, antisymmetric, pairs, schouten
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.export import bivector_invariance_step, casimir_step, darboux_step, jacobi_step, nambu_step
from hkproof.proof.status import Status

__all__ = ["bivector_steps", "NambuStructure", "UNIVERSAL_IDENTITIES", "independent_subset", "nambu_bivector", "nambu_dual",
           "prove_nambu", "rank_at", "require_claimed", "universal_identity"]

UNIVERSAL_IDENTITIES = {
    "transformation": "A W(g A) A^T = det(A) W(g) in Z[A, g]",
    "jacobi": "[phi W(grad I), phi W(grad I)] = 0 in the ring of jets (total derivatives)",
    "casimir": "W(g) g_k = 0 in Z[g]",
}


def nambu_dual(rows: Sequence[Sequence[Element]]) -> list[Element]:
    """W^ij (i < j, in the order of `pairs(n)`) of n - 2 rows g_k of length n: the signed maximal minor of the rows
    on the columns other than i and j (sign of the permutation (i, j, the rest in order): (-1)^(i + j - 1))."""
    n = len(rows[0]) if rows else 0
    if n < 3 or len(rows) != n - 2 or any(len(r) != n for r in rows):
        raise ShapeError(f"the Nambu bivector takes n - 2 rows of length n >= 3, got {len(rows)} of length {n}")
    minors = maximal_minors(rows)
    zero = rows[0][0] - rows[0][0]
    full = (1 << n) - 1
    out = []
    for i, j in pairs(n):
        minor = minors.get(full & ~(1 << i) & ~(1 << j), zero)
        out.append(minor if (i + j - 1) % 2 == 0 else -minor)
    return out


def nambu_bivector(ring: Ring, variables: Sequence[str], integrals: Sequence[Frac], density: flint.fmpz_mpoly
                   ) -> Bivector:
    """Pi = P W(grad I_1, ..., grad I_(n-2)) for the density 1/P, over one denominator, common factors removed."""
    n = len(variables)
    if len(integrals) != n - 2:
        raise ShapeError(f"a Nambu bivector in {n} variables takes {n - 2} integrals, got {len(integrals)}")
    rows, dens = [], []
    for h in integrals:
        grad = [h.derivative(v) for v in variables]
        den = lcm([g.den for g in grad])
        rows.append([g.num * (den / g.den) for g in grad])
        dens.append(den)
    upper = [density * w for w in nambu_dual(rows)]
    den = ring.constant(1)
    for d in dens:
        den *= d
    common = den
    for q in upper:
        common = common.gcd(q)
    if common.is_zero() or all(q.is_zero() for q in upper):
        raise ShapeError("the integrals' gradients are dependent: their Nambu bivector is zero")
    return Bivector(ring, tuple(variables), tuple(q / common for q in upper), den / common)


def rank_at(ring: Ring, variables: Sequence[str], integrals: Sequence[Frac], density: flint.fmpz_mpoly,
            point: Mapping[str, Rational]) -> int:
    """The rank over Q of P W(grad I) at a rational point, from the gradients' values (nothing expanded; a lower
    bound of the generic rank); 0 where an integral has a pole."""
    try:
        rows = [gradient_at(h, variables, point) for h in integrals]
    except SingularPointError:
        return 0
    p = flint.fmpq(ring.evaluate(density, point))
    return int(flint.fmpq_mat(antisymmetric([p * w for w in nambu_dual(rows)], len(variables), flint.fmpq(0))).rank())


@functools.lru_cache(maxsize=None)
def universal_identity(key: str, n: int) -> bool:
    """Identity `key` of UNIVERSAL_IDENTITIES (3, 4 and 5 of the module docstring) for n phase variables, exactly."""
    if n < 3:
        raise ShapeError(f"Nambu bivectors need n >= 3 phase variables, got {n}")
    return {"transformation": _transformation_holds, "jacobi": _jacobi_holds, "casimir": _casimir_holds}[key](n)


def _transformation_holds(n: int) -> bool:
    names = tuple(f"a{p}_{q}" for p in range(n) for q in range(n)) + tuple(
        f"g{k}_{i}" for k in range(n - 2) for i in range(n))
    ring = get_ring(names)
    a = [[ring.gen(f"a{p}_{q}") for q in range(n)] for p in range(n)]
    g = [[ring.gen(f"g{k}_{i}") for i in range(n)] for k in range(n - 2)]
    ga = [[sum((g[k][p] * a[p][q] for p in range(n)), ring.constant(0)) for q in range(n)] for k in range(n - 2)]
    w = antisymmetric(nambu_dual(ga), n, ring.constant(0))
    det_a = maximal_minors(a)[(1 << n) - 1]
    right = nambu_dual(g)
    for (p, q), r in zip(pairs(n), right, strict=True):
        budget.check("the universal transformation identity of Nambu bivectors")
        left = sum((a[p][i] * a[q][j] * w[i][j] for i, j in itertools.product(range(n), repeat=2)
                    if not w[i][j].is_zero()), ring.constant(0))
        if left != det_a * r:
            return False
    return True


def _jacobi_holds(n: int) -> bool:
    """[phi W, phi W] = 0 with W built from the jets I_(k,i) and d_l the total derivative: d_l phi = phi_l,
    d_l I_(k,i) = I_(k,il) (symmetric in i, l); nothing else is differentiated."""
    second = [(k, i, l) for k in range(n - 2) for i in range(n) for l in range(i, n)]
    names = (("phi",) + tuple(f"phi_{l}" for l in range(n)) + tuple(f"I{k}_{i}" for k in range(n - 2) for i in range(n))
             + tuple(f"I{k}_{i}_{l}" for k, i, l in second) + tuple(f"x{i}" for i in range(n)))
    ring = get_ring(names)
    first = {ring.index(f"I{k}_{i}"): (k, i) for k in range(n - 2) for i in range(n)}
    phi = ring.index("phi")

    def total(p: flint.fmpz_mpoly, l: int) -> flint.fmpz_mpoly:
        out = p.derivative(phi) * ring.gen(f"phi_{l}")
        for v, (k, i) in first.items():
            out += p.derivative(v) * ring.gen(f"I{k}_{min(i, l)}_{max(i, l)}")
        return out
    g = [[ring.gen(f"I{k}_{i}") for i in range(n)] for k in range(n - 2)]
    pi = Bivector(ring, tuple(f"x{i}" for i in range(n)), tuple(ring.gen("phi") * w for w in nambu_dual(g)),
                  ring.constant(1))
    return all(c.is_zero() for c in schouten(pi, pi, derivation=total))


def _casimir_holds(n: int) -> bool:
    ring = get_ring(tuple(f"g{k}_{i}" for k in range(n - 2) for i in range(n)))
    g = [[ring.gen(f"g{k}_{i}") for i in range(n)] for k in range(n - 2)]
    w = antisymmetric(nambu_dual(g), n, ring.constant(0))
    return all(sum((w[i][j] * g[k][j] for j in range(n)), ring.constant(0)).is_zero()
               for k in range(n - 2) for i in range(n))


# ---- the proof ---------------------------------------------------------------------------------------------------------
@dataclass
class NambuStructure:
    """Pi = P W(grad I_1, ..., grad I_(n-2)) with its certificate; `hamiltonians`: further proven integrals,
    functionally independent of the Casimirs (one of them makes the map Liouville-Arnold integrable, r = 1)."""
    density: str                               # P of the density 1/P
    casimirs: list[tuple[str, Frac]]
    hamiltonians: list[tuple[str, Frac]]
    certificate: Certificate
    rank: int | None = None
    bivector: Bivector | None = None           # Pi expanded over one denominator: only for small integrals
    density_poly: flint.fmpz_mpoly | None = None
    point: Mapping[str, Rational] | None = None  # a rational point where the rank is 2 (for the checker's nambu step)

    @property
    def status(self) -> Status:
        return self.certificate.status

    @property
    def liouville_arnold(self) -> bool:
        """Rank 2, n - 2 Casimirs and one further independent integral (involution holds for one): r = 1."""
        return self.status.is_verified and self.rank == 2 and bool(self.hamiltonians)

    def to_dict(self, label: Any = str) -> dict[str, Any]:
        """The JSON entry of `hkproof poisson` ("nambu")."""
        pi = self.bivector
        terms = None if pi is None else sum(len(q) for q in pi.upper) + len(pi.denominator)
        return {"formula": f"P * W({', '.join(f'grad {n}' for n, _ in self.casimirs)})", "density": f"1/({self.density})",
                "casimirs": [n for n, _ in self.casimirs], "hamiltonians": [n for n, _ in self.hamiltonians],
                "rank": self.rank, "status": label(self.status), "liouville_arnold": self.liouville_arnold,
                "degree": None if pi is None else int(pi.degree()), "terms": terms,
                "matrix": pi.texts() if pi is not None and terms is not None and terms <= MATRIX_TERMS else None,
                "certificate": self.certificate.to_dict()}


MATRIX_TERMS = 2000
"""The largest Nambu bivector (terms of its Q_ij and D) whose matrix the JSON writes out (else its formula only)."""
EXPAND_TERMS = 200
"""Pi is expanded over one denominator when the chosen integrals have at most this many terms in all (the proof never
needs it: the Clebsch map's integrals, 6 000 terms, would take minutes of 4 x 4 minors)."""


def independent_subset(integrals: Sequence[tuple[str, Frac]], variables: Sequence[str], size: int
                       ) -> list[tuple[str, Frac]]:
    """The first `size` integrals, in order, whose gradients are independent (exact Jacobian ranks at rational points);
    fewer when there are not so many."""
    chosen: list[tuple[str, Frac]] = []
    points = jacobian_points(list(integrals[0][1].ring.names)) if integrals else []
    for name, h in integrals:
        if len(chosen) == size:
            break
        if max_jacobian_rank([g for _, g in chosen] + [h], variables, points) == len(chosen) + 1:
            chosen.append((name, h))
    return chosen


def prove_nambu(kmap: KahanMap, integrals: Sequence[tuple[str, Frac, Status]], density: tuple[str, flint.fmpz_mpoly,
                Status], fixed: Mapping[str, Any] | None = None, cert: Certificate | None = None) -> NambuStructure:
    """The theorem "Pi = P W(grad I) is an invariant Poisson structure of rank 2 with the Casimirs I_k" for n - 2
    integrals (the first n - 2 independent ones) and the density 1/P, each step exact (module docstring); the other
    integrals independent of them are listed as Hamiltonians. The steps go to `cert` when given (a claim's)."""
    n, ring = len(kmap.variables), kmap.ring
    status_of = {name: st for name, _, st in integrals}
    pairs_in = [(name, h) for name, h, _ in integrals]
    chosen = independent_subset(pairs_in, kmap.variables, n - 2)
    names = [name for name, _ in chosen]
    cert = cert or Certificate(f"nambu:{kmap.field.name}", f"a Nambu Poisson structure of the Kahan map of "
                               f"{kmap.field.name}", "issue 38; docs/poisson.md (Nambu structures); "
                               "Byrnes-Haggar-Quispel 1999",
                               f"Pi = P W({', '.join(f'grad {a}' for a in names)}) with P = {density[0]} is an "
                               f"invariant Poisson structure of rank 2 whose Casimirs are {', '.join(names) or 'none'}",
                               fixed={k: str(v) for k, v in (fixed or {}).items()})
    out = NambuStructure(density[0], chosen, [], cert, density_poly=density[1])
    with suppress(ProofStopped):
        with cert.step(f"{n - 2} functionally independent integrals", "exact Jacobian rank at rational points",
                       ring) as s:
            if len(chosen) != n - 2:
                s.inconclusive(f"{len(chosen)} independent integrals among {len(integrals)}, a Nambu bivector in "
                               f"dimension {n} needs {n - 2}")
            s.note(", ".join(names))
        with cert.step("I_k o f = I_k, hence grad I_k(x) = grad I_k(f(x)) Df(x)", "the integrals' own proofs (exact "
                       "substitution); the chain rule on an identity of rational functions", ring) as s:
            weak = [a for a in names if not status_of[a].is_verified]
            if weak:
                s.inconclusive(f"the integrals {', '.join(weak)} are not proven")
        with cert.step("P o f = det Df P (the density 1/P)", "measure's Darboux identity with the Jacobian as cofactor",
                       ring) as s:
            if not density[2].is_verified:
                s.inconclusive("the density is not proven")
            s.note(f"P = {density[0]}")
        for key, text in UNIVERSAL_IDENTITIES.items():
            with cert.step(f"universal identity ({key}), n = {n}", text + ", expanded exactly", "Z[universal]") as s:
                s.require(universal_identity(key, n), f"the {key} identity fails for n = {n}")
        with cert.step("rank 2", "rank <= 2: the n - 2 independent Casimirs; rank >= 2: the exact rank at a rational "
                       "point, from the gradients' values", ring) as s:
            ranks = [(rank_at(ring, kmap.variables, [h for _, h in chosen], density[1], x), x)
                     for x in jacobian_points(list(ring.names))]
            out.rank, out.point = max(ranks, key=lambda r: r[0])
            s.require(out.rank == 2, f"Pi has rank {out.rank} at the points")
        if sum(len(h.num) + len(h.den) for _, h in chosen) <= EXPAND_TERMS:
            out.bivector = nambu_bivector(ring, kmap.variables, [h for _, h in chosen], density[1])
        others = [(a, h) for a, h, st in integrals if a not in names and st.is_verified]
        out.hamiltonians = [c for c in independent_subset(chosen + others, kmap.variables, n - 1)
                            if c[0] not in names]
    return out


def bivector_steps(field: QuadraticField, structure: NambuStructure, name: str) -> list[dict]:
    """The checker's steps for a proven Nambu structure (the caller exports its Casimirs' substitution steps first):
    written out when its matrix has at most MATRIX_TERMS terms (invariance by substitution into the checker's own
    map, Jacobi, the Casimirs), else the density's Darboux identity with K = det Df and a nambu step (version 10: the
    checker expands the universal identities itself and checks the rank at the point)."""
    pi = structure.bivector
    if not structure.status.is_verified:
        return []
    if pi is not None and sum(len(q) for q in pi.upper) + len(pi.denominator) <= MATRIX_TERMS:
        return [bivector_invariance_step(field, name, pi.texts()), jacobi_step(field, [name]),
                casimir_step(field, name, [c for c, _ in structure.casimirs])]
    if structure.density_poly is None or structure.point is None:
        return []
    density = Frac(field.ring, structure.density_poly)
    rho = f"rho_{name}"
    return [darboux_step(field, ["P"], [density], DET_DF, densities=[(rho, 1 / density, "1/(P)")]),
            nambu_step(field, name, [c for c, _ in structure.casimirs], rho, structure.point)]


def require_claimed(cert: Certificate, ring: Ring, out: NambuStructure, claimed: Mapping[str, str],
                    liouville_arnold: bool = False) -> None:
    """A claim's last step: the proven rank and number of Casimirs are the claimed `rank` and `casimirs`, and with
    `liouville_arnold` a further proven integral is independent of them (r = 1)."""
    integrable = out.liouville_arnold       # read before the step opens (an open step is not yet verified)
    name, method = (("Liouville-Arnold: rank 2, n - 2 Casimirs, one further integral", "the steps above; functional "
                     "independence of the Casimirs and the further integral by an exact Jacobian rank")
                    if liouville_arnold else ("the claim's rank and Casimirs", "read from the steps above"))
    with cert.step(name, method, ring) as s:
        s.require(str(out.rank) == claimed["rank"].strip() and str(len(out.casimirs)) == claimed["casimirs"].strip(),
                  f"rank {out.rank} with {len(out.casimirs)} Casimirs, the claim says rank {claimed['rank']} with "
                  f"{claimed['casimirs']}")
        if liouville_arnold:
            s.require(integrable, "no proven integral is independent of the Casimirs")
        s.note(f"Casimirs {', '.join(n for n, _ in out.casimirs)}; further independent integrals: "
               f"{', '.join(n for n, _ in out.hamiltonians) or 'none'}")
