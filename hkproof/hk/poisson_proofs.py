"""Certificates of invariant bivectors: invariance, Jacobi, rank, Casimirs, compatibility, involution, and the
exclusion of a whole class Q/D by a full column rank mod p (docs/poisson.md; the rules of docs/method.md)."""
from __future__ import annotations

import itertools
from contextlib import suppress
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac, poly_str
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.poisson import Bivector, bracket, casimir_combination, compatible, generic_rank, invariance_holds, is_casimir, is_poisson
from hkproof.hk.torus import Torus, is_semi_invariant, torus_data
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

__all__ = ["BlockRank", "LEMMA", "METHOD_INVARIANCE", "StructureProof", "compatibility_step", "exclusion_certificate",
           "involution_certificate", "no_poisson_certificate", "prove_structure"]

LEMMA = "M(x, eps) Df(x) = M(f(x), -eps) (the Kahan equations differentiated; hk.jacobian.matrix_identity_holds)"
METHOD_INVARIANCE = ("through the Kahan equations: M(x, eps) Q(x~) M(x, eps)^T D(x) Delta^(dD+2) = "
                     "D(x~) Delta^dD M(x~, -eps) Delta Q(x) (M(x~, -eps) Delta)^T Delta^dQ at x~ = N/Delta, homogenized "
                     "compositions, no Df and no gcd")


@dataclass
class StructureProof:
    """One invariant bivector with its certificate and what was proven about it."""
    bivector: Bivector
    certificate: Certificate
    poisson: bool | None = None           # Jacobi: True, False (the bracket is not zero, exactly), None (not decided)
    rank: int | None = None
    casimirs: list[tuple[str, Frac]] = field(default_factory=list)

    @property
    def status(self) -> Status:
        return self.certificate.status


def prove_structure(kmap: KahanMap, pi: Bivector, integrals: Sequence[tuple[str, Frac]], lemma: bool,
                    fixed: Mapping[str, Any] | None = None, name: str = "Pi") -> StructureProof:
    """Invariance (the claim), then Jacobi, the exact rank and which integrals are Casimirs, each a step."""
    fixed_text = {k: str(v) for k, v in (fixed or {}).items()}
    cert = Certificate(f"poisson:{kmap.field.name}", f"an invariant bivector of the Kahan map of {kmap.field.name}",
                       "issue 38; docs/poisson.md", f"{name} = {pi} satisfies {name}(f(x)) = Df {name}(x) Df^T",
                       fixed=fixed_text)
    for (i, j), row in ((ij, pi.fracs()[ij[0]][ij[1]]) for ij in itertools.combinations(range(len(pi.variables)), 2)):
        cert.formula(f"{name}[{pi.variables[i]},{pi.variables[j]}]", row)
    out = StructureProof(pi, cert)
    with suppress(ProofStopped):
        with cert.step("M(x, eps) Df(x) = M(f(x), -eps)", LEMMA, kmap.ring) as s:
            s.require(lemma, "the matrix identity of the Kahan equations fails")
        with cert.step(f"{name}(f(x)) = Df {name}(x) Df^T", METHOD_INVARIANCE, kmap.ring) as s:
            s.require(invariance_holds(kmap, pi), f"{name} is not invariant: the identity has a non-zero residue")
        with cert.step("Jacobi: [Pi, Pi] = 0", "Schouten bracket, D cleared, expanded exactly", kmap.ring) as s:
            out.poisson = is_poisson(pi)
            s.note("[Pi, Pi] = 0: Pi is Poisson" if out.poisson else
                   "[Pi, Pi] != 0 (exact): an invariant bivector that is NOT a Poisson structure")
        with cert.step("rank of Pi", "fraction-free elimination over Q(x, eps, params)", kmap.ring) as s:
            out.rank = generic_rank(pi)
            s.note(f"rank {out.rank}")
        for cname, c in casimirs(pi, integrals):
            with cert.step(f"{cname} is a Casimir: Pi grad ({cname}) = 0", "exact", kmap.ring) as s:
                s.require(is_casimir(pi, c), f"Pi grad ({cname}) != 0")
                s.note(f"{cname} = {c}")
            out.casimirs.append((cname, c))
    if out.poisson is False:
        cert.statement += "; [Pi, Pi] != 0: not a Poisson structure"
    return out


def casimirs(pi: Bivector, integrals: Sequence[tuple[str, Frac]]) -> list[tuple[str, Frac]]:
    """Casimirs among the integrals, their reciprocals and ratios, and combinations g - c h of two of these with c free
    of x (the first found):
    candidates, each checked exactly by the caller."""
    candidates = list(integrals) + [(f"1/{a}", 1 / f) for a, f in integrals if not f.is_zero()]
    candidates += [(f"{a}/{b}", f / g) for (a, f), (b, g) in itertools.permutations(integrals, 2) if not g.is_zero()]
    found: list[tuple[str, Frac]] = []
    for name, g in candidates:
        c = casimir_combination(pi, g)
        if c is not None:
            found.append((name, c))
    if found:
        return found[:1]
    for (a, g), (b, h) in itertools.combinations(candidates, 2):
        c = casimir_combination(pi, g, h)
        if c is not None:
            return [(f"{a} - c ({b})", c)]
    return []


def involution_certificate(kmap: KahanMap, pi: Bivector, integrals: Sequence[tuple[str, Frac]],
                           fixed: Mapping[str, Any] | None = None) -> Certificate:
    """{I_k, I_l}_Pi = 0 for every pair of the given integrals, exactly."""
    names = ", ".join(n for n, _ in integrals)
    cert = Certificate(f"involution:{kmap.field.name}", f"integrals in involution for an invariant Poisson structure "
                       f"of {kmap.field.name}", "issue 38; docs/poisson.md",
                       f"{{I_k, I_l}} = 0 for I in ({names}) and Pi = {pi}",
                       fixed={k: str(v) for k, v in (fixed or {}).items()})
    with suppress(ProofStopped):
        for (a, f), (b, g) in itertools.combinations(integrals, 2):
            with cert.step(f"{{{a}, {b}}} = 0", "grad f . Pi grad g, exact", kmap.ring) as s:
                value = bracket(pi, f, g)
                s.require(value.is_zero(), f"{{{a}, {b}}} = {value}")
        if len(integrals) < 2:
            with cert.step("no pair of integrals", "nothing to check", kmap.ring) as s:
                s.note("fewer than two integrals: involution holds trivially")
    return cert


def compatibility_step(cert: Certificate, kmap: KahanMap, a: tuple[str, Bivector], b: tuple[str, Bivector]) -> bool:
    """[Pi_a, Pi_b] = 0 as a step of `cert` (a bi-Hamiltonian pair when both are Poisson); its truth value."""
    ok = compatible(a[1], b[1])
    with suppress(ProofStopped), cert.step(f"[{a[0]}, {b[0]}] = 0", "Schouten bracket, exact", kmap.ring) as s:
        s.note("compatible" if ok else "[Pi_a, Pi_b] != 0 (exact): not compatible")
    return ok


@dataclass(frozen=True)
class BlockRank:
    """One character block of an excluded class: its columns, the rows, the rank mod p and the points."""
    character: tuple[int, ...]
    columns: int
    rows: int
    rank: int
    points: tuple[tuple[int, ...], ...]


def exclusion_certificate(kmap: KahanMap, denominator: flint.fmpz_mpoly, degree: int, prime: int,
                          values: Mapping[str, flint.fmpq], symmetries: Sequence[str], ranks: Sequence[BlockRank],
                          fixed: Mapping[str, Any] | None = None, torus: Torus | None = None) -> Certificate:
    """No invariant Q/D with deg Q <= degree over Q(eps, params): each block has full column rank mod p."""
    cert = _class_certificate(kmap, "exclusion", f"no invariant bivector Q/D, deg Q <= {degree}",
                              "issue 38, item 4; docs/poisson.md",
                              f"no Q != 0 (antisymmetric, polynomial of degree <= {degree} in the phase variables, "
                              f"coefficients in Q(eps, parameters)) with Pi = Q/({poly_str(denominator)}) invariant",
                              fixed)
    with suppress(ProofStopped):
        _full_rank_steps(cert, kmap, denominator, prime, values, symmetries, ranks, torus)
    return cert


def no_poisson_certificate(kmap: KahanMap, denominator: flint.fmpz_mpoly, degree: int, prime: int,
                           values: Mapping[str, flint.fmpq], symmetries: Sequence[str], others: Sequence[BlockRank],
                           kernels: Sequence[BlockRank], fixed: Mapping[str, Any] | None = None,
                           torus: Torus | None = None, *, on_fixed: bool = False, text: str = "") -> Certificate:
    """No invariant Q/D with deg Q <= degree is Poisson: full column rank mod p off the kernels' sign characters, and on
    each (in the field's coordinates) a kernel mod p; the brackets of all their members are independent mod p (the
    caller tested them), so that no member is Poisson; any invariant Poisson Q over Q(eps, params) would reduce to
    such a member. `text`: D as the product of its factors, for the statement."""
    cert = _class_certificate(kmap, "no-poisson", f"no invariant Poisson structure Q/D, deg Q <= {degree}",
                              "issue 38; docs/poisson.md",
                              f"no Q != 0 (antisymmetric, polynomial of degree <= {degree} in the phase variables, "
                              f"coefficients in Q(eps, parameters)) with Pi = Q/({text or poly_str(denominator)}) "
                              "invariant and Poisson", fixed)
    r = sum(b.columns - b.rank for b in kernels)
    with suppress(ProofStopped):
        _full_rank_steps(cert, kmap, denominator, prime, values, symmetries, others, torus)
        where = (" (on the bivectors fixed by the torus' flow: ker(L_X - chi), exact, as many as the columns of weight "
                 "chi mod p)" if on_fixed else "")
        with cert.step("no member of the kernels mod p satisfies Jacobi",
                       f"nmod_mat kernels of the blocks {[list(b.character) for b in kernels]} in the field's "
                       f"coordinates{where} mod {prime}; the Schouten brackets of their members, independent mod p",
                       kmap.ring) as s:
            s.note(f"kernels of dimension {r} in all ({[b.columns for b in kernels]} columns); the {r * (r + 1) // 2} "
                   "brackets [v_a, v_b] are linearly independent mod p, so sum c_a c_b [v_a, v_b] = 0 forces c = 0. "
                   "An invariant Poisson Q/D over Q(eps, params), restricted to a generic line through the values, "
                   "divided by the power of t that divides it and set at t = 0, would give a non-zero rational "
                   "invariant Poisson bivector at the values, hence such a member mod p: there is none")
    return cert


def _full_rank_steps(cert: Certificate, kmap: KahanMap, denominator: flint.fmpz_mpoly, prime: int,
                     values: Mapping[str, flint.fmpq], symmetries: Sequence[str], ranks: Sequence[BlockRank],
                     torus: Torus | None) -> None:
    """The sign symmetries and torus that split the columns, and full column rank mod p in the `ranks` blocks."""
    if symmetries:
        with cert.step("sign symmetries split the columns", "exact identities of the Kahan equations",
                       kmap.ring) as s:
            s.note("; ".join(symmetries))
    if torus is not None:
        with cert.step("a linear symmetry splits the columns by weight", "[A x, F] = 0 by an exact nullspace; "
                       "grad D . A x = c D exactly; T A = diag(l) T mod p (hkproof.hk.torus)", kmap.ring) as s:
            s.require(is_semi_invariant(kmap, torus.generator, denominator), "D is not semi-invariant under A")
            s.note(f"A = {torus_data(torus)['generator']}, eigenvalues mod {prime}: {list(torus.weights)}")
    at = ", ".join(f"{k} = {v}" for k, v in values.items())
    with cert.step("full column rank mod p", f"nmod_mat.rank at {at} mod {prime}", kmap.ring) as s:
        for b in ranks:
            s.require(b.rank == b.columns, f"block {b.character}: rank {b.rank} < {b.columns} columns")
        s.note(f"{len(ranks)} block(s), columns {[b.columns for b in ranks]}, rows {[b.rows for b in ranks]}")


def kernel_certificate(kmap: KahanMap, denominator: str, degree: int, prime: int, dimension: int,
                       fixed: Mapping[str, Any] | None = None) -> Certificate:
    """Evidence (exact, mod p at one specialization) that invariant Q/D of degree `degree` likely exist: the rows
    have a kernel of `dimension` there, confirmed on more points, not rebuilt (`poisson --screen`)."""
    cert = _class_certificate(kmap, "kernel", f"invariant bivectors Q/D, deg Q <= {degree}: a kernel",
                              "issue 38; docs/poisson.md (--screen)",
                              f"the invariance rows of Q/({denominator}), deg Q <= {degree}, have a kernel of "
                              f"dimension {dimension} mod {prime} at one specialization (the lowest such degree)", fixed)
    with suppress(ProofStopped):
        with cert.step("kernel of the invariance rows mod p", f"nmod_mat.rank mod {prime}, confirmed on more points",
                       kmap.ring) as s:
            s.evidence(Status.EVIDENCE_EXACT)
            s.note(f"kernel dimension {dimension} at degree {degree}; not rebuilt, so neither invariance over "
                   "Q(eps, params) nor Jacobi is proven")
    return cert


def _class_certificate(kmap: KahanMap, kind: str, title: str, ref: str, statement: str,
                       fixed: Mapping[str, Any] | None) -> Certificate:
    """The certificate of one class Q/D of the Kahan map (an exclusion or a screened kernel)."""
    return Certificate(f"poisson-{kind}:{kmap.field.name}", f"{title}, of the Kahan map of {kmap.field.name}", ref,
                       statement, fixed={k: str(v) for k, v in (fixed or {}).items()})

