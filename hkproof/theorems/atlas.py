"""An atlas beyond the paper: integrals of Kahan maps of systems named in its conclusions, found by `discover`.

For each system two claims: the integrals `discover` reconstructs, each proven by exact substitution, and their
functional independence by an exact Jacobian rank (verified, or verified(specialized) where parameters are fixed
to keep the reconstruction dense-sized); and the kernel dimensions of the union basis of all monomials of degree
<= D with the number of independent integrals their coordinates carry (gradients mod p): exact evidence, which
is also what a negative result ("no further integral of this degree") rests on. Sources: docs/atlas.md.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Callable, Mapping

from hkproof.dynamics.catalogue import SO4_SPLIT, get_system, kahan_map
from hkproof.budget import Budget
from hkproof.hk.conjugacy import LinearChart, conjugacy_mismatches, pull_back
from hkproof.hk.certified_integrals import jacobian_points
from hkproof.hk.independence import max_jacobian_rank
from hkproof.orchestration.registry import claim, require_proven
from hkproof.pipelines.discover import DiscoveryReport, discover
from hkproof.hk.nambu import prove_nambu, require_claimed
from hkproof.pipelines.darboux import search_darboux
from hkproof.pipelines.poisson import nambu_densities, with_integrals
from hkproof.pipelines.poisson_certificate import poisson_steps
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import recall
from hkproof.theorems._common import nambu_checks

__all__ = ["ENTRIES", "Entry", "GROUP", "prove_integrals", "prove_kernels", "prove_liouville_arnold",
           "prove_nambu_liouville_arnold", "run"]

GROUP = "atlas"


@dataclass(frozen=True)
class Entry:
    """One system of the atlas: where discover runs, and what Liouville integrability needs."""

    system: str
    degree: int
    params: tuple[tuple[str, str], ...]
    liouville: int          # Casimirs + half the rank of the Poisson structure (docs/atlas.md)
    seconds: float = 240.0


ENTRIES: dict[str, Entry] = {}
"""The registered entries by system name."""


@lru_cache(maxsize=None)
def run(entry: Entry) -> DiscoveryReport:
    """discover on one atlas entry, once per process (both claims of the entry read the same report)."""
    return discover(entry.system, entry.degree, params=dict(entry.params), budget=Budget(entry.seconds))


def prove_integrals(cert: Certificate, claimed: Mapping[str, str], entry: Entry) -> None:
    """Integrals found and proven, and their independence, against the claimed number."""
    fixed = dict(entry.params)
    field = get_system(entry.system).specialize(fixed) if fixed else get_system(entry.system)
    kmap = kahan_map(field)
    with cert.step("integrals h o f = h", f"hkproof discover at degree {entry.degree}; each integral proven by exact "
                   "substitution h(N/Delta) - h = 0 (hkproof.hk.integrals) or, as a kernel coordinate of a whole "
                   "HK-basis, by Prop. \"prop: even\" (hkproof.hk.reduced)", kmap.ring, fixed or None) as s:
        report = run(entry)
        cert.notes.append(f"discover at degree {entry.degree}, seconds per stage: "
                          + ", ".join(f"{k} {v:.2f}" for k, v in report.stages.items()) + "; "
                          + "; ".join(report.covered))
        proven = [(i, i.frac) for i in report.integrals if i.frac is not None and i.status >= Status.VERIFIED_SPECIALIZED]
        failed = [i.name for i in report.integrals if i.status == Status.REFUTED]
        s.require(not failed, f"reconstructed candidates {failed} are not integrals")
        for i, frac in proven:
            cert.formula(i.name, frac)
            where = f"the kernel of ({', '.join(i.basis)})" if i.basis else "a conserved coordinate"
            s.note(f"{i.name} from {where}: {i.method}")
        if not report.complete:
            s.note("the time budget ran out: " + "; ".join(report.covered))
    with cert.step("functional independence", "exact Jacobian rank at a rational point", kmap.ring, fixed or None) as s:
        funcs = [frac for i, frac in proven if i.independent]
        rank = max_jacobian_rank(funcs, kmap.variables, jacobian_points(kmap.ring.names))
        s.require(str(rank) == claimed["independent"].strip(),
                  f"{rank} independent integrals proven, the claim says {claimed['independent']}")
        s.note(f"{rank} independent of the {entry.liouville} Liouville integrability needs in dimension "
               f"{len(kmap.variables)}")


def prove_kernels(cert: Certificate, claimed: Mapping[str, str], entry: Entry) -> None:
    """Kernel dimensions of the union bases and the gradient rank of their coordinates: exact evidence."""
    report = run(entry)
    with cert.step("kernels of all monomials of degree <= D", "algorithm (N) mod p at random points; ranks mod p "
                   "bound ranks over Q", "Z/p at random rational points and parameter values") as s:
        dims = ",".join(str(k["new"]) for k in report.kernels)
        s.require(dims == claimed["new_dimensions"],
                  f"new kernel dimensions by degree {dims}, the claim says {claimed['new_dimensions']}")
        s.require(str(report.expected_independent or 0) == claimed["gradient_rank"],
                  f"the kernel coordinates carry {report.expected_independent} independent integrals, the claim "
                  f"says {claimed['gradient_rank']}")
        for k in report.kernels:
            s.note(f"degree {k['degree']}: {k['monomials']} monomials, kernel {k['dimension']} "
                   f"({k['trivial']} trivial, {k['new']} new)")
        s.evidence(Status.EVIDENCE_EXACT, points=len(report.probes))


def _register(entry: Entry, title: str, statement: str, independent: int, new_dimensions: str, gradient_rank: int,
              slow: bool = False) -> None:
    """The two claims of an entry; a negative result (no integral proven) is only the kernels' evidence, with the
    statement, never a "verified" claim."""
    key = entry.system
    fixed = ", ".join(f"{k}={v}" for k, v in entry.params)
    if independent:
        claim(f"atlas-{key}-integrals", GROUP, f"{title}: integrals of the Kahan map",
              "docs/atlas.md; paper sec. 7 (conclusions)",
              statement + (f" (parameters fixed: {fixed})" if fixed else ""),
              claimed={"independent": str(independent)}, slow=slow, shares=f"discover {key}",
              expected=Status.VERIFIED_SPECIALIZED if entry.params else Status.VERIFIED)(
            lambda cert, claimed: prove_integrals(cert, claimed, entry))
    ENTRIES[key] = entry
    kernels = (f"New kernel dimensions by degree 1..{entry.degree}: {new_dimensions}; the kernel coordinates carry "
               f"{gradient_rank} independent integrals (evidence(exact))")
    claim(f"atlas-{key}-kernels", GROUP, f"{title}: kernels of all monomials of degree <= {entry.degree}",
          "docs/atlas.md; algorithm (N)", kernels if independent else f"{statement}. {kernels}",
          claimed={"new_dimensions": new_dimensions, "gradient_rank": str(gradient_rank)}, slow=slow,
          shares=f"discover {key}", expected=Status.EVIDENCE_EXACT)(
        lambda cert, claimed: prove_kernels(cert, claimed, entry))


_register(Entry("volterra-3", 3, (), 2), "Periodic Volterra lattice, N = 3",
          "The Kahan map has 2 functionally independent rational integrals (the linear x1 + x2 + x3 and a deformed "
          "x1 x2 x3), as many as Liouville integrability needs (1 Casimir + 1)", 2, "1,0,1", 2)
_register(Entry("volterra-4", 2, (), 3), "Periodic Volterra lattice, N = 4",
          "The Kahan map has 3 functionally independent rational integrals (the linear sum and deformations of the "
          "Casimirs x1 x3, x2 x4), as many as Liouville integrability needs (2 Casimirs + 1)", 3, "1,2", 3)
_register(Entry("volterra-5", 3, (), 3), "Periodic Volterra lattice, N = 5",
          "Up to degree 3 the Kahan map has only the linear integral x1 + ... + x5: the kernels of all monomials "
          "of degree 2 and 3 consist of its multiples; Liouville integrability would need 3", 1, "1,0,0", 1)
_register(Entry("toda-3", 3, (), 4), "Periodic Toda lattice, N = 3 (Flaschka variables)",
          "Up to degree 3 the Kahan map has only the linear integral b1 + b2 + b3: no deformation of the energy or of "
          "a1 a2 a3 of degree <= 3 survives; Liouville integrability would need 4", 1, "1,0,0", 1)
_register(Entry("kirchhoff", 2, (), 4, seconds=900.0), "Kirchhoff case of a rigid body in "
          "an ideal fluid", "The Kahan map has 4 functionally independent rational integrals proven (the conserved m3, "
          "a deformed quadric ratio by interpolation, and two more from whole HK-bases by Prop. \"prop: even\" with "
          "relations whose right-hand sides are proven integrals), what Liouville integrability needs (2 Casimirs + 2)",
          4, "0,3", 3, slow=True)
_register(Entry("gaudin-2", 2, (), 4, seconds=900.0), "Classical Gaudin magnet, two spins in a field",
          "The Kahan map has 4 functionally independent rational integrals proven (s3 + t3, a deformed quadric "
          "ratio by interpolation, and two more from whole HK-bases by Prop. \"prop: even\"), all that the degree-2 "
          "kernel carries and what Liouville integrability needs (2 Casimirs + 2)", 4, "1,3", 4)
_register(Entry("zhukovsky-volterra-1", 2, (), 2), "Zhukovsky-Volterra gyrostat with one gyrostatic moment",
          "The Kahan map has 2 functionally independent rational integrals (deformations of |x|^2 and of the energy, "
          "both from bases of squares and x1 by Prop. \"prop: even\"), what Liouville integrability needs "
          "(1 Casimir + 1)", 2, "0,2", 2)
_register(Entry("zhukovsky-volterra", 6, (), 2), "Zhukovsky-Volterra gyrostat, beta = (b1, b2, b3)",
          "Up to degree 6 the Kahan map has no rational integral: no monomial basis of degree <= 6 has a kernel at "
          "the sampled parameter values; Liouville integrability would need 2", 0, "0,0,0,0,0,0", 0)
_register(Entry("lagrange-top", 2, (), 4), "Lagrange top",
          "The Kahan map (Kimura-Hirota) has 4 functionally independent rational integrals proven (the conserved m3, "
          "a deformed quadric ratio by interpolation and two from whole HK-bases by Prop. \"prop: even\"), what "
          "Liouville integrability needs (2 Casimirs + 2)", 4, "0,3", 3)
# the commuting flow's integrals have larger coefficients in a_i: its parameters are fixed (verified(specialized));
# the Manakov flow itself is searched in its chart so(3) + so(3) (below), where discover proves all 4
_A_FIXED = (("a1", "1"), ("a2", "2"), ("a3", "3"), ("a4", "5"))
_register(Entry("so4-euler-top-flow2", 2, _A_FIXED, 4, seconds=900.0), "Euler top on so(4), commuting Manakov flow",
          "The Kahan map has 4 functionally independent rational integrals proven, what Liouville integrability "
          "needs (2 Casimirs + 2): a ratio of quadrics by sparse reconstruction and substitution, and three from "
          "three bases of monomials and integrals of the continuous flow solved together (Prop. \"prop: even\" on "
          "the block system)", 4, "0,4", 4, slow=True)
_SPLIT = Entry("so4-euler-top-split", 2, (), 4, seconds=900.0)
_register(_SPLIT, "Euler top on so(4), Manakov case, in the chart so(3) + so(3)",
          "The Kahan map has 4 functionally independent rational integrals proven with b1, b2, b3 symbolic, what "
          "Liouville integrability needs (2 Casimirs + 2): a ratio of quadrics from the basis (u1 v1, u2 v2, u3 v3, "
          "1), two from the basis of the six squares, each by Prop. \"prop: even\" on the whole basis, and a fourth "
          "from three bases of monomials and integrals of the continuous flow solved together (Prop. \"prop: "
          "even\" on the block system)", 4, "0,4", 4, slow=True)


@claim("atlas-so4-euler-top-chart", GROUP, "Euler top on so(4), Manakov case: integrals through the chart "
       "so(3) + so(3)", "docs/atlas.md; hkproof.hk.conjugacy",
       "The Kahan map of so4-euler-top is conjugate to that of so4-euler-top-split by the linear chart u, v of "
       "so(4) = so(3) + so(3) (g o T = T o f exactly, a1..a4 symbolic), so the integrals proven for the split map, "
       "pulled back, are integrals of the so(4) Kahan map: 4 functionally independent ones, what Liouville "
       "integrability needs",
       claimed={"independent": "4"}, slow=True, uses=["atlas-so4-euler-top-split-integrals"])
def _so4_chart(cert: Certificate, claimed: Mapping[str, str]) -> None:
    source = kahan_map("so4-euler-top")
    chart = LinearChart(source, kahan_map(_SPLIT.system), SO4_SPLIT)
    with cert.step("the chart conjugates the Kahan maps", "g(T x) = T f(x) component by component, exact "
                   "(hkproof.hk.conjugacy); the chart is invertible (Jacobian at a point)", source.ring) as s:
        bad = conjugacy_mismatches(chart)
        s.require(not bad, f"g o T != T o f in the components {bad}")
        s.note("chart: " + ", ".join(f"{k} = {v}" for k, v in SO4_SPLIT.items()))
    with cert.step("integrals pulled back", "the integrals of atlas-so4-euler-top-split-integrals, each h o T (one "
                   "compose): h(g(T x)) = h(T f(x)) and h o g = h", source.ring) as s:
        split = require_proven(cert, "atlas-so4-euler-top-split-integrals")
        names = list(split.formulas)
        pulled = pull_back(chart, [recall(split, n, chart.target.ring) for n in names])
        for n, h in zip(names, pulled, strict=True):
            cert.formula(f"{n}_m", h)
            s.note(f"{n} o T: {len(h.num)} + {len(h.den)} terms")
    with cert.step("functional independence", "exact Jacobian rank at a rational point", source.ring) as s:
        rank = max_jacobian_rank(pulled, source.variables, jacobian_points(source.ring.names))
        s.require(str(rank) == claimed["independent"].strip(),
                  f"{rank} independent integrals pulled back, the claim says {claimed['independent']}")
        s.note(f"{rank} of the 4 that Liouville integrability needs in dimension 6")


def prove_liouville_arnold(cert: Certificate, claimed: Mapping[str, str], system: str, degree: int,
                           darboux_degree: int = 4) -> None:
    """Liouville-Arnold integrability for each invariant Poisson structure `poisson` finds (issue 38): invariant,
    Jacobi, rank 2r, n - 2r Casimirs among the proven integrals, r further integrals in involution, all of them
    functionally independent; the re-checkable steps go to `prove --certificate` (checker version 7)."""
    kmap = kahan_map(system)
    n = len(kmap.variables)
    with cert.step("invariant Poisson structures", f"hkproof poisson at degree {degree} (invariance, Jacobi and rank "
                   "exact; hkproof.pipelines.poisson) with the integrals of discover and D among the factors of their "
                   f"denominators{' and of measure' + chr(39) + 's Darboux polynomials' if darboux_degree else ''}",
                   kmap.ring) as s:
        report = with_integrals(kmap, degree, darboux_degree=darboux_degree)
        found = [(k, p) for k, p in enumerate(report.structures) if p.status.is_verified and p.poisson]
        s.require(str(len(found)) == claimed["structures"].strip() and all(str(p.rank) == claimed["rank"].strip()
                                                                           for _, p in found),
                  f"{len(found)} proven Poisson structures of ranks {[p.rank for _, p in found]}, the claim says "
                  f"{claimed['structures']} of rank {claimed['rank']}")
        s.note(f"{len(found)} structures, ranks {[p.rank for _, p in found]}; compatible pairs "
               f"{[(a + 1, b + 1) for a, b, ok in report.compatibility if ok]}")
    involution = dict(report.involution)
    for k, p in found:
        r = (p.rank or 0) // 2
        with cert.step(f"Pi{k + 1}: Casimirs, involution, independence", "Casimirs Pi grad C = 0 and {I, J} = 0 exact; "
                       "functional independence by an exact Jacobian rank at a rational point", kmap.ring) as s:
            s.require(len(p.casimirs) >= n - 2 * r, f"{len(p.casimirs)} Casimirs among the integrals, {n - 2 * r} needed")
            casimirs = [c for _, c in p.casimirs][:n - 2 * r]
            others = [h for name, h in report.integrals if name not in {c for c, _ in p.casimirs}]
            chosen = casimirs + others[:r]
            s.require(k in involution and involution[k].status.is_verified, "involution not proven")
            rank = max_jacobian_rank(chosen, kmap.variables, jacobian_points(kmap.ring.names))
            s.require(len(chosen) == n - r and rank == n - r, f"{rank} independent of the {n - r} needed")
            s.note(f"Casimirs {', '.join(c for c, _ in p.casimirs[:n - 2 * r])}; {r} further integral(s) in involution; "
                   f"Jacobian rank {rank}")
    cert.checks.extend(poisson_steps(kmap, report))


@claim("atlas-euler-top-liouville-arnold", GROUP, "Euler top: the Kahan map is Liouville-Arnold integrable",
       "issue 38; docs/atlas.md, docs/poisson.md; Petrera-Suris 2007 (arXiv 0707.4382)",
       "The Kahan map of the Euler top preserves three pairwise compatible Poisson structures of rank 2 (cubic, found "
       "from the field alone: a bi-Hamiltonian pencil); for each, a proven integral is its Casimir and another is "
       "functionally independent of it (r = 1, involution trivial): Liouville-Arnold integrable for each",
       claimed={"structures": "3", "rank": "2"})
def _euler_top_liouville_arnold(cert: Certificate, claimed: Mapping[str, str]) -> None:
    prove_liouville_arnold(cert, claimed, "euler-top", 3)


@claim("atlas-zhukovsky-volterra-1-liouville-arnold", GROUP,
       "Zhukovsky-Volterra gyrostat (one b): the Kahan map is Liouville-Arnold integrable",
       "issue 38; docs/atlas.md, docs/poisson.md",
       "The Kahan map of the Zhukovsky-Volterra gyrostat with one gyrostatic term preserves four Poisson structures of "
       "rank 2, Q/D with deg Q <= 5 and D the denominator of a proven integral (two compatible ones per denominator, "
       "found from the field alone; none with D = 1); for each, a proven integral is its Casimir and the other is "
       "functionally independent of it (r = 1): Liouville-Arnold integrable for each",
       claimed={"structures": "4", "rank": "2"}, slow=True)
def _zhukovsky_volterra_liouville_arnold(cert: Certificate, claimed: Mapping[str, str]) -> None:
    prove_liouville_arnold(cert, claimed, "zhukovsky-volterra-1", 5, darboux_degree=0)


def prove_nambu_liouville_arnold(cert: Certificate, claimed: Mapping[str, str], system: str, darboux_degree: int
                                 ) -> None:
    """Liouville-Arnold integrability by a Nambu structure (docs/poisson.md): the integrals of the atlas entry, the
    densities of measure, Pi = P W(grad I_1, ..., grad I_(n-2)) proven by hkproof.hk.nambu (rank 2, the n - 2 Casimirs),
    and one further independent integral (r = 1: involution holds for one)."""
    entry = ENTRIES[system]
    kmap = kahan_map(system)
    with cert.step("integrals and densities", f"discover at degree {entry.degree} (each integral by exact "
                   f"substitution); measure at degree {darboux_degree} (P o f = det Df P exact)", kmap.ring) as s:
        report = run(entry)
        found = [(i.name, i.frac, i.status) for i in report.integrals if i.frac is not None]
        densities = nambu_densities(kmap, search_darboux(kmap, darboux_degree))
        s.require(bool(densities), f"measure finds no density of degree <= {darboux_degree}")
        s.note(f"integrals {', '.join(n for n, _, _ in found)}; density 1/({densities[0][0]})")
    for name, h, _ in found:
        cert.formula(name, h)
    structure = prove_nambu(kmap, found, densities[0], cert=cert)
    require_claimed(cert, kmap.ring, structure, claimed, liouville_arnold=True)
    cert.checks += nambu_checks(kmap, report, structure)


def _nambu_prover(system: str) -> Callable[[Certificate, Mapping[str, str]], None]:
    def prove(cert: Certificate, claimed: Mapping[str, str]) -> None:
        prove_nambu_liouville_arnold(cert, claimed, system, 4)
    return prove


for _system, _n, _casimirs in (("volterra-3", 3, 1), ("volterra-4", 4, 2)):
    claim(f"atlas-{_system}-liouville-arnold", GROUP,
          f"{_system}: the Kahan map is Liouville-Arnold integrable (a Nambu structure)",
          "issue 38; docs/atlas.md, docs/poisson.md (Nambu structures); Byrnes-Haggar-Quispel 1999",
          f"With {_casimirs} of its integrals I_k and an invariant density 1/P of measure, Pi = P W(grad I) is an "
          f"invariant Poisson structure of rank 2 in dimension {_n} whose Casimirs are those integrals, and a further "
          "proven integral is independent of them (r = 1, involution trivial): Liouville-Arnold integrable",
          claimed={"rank": "2", "casimirs": str(_casimirs)}, shares=f"discover {_system}")(
        _nambu_prover(_system))
