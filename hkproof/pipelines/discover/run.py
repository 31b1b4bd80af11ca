"""`discover`: from a quadratic field to certified integrals, by the paper's method run end to end.

0. Slice (slices): a translation of the parameters that leaves the field invariant lets the search run with
   a_pivot = 0; what it finds is lifted at the end (one parameter fewer in every reconstruction).
1. Screening (hkproof.pipelines.discover.screen): algorithm (N) mod p on all monomials of degree <= D.
2. Minimal HK-bases (bases, circuits): the circuits of the new part of each kernel.
3. Candidates (candidates): which kernel coordinates carry independent integrals, by gradients mod p.
4. Reconstruction (reconstruct): a dense ansatz on values mod primes, or recipe (E) with Prop. "prop: even".
5. Certification (hkproof.hk.certified_integrals): substitution with every parameter symbolic, independence by an exact
   Jacobian rank. Nothing is called an integral before step 5 says so.
"""
from __future__ import annotations

import time
from typing import Mapping

import flint

from hkproof.algebra.reconstruction import Mapper
from hkproof.algebra.sampling import random_point
from hkproof.algebra.fraction import Frac
from hkproof.algebra.modular import rank_mod_p, residue_or_none
from hkproof.algebra.monomials import count_upto, exponents_upto
from hkproof.algebra.ring import Rational
from hkproof.budget import Budget, check
from hkproof.dynamics.catalogue import get_system, kahan_map
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, ParseError, ResourceLimitError
from hkproof.experiments.scene import Scene, make_scene
from hkproof.hk.certified_integrals import certify, independent_subset, jacobian_points
from hkproof.pipelines.discover.bases import confirm_basis, minimal_bases
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.hamiltonian_seed import seed_modified_hamiltonian
from hkproof.pipelines.discover.integral_bases import prove_with_integral_bases
from hkproof.pipelines.discover.reconstruct import reconstruct_candidates
from hkproof.pipelines.discover.report import DiscoveryReport, FoundIntegral
from hkproof.pipelines.discover.screen import Probe, screen, without_conserved
from hkproof.pipelines.charts import Chart, pull_back_integrals
from hkproof.pipelines.slices import Slice, lift_integrals
from hkproof.pipelines.stages import Progress, Stages
from hkproof.proof.status import Status

__all__ = ["MAX_CONFIRMED", "discover"]

MAX_CONFIRMED = 24          # minimal bases confirmed by algorithm (N) over Q; the rest are listed
MAX_SEARCH_DEGREE = 6
INTEGRAL_BASIS_ROUNDS = 2    # groups of bases with integrals of the flow proven, at most


def discover(system: str | QuadraticField, degree: int = 2, *, params: Mapping[str, Rational] | None = None,
             budget: Budget | None = None, seed: int = 0, progress: Progress | None = None, max_degree: int = 16,
             max_unknowns: int = 2500, mapper: Mapper | None = None, translations: bool = True,
             symmetries: bool = True, charts: bool = True, hamiltonian: bool = True) -> DiscoveryReport:
    """Integrals of the Kahan map of `system` whose HK-bases are monomials of degree <= `degree`, certified; when the
    budget runs out, the report says what was covered ("complete": false). `mapper` runs the batches of probes of
    the sparse reconstruction (e.g. on a process pool); the result does not depend on it. `translations=False`
    searches with every parameter instead of on the slice of the field's parameter translations, `symmetries=False`
    rebuilds every block of step 5d instead of carrying blocks by symmetries of the field, `charts=False` searches in
    the coordinates given instead of the chart of the field's affine normal form, `hamiltonian=False` does not seed the
    modified Hamiltonian of a field F = J grad H (comparisons)."""
    if not 1 <= degree <= MAX_SEARCH_DEGREE:
        raise ParseError(f"the degree of the basis monomials must be between 1 and {MAX_SEARCH_DEGREE}, got {degree}")
    base = get_system(system) if isinstance(system, str) else system
    unknown = sorted(set(params or {}) - set(base.parameters))
    if unknown:
        raise ParseError(f"{unknown} are not parameters of {base.name} ({list(base.parameters)})")
    fixed = base.check_values(params or {})
    original = base.specialize(fixed) if fixed else base
    report = DiscoveryReport(base.name, list(original.variables), list(original.parameters), degree,
                             {k: str(v) for k, v in fixed.items()})
    stages = Stages("discover", progress)
    stages.started = report.started
    budget = budget or Budget(None)
    chart = None
    if charts:
        try:
            chart = Chart.of(original)
        except ResourceLimitError as exc:      # the budget ran out before the search: it runs in the chart given
            report.covered.append(f"no normal form sought ({exc})")
    if chart is not None:
        report.chart = chart
        report.covered.append(chart.describe())
        stages.say(chart.describe())
    in_chart = chart.searched if chart is not None else original
    where = Slice.of(in_chart) if translations else Slice(in_chart, in_chart, ())
    if where.shifts:
        report.on_slice = where
        report.covered.append(where.describe())
    report.searched = where.searched
    full_map = kahan_map(where.searched)
    field, conserved = without_conserved(where.searched)
    kmap = kahan_map(field)
    ctx = SearchContext.for_maps(kmap, full_map, fixed=fixed, seed=seed, budget=budget, stages=stages,
                                 max_degree=max_degree, max_unknowns=max_unknowns, mapper=mapper,
                                 symmetries=symmetries, hamiltonian=hamiltonian)
    with budget.active():
        _run(ctx, report, conserved, kahan_map(in_chart) if where.shifts else full_map, kahan_map(original))
    return report


def _run(ctx: SearchContext, report: DiscoveryReport, conserved: list[str], target: KahanMap, given: KahanMap) -> None:
    """The stages of discover, stopped cleanly by a limit (the report says what was covered); the integrals are
    lifted from the slice (if the search ran on one) to `target`, the map of the chart searched, and pulled back
    from that chart (if it is not the user's) to `given`, the map of the system asked for; their independence is
    decided in the chart (y = T x + c with det T != 0 multiplies each Jacobian by T), again in the user's chart only
    if a pull-back lost its proof."""
    try:
        report.integrals += _conserved(ctx.full_map, conserved, ctx.fixed)
        report.conserved += conserved
        if len(conserved) == len(ctx.full_map.variables):
            report.covered.append("every coordinate is conserved")
            return
        _search(ctx, report)
    except ResourceLimitError as exc:         # the budget ran out, or a limit stopped a stage: what was covered stays
        report.complete = False
        report.covered.append(str(exc))
    finally:
        if report.on_slice is not None:
            lift_integrals(report, report.on_slice, target, ctx.stages)
        if report.chart is not None:         # an affine bijection keeps Jacobian ranks: counted in the chart, where
            _independence(report, target, ctx.stages)          # the integrals are smaller
            pull_back_integrals(report, report.chart, given, ctx.stages)
        if report.chart is None or any(i.independent and i.status < Status.VERIFIED_SPECIALIZED
                                       for i in report.integrals):
            _independence(report, given, ctx.stages)
        ctx.stages.stop()
        report.stages = ctx.stages.seconds


def _conserved(kmap: KahanMap, conserved: list[str], fixed: Mapping[str, flint.fmpq]) -> list[FoundIntegral]:
    """Conserved coordinates (x_i' = 0) are integrals, proven by the same substitution (named conserved_<x_i> in
    their certificates: a conclusion cannot take a variable's name)."""
    out = []
    for v in conserved:
        start = time.perf_counter()
        h = Frac.parse(kmap.ring, v)
        cert = certify(kmap, h, fixed, f"conserved_{v}")
        out.append(FoundIntegral(v, h, cert.status, "conserved coordinate", [], v, time.perf_counter() - start,
                                 cert.steps[-1].detail or cert.error, certificate=cert))
    return out


def _search(ctx: SearchContext, report: DiscoveryReport) -> None:
    """The modified Hamiltonian when the field has one (hamiltonian_seed); then screen, find minimal bases and
    candidates, confirm the bases, reconstruct and certify."""
    kmap, rng, stages = ctx.kmap, ctx.rng, ctx.stages
    if ctx.hamiltonian:
        seed_modified_hamiltonian(ctx, report)
    n = len(kmap.variables)
    degree = report.degree
    stages.start("screening", f"screening monomials of degree <= {degree} mod p (algorithm (N))")
    # each probe at its own generic scene: normalized names 1 (as in reconstruction), the others random. A kernel is
    # never smaller at special parameter values (a drawn value equal to a fixed one, two equal ones) than at generic
    # ones, so the smallest kernel is the generic one; one scene for all probes could be special for all of them.
    screens = [_screened(ctx, n, degree) for _ in range(2)]
    if len(screens[0][2].kernels[degree]) != len(screens[1][2].kernels[degree]):
        screens.append(_screened(ctx, n, degree))
    values, scene, probe = min(screens, key=lambda sc: len(sc[2].kernels[degree]))
    report.probes = [{"prime": pr.p, "point": [str(v) for v in pr.point],
                      "values": {k: str(v) for k, v in vals.items()},
                      "dimensions": {d: len(k) for d, k in pr.kernels.items()}} for vals, _, pr in screens]
    new_degrees = []
    for d in range(1, degree + 1):
        dim, triv = len(probe.kernels[d]), probe.trivial_rank[d]
        report.kernels.append({"degree": d, "monomials": count_upto(n, d), "dimension": dim, "trivial": triv,
                               "new": dim - triv, "verdict": probe.verdict[d]})
        if dim > triv:
            new_degrees.append(d)
    report.covered.append(f"screened all {count_upto(n, degree)} monomials of degree <= {degree} "
                          f"at {len(screens)} points mod p, each at its own parameter values (the smallest kernel at "
                          f"{', '.join(f'{k}={v}' for k, v in values.items())})")
    if not new_degrees:
        report.negative = (f"no non-zero polynomial of degree <= {degree} in {', '.join(kmap.variables)} vanishes on "
                           f"the first {count_upto(n, degree) + 3} points of an orbit (exact: the rank "
                           "mod p bounds the rank over Q), so there is no integral P/Q with deg P, deg Q <= "
                           f"{degree} at these parameter values: evidence(exact)")
        stages.say(report.negative)
        return

    stages.start("minimal bases", "minimal HK-bases (circuits of the kernel)")
    found = minimal_bases(ctx, probe, new_degrees)
    report.bases += found.bases
    report.trivial += found.trivial
    report.covered += found.covered
    candidates = found.candidates
    # how many independent integrals the kernels carry (gradients mod p), and which coordinates show them
    chosen_rank = rank_mod_p([c.gradient for c in candidates], probe.p) if candidates else 0
    report.expected_independent = chosen_rank
    seeded = _proven_gradients(ctx, report, probe, values)      # the modified Hamiltonian, when it was seeded
    target = rank_mod_p([c.gradient for c in candidates] + seeded, probe.p) if candidates or seeded else 0
    stages.say(f"{len(report.bases)} minimal HK-bases; their kernel coordinates carry {chosen_rank} independent "
               "integrals (gradients mod p)")

    stages.start("confirm bases", "confirming the minimal HK-bases by algorithm (N)")
    for k, entry in enumerate(report.bases):
        check("confirming every minimal HK-basis")
        entry.update(confirm_basis(scene, [Frac.parse(kmap.ring, t) for t in entry["basis"]])
                     if k < MAX_CONFIRMED else
                     {"dimension": None, "status": Status.UNKNOWN.label, "check": "not confirmed (cap)"})

    done = reconstruct_candidates(ctx, report, candidates, target, probe.p, seeded)
    report.skipped += done.skipped
    report.covered.append(done.covered)
    _with_integral_bases(ctx, report, probe, new_degrees, target)


def _screened(ctx: SearchContext, n: int, degree: int) -> tuple[dict[str, flint.fmpq], Scene, Probe]:
    """Algorithm (N) at a random phase point of a random scene (the normalized names 1, the free ones random)."""
    values = {m: flint.fmpq(1) for m in ctx.weights.normalized}
    values.update(random_point(ctx.rng, ctx.free, 29))
    scene = make_scene(ctx.kmap, values)
    return values, scene, screen(scene, n, degree, ctx.rng)


def _proven_gradients(ctx: SearchContext, report: DiscoveryReport, probe, values: Mapping[str, flint.fmpq]
                      ) -> list[list[int]]:
    """Independent gradients mod p, at the probe's point, of the integrals proven before the search (the seeded
    modified Hamiltonian): kernel coordinates that depend on them are not proven again."""
    ring, p = ctx.kmap.ring, probe.p
    at = dict(zip(ctx.kmap.variables, probe.point, strict=True)) | dict(values)
    point: list[int] = []
    for name in ring.names:
        r = residue_or_none(at[name], p)
        if r is None:                    # p divides a denominator of the point: no gradient to skip with
            return []
        point.append(r)
    phase = [ring.index(v) for v in ctx.kmap.variables]
    out: list[list[int]] = []
    for found in report.integrals:
        if found.frac is None or found.status < Status.VERIFIED_SPECIALIZED or \
                not set(found.frac.variables()) <= set(ring.names):
            continue
        g = found.frac.to_ring(ring).mod_p(p).gradient(point, phase)
        if g is not None and rank_mod_p(out + [g], p) > len(out):
            out.append(g)
    return out


def _with_integral_bases(ctx: SearchContext, report: DiscoveryReport, probe, degrees: list[int], target: int) -> None:
    """The last stage, when the kernels carry more integrals than are proven: bases with integrals of the continuous
    flow, solved together (hkproof.pipelines.discover.integral_bases)."""
    n = len(ctx.kmap.variables)
    for _ in range(INTEGRAL_BASIS_ROUNDS):
        known = {i.name: i.frac.to_ring(ctx.kmap.ring) for i in report.integrals
                 if i.frac is not None and i.status >= Status.VERIFIED_SPECIALIZED
                 and set(i.frac.variables()) <= set(ctx.kmap.ring.names)}
        if len(independent_subset(list(known.values()), list(ctx.kmap.variables),
                                  jacobian_points(ctx.kmap.ring.names))) >= target:
            return
        d = max(degrees)
        monos = exponents_upto(n, d)
        support = [monos[j] for j in range(len(monos)) if any(v[j] for v in probe.kernels[d])]
        try:
            found = prove_with_integral_bases(ctx, support, known, d, len(report.integrals) + 1)
        except ResourceLimitError:
            raise
        except HKProofError as exc:          # an unlucky prime or point, a reconstruction that failed: not an answer
            report.covered.append(f"bases with integrals of the continuous flow: stopped ({exc})")
            return
        report.integrals += found
        proven = sum(i.status >= Status.VERIFIED_SPECIALIZED for i in found)
        report.covered.append(f"bases with integrals of the continuous flow: {proven} new independent integrals "
                              "proven" + (f", {len(found) - proven} candidates only checked at random exact points "
                                          "(the budget stopped their proof)" if len(found) > proven else ""))
        if len(found) > proven:              # the budget stopped a proof: what is reported is not all it could be
            report.complete = False
        if not proven:
            return


def _independence(report: DiscoveryReport, full_map: KahanMap, stages: Stages) -> None:
    """Mark a maximal set of verified integrals with an exact full-rank Jacobian as independent."""
    stages.start("independence", "functional independence (exact Jacobian rank)")
    proven = [i for i in report.integrals if i.status >= Status.VERIFIED_SPECIALIZED and i.frac is not None]
    chosen = independent_subset([i.frac for i in proven if i.frac is not None], list(full_map.variables),
                                jacobian_points(full_map.ring.names))
    for k, i in enumerate(proven):
        i.independent = k in chosen
    for i in report.integrals:
        if i.independent is None:
            i.independent = False
