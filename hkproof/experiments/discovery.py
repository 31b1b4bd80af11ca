"""`discover`: from a quadratic field to certified integrals, by the paper's method run end to end.

1. Screening, algorithm (N) mod p on the union basis Phi_D of all monomials of degree <= D (paper, sec. 4): the
   kernel K_Phi(x) = polynomials of degree <= D vanishing on the orbit. Products of a lower-degree kernel with
   monomials (trivial inflation) are split off degree by degree. A kernel of dimension 0 mod p is exact: the
   rank over Q is at least the rank mod p.
2. Minimal HK-bases: the minimal supports (circuits) of K_Phi(x); each has a one-dimensional kernel, confirmed
   by algorithm (N) mod two primes and once over Q. This replaces a search over subsets of monomials.
3. Which kernel coordinates c_k (recipe (B), last coordinate -1) carry independent integrals: their
   gradients mod p, from the orbit's tangent map (M(x) dx~ + dM x~ = db, eq. "Kahan gen" differentiated).
4. Reconstruction of each chosen c_k as P/Q from exact values (hkproof.experiments.reconstruction), eps and
   the parameters that scaling symmetries allow set to 1 while sampling and restored exactly afterwards.
5. Certification (hkproof.hk.discover): substitution with every parameter symbolic, independence by an exact
   Jacobian rank. Nothing is called an integral before step 5 says so.
"""
from __future__ import annotations

import itertools
import math
import random
import sys
import time
from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational, Ring, to_fmpq
from hkproof.dynamics.catalogue import get_system, kahan_map
from hkproof.dynamics.field import EPS, QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, ParseError, SingularPointError
from hkproof.experiments.arithmetics import ExactQ, pivot_columns
from hkproof.experiments.modular import ModP, UnluckyPrimeError, random_prime
from hkproof.experiments.profiles import HK_BASIS, ProfileProblem, fundamental_finite, kernel_vector
from hkproof.experiments.scene import Scene, make_scene
from hkproof.experiments.weights import Weights, scaling_weights
from hkproof.experiments.relations import find_relations
from hkproof.hk.discover import (DiscoveryReport, FoundIntegral, certify, independent_subset, is_phase_constant,
                                 jacobian_points, solve_by_evenness)
from hkproof.hk.reduced import Relation
from hkproof.experiments.reconstruction import (dense_size, kernel_mod_p, line_degrees, monomials_upto,
                                                reconstruct_rational, univariate_degrees)
from hkproof.proof.status import Status

Exponents = tuple[int, ...]
MAX_CIRCUIT_TRIALS = 20000
FULL_CIRCUITS = 5000        # above this many trials, circuits are sought in a complement of the trivial part
MAX_CONFIRMED = 24          # minimal bases confirmed by algorithm (N) over Q; the rest are listed
MAX_RELATION_BASIS = 8      # recipe (E) is tried on minimal bases of at most this many functions


class BudgetExhausted(HKProofError):
    """The time budget (--seconds) ran out; the report says what was covered."""


# ---- fields, monomials ----------------------------------------------------------------------------------------
def without_conserved(field: QuadraticField) -> tuple[QuadraticField, list[str]]:
    """Conserved coordinates (x_i' = 0, so x~_i = x_i) become parameters: they would only inflate the kernels."""
    conserved = [v for v, f in zip(field.variables, field.rhs, strict=True) if f.is_zero()]
    if not conserved or len(conserved) == len(field.variables):
        return field, conserved
    keep = [i for i, v in enumerate(field.variables) if v not in conserved]
    return QuadraticField(field.name + "[moving]", tuple(field.variables[i] for i in keep),
                          field.parameters + tuple(conserved), tuple(field.rhs_text[i] for i in keep),
                          field.description, field.step), conserved


def monomial_exponents(n: int, degree: int) -> list[Exponents]:
    """All monomials of degree <= D in n variables, highest degree first, the constant 1 last."""
    return monomials_upto(n, degree)


def monomial_frac(ring: Ring, variables: Sequence[str], e: Exponents) -> Frac:
    full = [0] * len(ring.names)
    for v, k in zip(variables, e, strict=True):
        full[ring.index(v)] = k
    return Frac(ring, ring.ctx.from_dict({tuple(full): 1}))


def monomial_text(variables: Sequence[str], e: Exponents) -> str:
    parts = [v if k == 1 else f"{v}**{k}" for v, k in zip(variables, e, strict=True) if k]
    return "*".join(parts) or "1"


# ---- modular orbits with tangent maps -------------------------------------------------------------------------
class ModularOrbit:
    """The orbit x, f(x), ... mod p and the Jacobians D(f^i)(x) (for gradients of kernel coordinates)."""

    def __init__(self, scene: Scene, point: Sequence[flint.fmpq], p: int, steps: int):
        self.p = p
        arith = ModP(p)
        m0, mk, b0, bmat = arith.prepare(scene, []).matrices
        n = len(point)
        x = [arith.number(v) for v in point]
        jac = flint.nmod_mat([[int(i == j) for j in range(n)] for i in range(n)], p)
        self.points, self.jacobians = [x], [jac]
        for i in range(steps):
            m = m0
            for k, v in enumerate(x):
                if v:
                    m = m + mk[k] * v
            col = flint.nmod_mat([[v] for v in x], p)
            try:
                xt = m.solve(b0 + bmat * col)
            except ZeroDivisionError:
                raise UnluckyPrimeError(f"det M = 0 mod {p} at step {i + 1}") from None
            dm = flint.nmod_mat([[int((mk[j] * xt)[r, 0]) for j in range(n)] for r in range(n)], p)
            df = m.solve(bmat - dm)
            x = [int(xt[r, 0]) for r in range(n)]
            jac = df * jac
            self.points.append(x)
            self.jacobians.append(jac)

    def value(self, e: Exponents, i: int) -> int:
        v = 1
        for x, k in zip(self.points[i], e, strict=True):
            if k:
                v = v * pow(x, k, self.p) % self.p
        return v

    def gradient(self, e: Exponents, i: int) -> list[int]:
        """d/dx of phi(f^i(x)) for the monomial phi = x^e: grad phi at f^i(x) times D(f^i)(x)."""
        n = len(e)
        g = []
        for j in range(n):
            if not e[j]:
                g.append(0)
                continue
            lower = list(e)
            lower[j] -= 1
            x = self.points[i]
            v = e[j]
            for xx, k in zip(x, lower, strict=True):
                if k:
                    v = v * pow(xx, k, self.p) % self.p
            g.append(v)
        row = flint.nmod_mat([g], self.p) * self.jacobians[i]
        return [int(row[0, j]) for j in range(n)]


def rank_mod(rows: list[list[int]], p: int) -> int:
    return flint.nmod_mat(rows, p).rank() if rows else 0


# ---- the screening stage --------------------------------------------------------------------------------------
@dataclass
class Probe:
    """One random point and prime: the orbit mod p and the kernels of Phi_D' for D' = 1..D."""

    point: list[flint.fmpq]
    orbit: ModularOrbit
    kernels: dict[int, list[list[int]]]
    trivial_rank: dict[int, int]
    verdict: dict[int, str]

    @property
    def p(self) -> int:
        return self.orbit.p


def screen(scene: Scene, n: int, degree: int, rng: random.Random, extra: int = 3) -> Probe:
    """Kernels of the union bases at one random point mod one random prime (algorithm (N), exact in the sense
    that a rank mod p is a lower bound of the rank over Q)."""
    monos = {d: monomial_exponents(n, d) for d in range(1, degree + 1)}
    top = len(monos[degree])
    for _ in range(8):
        point = [to_fmpq(rng.choice([-1, 1]) * rng.randint(1, 99)) / rng.randint(1, 97) for _ in range(n)]
        p = random_prime(rng)
        try:
            orbit = ModularOrbit(scene, point, p, top + extra - 1)
        except UnluckyPrimeError:
            continue
        kernels, trivial, verdict = {}, {}, {}
        for d, ms in monos.items():
            rows = [[orbit.value(e, i) for e in ms] for i in range(len(ms) + extra)]
            prefix = ModP(p).prefix_ranks(rows[:len(ms)])[0]
            verdict[d] = fundamental_finite(prefix)[0]
            kernels[d] = kernel_mod_p(rows, p)
            trivial[d] = rank_mod(_products(kernels.get(d - 1, []), monos.get(d - 1, []), ms, n), p)
        return Probe(point, orbit, kernels, trivial, verdict)
    raise SingularPointError("eight random orbits met det M = 0 mod p: the map looks singular on the whole space")


def _products(kernel: list[list[int]], lower: list[Exponents], monos: list[Exponents],
              n: int) -> list[list[int]]:
    """Coefficient vectors of m * v for v in a kernel of degree D-1 and m in {1, x_1, ..., x_n} (trivial part)."""
    index = {e: i for i, e in enumerate(monos)}
    shifts = [tuple(0 for _ in range(n))] + [tuple(int(i == j) for i in range(n)) for j in range(n)]
    out = []
    for v in kernel:
        for s in shifts:
            w = [0] * len(monos)
            for e, c in zip(lower, v, strict=True):
                if c:
                    w[index[tuple(a + b for a, b in zip(e, s, strict=True))]] = c
            out.append(w)
    return out


def complement_of_trivial(kernel: list[list[int]], trivial: list[list[int]], monos: list[Exponents],
                          p: int) -> tuple[list[list[int]], list[int]]:
    """The kernel vectors vanishing on the pivot columns Z of the trivial part T (a complement of T), and Z.

    Z is chosen among the monomials with the highest powers of the last variables, so that a linear integral
    L = ... + x_n eliminates x_n: what is left are the polynomials free of the eliminated monomials."""
    if not trivial or rank_mod(trivial, p) == 0:
        return kernel, []
    order = sorted(range(len(monos)), key=lambda j: tuple(reversed(monos[j])), reverse=True)
    r, rank = flint.nmod_mat([[t[j] for j in order] for t in trivial], p).rref()
    pivots = [order[j] for j in pivot_columns(r, rank)]
    lam = kernel_mod_p([[v[j] for v in kernel] for j in pivots], p)
    return [[sum(l[i] * kernel[i][j] for i in range(len(kernel))) % p for j in range(len(monos))]
            for l in lam], sorted(pivots)


def circuits(kernel: list[list[int]], p: int, cap: int = MAX_CIRCUIT_TRIALS) -> tuple[list[tuple[int, ...]], bool]:
    """The minimal supports of the kernel's non-zero vectors (each is a minimal HK-basis), and whether the
    enumeration was complete (it stops after `cap` trials)."""
    d = len(kernel)
    if d == 0:
        return [], True
    support = [j for j in range(len(kernel[0])) if any(v[j] for v in kernel)]
    supports: set[tuple[int, ...]] = set()
    complete = True
    for trials, zeros in enumerate(itertools.combinations(support, d - 1)):
        if trials >= cap:
            complete = False
            break
        if d == 1:
            lam = [[1]]
        else:
            sub = [[v[j] for v in kernel] for j in zeros]        # (d-1) x d: lam . columns = 0
            lam = kernel_mod_p(sub, p)
            if len(lam) != 1:
                continue
        vec = [sum(lam[0][i] * kernel[i][j] for i in range(d)) % p for j in range(len(kernel[0]))]
        supports.add(tuple(j for j, c in enumerate(vec) if c))
    minimal = [s for s in supports if not any(set(t) < set(s) for t in supports)]
    return sorted(minimal, key=lambda s: (len(s), s)), complete


# ---- candidate integrals: kernel coordinates and their gradients mod p ----------------------------------------
@dataclass
class Candidate:
    """The ratio c_k / c_j of two coordinates of the kernel of a minimal HK-basis (an integral: K_Phi(x) is
    one-dimensional); j = l - 1 is recipe (B)'s normalization c_l = -1, up to sign."""

    basis: list[Exponents]
    k: int
    gradient: list[int]
    norm: int = -1
    estimate: int = 0            # unknowns of its dense ansatz, from degrees along one line mod p


    @property
    def j(self) -> int:
        return self.norm % len(self.basis)


def recipe_b_mod_p(orbit: ModularOrbit, basis: list[Exponents]) -> tuple[flint.nmod_mat, list[int]] | None:
    """(A, c) with A c = b: sum_k c_k phi_k(f^i x) = phi_l(f^i x), i = 0..l-2 (eq. "smaller system") mod p."""
    p, l = orbit.p, len(basis)
    a = flint.nmod_mat([[orbit.value(e, i) for e in basis[:-1]] for i in range(l - 1)], p)
    b = flint.nmod_mat([[orbit.value(basis[-1], i)] for i in range(l - 1)], p)
    try:
        c = a.solve(b)
    except ZeroDivisionError:
        return None
    return a, [int(c[k, 0]) for k in range(l - 1)]


def coordinate_gradients(orbit: ModularOrbit, basis: list[Exponents]) -> list[list[int]] | None:
    """Gradients mod p of the kernel coordinates c_1..c_(l-1) of recipe (B), by the orbit's tangent maps."""
    solved = recipe_b_mod_p(orbit, basis)
    if solved is None:
        return None
    a, cs = solved
    p = orbit.p
    g = []
    for i in range(len(basis) - 1):
        row = orbit.gradient(basis[-1], i)
        for ck, e in zip(cs, basis[:-1], strict=True):
            if ck:
                gk = orbit.gradient(e, i)
                row = [(r - ck * q) % p for r, q in zip(row, gk, strict=True)]
        g.append(row)
    dc = a.solve(flint.nmod_mat(g, p))
    return [[int(dc[k, j]) for j in range(dc.ncols())] for k in range(len(basis) - 1)]


def ratio_candidates(orbit: ModularOrbit, basis: list[Exponents], j: int) -> list[Candidate]:
    """The ratios c_k / c_j, k != j, with their gradients mod p (quotient rule on recipe (B)'s coordinates)."""
    grads = coordinate_gradients(orbit, basis)
    solved = recipe_b_mod_p(orbit, basis)
    if grads is None or solved is None:
        return []
    p, n = orbit.p, len(orbit.points[0])
    c = solved[1] + [p - 1]
    g = grads + [[0] * n]
    if c[j] == 0:
        return []
    inv = pow(c[j], -2, p)
    return [Candidate(basis, k, [(gk * c[j] - c[k] * gj) * inv % p for gk, gj in zip(g[k], g[j], strict=True)], j)
            for k in range(len(basis)) if k != j]


def normalizations(kmap: KahanMap, basis: list[Exponents], weights: Weights, free: list[str], p: int,
                   rng: random.Random, nvars: int, max_degree: int = 12) -> list[tuple[int, dict[int, int]]]:
    """Recipe (B)'s normalization j = l - 1 and the coordinate j whose ratios c_k / c_j have the smallest dense
    ansatzes, with the size of each ratio's ansatz, from degrees along one random line (values mod p). A special
    line or prime only lowers degrees, so a size above the limit is a safe reason to skip."""
    names = list(free) + list(kmap.variables)
    a = [flint.fmpq(rng.randint(-30, 30) or 1, rng.randint(1, 30)) for _ in names]
    b = [flint.fmpq(rng.randint(-30, 30) or 1, rng.randint(1, 30)) for _ in names]
    sample = _modular_sampler(kmap, basis, None, weights, free, p)
    ts: list[int] = []
    vecs: list = []
    for t in range(1, 4 * max_degree + 20):
        if len(ts) >= 2 * max_degree + 5:
            break
        pt = dict(zip(names, (x + t * y for x, y in zip(a, b, strict=True)), strict=True))
        v = sample({m: pt[m] for m in free}, [{m: pt[m] for m in kmap.variables}])[0]
        if v is not None and all(v):
            ts.append(t)
            vecs.append(v)
    l = len(basis)
    options = []
    for j in range(l - 1, -1, -1):
        sizes = {}
        for k in range(l):
            if k != j:
                deg = univariate_degrees(ts, [v[k] * pow(v[j], -1, p) % p for v in vecs], p, max_degree)
                sizes[k] = 10**9 if deg is None else dense_size(nvars, deg)
        options.append((sum(sorted(sizes.values())[:max(1, len(sizes) // 2)]), j, sizes))   # the simpler half
    best = min(options, key=lambda o: o[0])
    return [(options[0][1], options[0][2])] + ([(best[1], best[2])] if best[1] != l - 1 else [])


# ---- weights ---------------------------------------------------------------------------------------------------
def restore_weights(h: Frac, weights: Weights, weight: Sequence[flint.fmpq]) -> Frac | None:
    """h sampled with the normalized names set to 1, made weighted homogeneous of `weight` again (None if no
    integer exponents do it)."""
    if not weights.normalized:
        return h
    ring = h.ring
    names = ring.names
    terms = []
    for which, poly in (("num", h.num), ("den", h.den)):
        for m, c in poly.to_dict().items():
            terms.append((which, {n: e for n, e in zip(names, m, strict=True) if e}, c))
    den_terms = [t for t in terms if t[0] == "den"]
    base = weights.of_monomial(den_terms[0][1])
    targets = {"den": base, "num": [a + b for a, b in zip(base, weight, strict=True)]}
    extra = []
    for which, exps, _ in terms:
        e = weights.restore(exps, [flint.fmpq(0)] * len(base), targets[which])
        if e is None or any(v.q != 1 for v in e.values()):
            return None
        extra.append(e)
    shift = {n: min(int(e.get(n, 0)) for e in extra) for n in weights.normalized}
    data: dict[str, dict] = {"num": {}, "den": {}}
    for (which, exps, c), e in zip(terms, extra, strict=True):
        mono = [0] * len(names)
        for n, v in exps.items():
            mono[ring.index(n)] += v
        for n in weights.normalized:
            mono[ring.index(n)] += int(e.get(n, 0)) - shift[n]
        data[which][tuple(mono)] = c
    return Frac(ring, ring.ctx.from_dict(data["num"]), ring.ctx.from_dict(data["den"]))


# ---- the pipeline ---------------------------------------------------------------------------------------------
class _Clock:
    def __init__(self, report: DiscoveryReport, seconds: float, progress: bool):
        self.report, self.deadline, self.progress = report, time.perf_counter() + seconds, progress
        self.stage_start = time.perf_counter()
        self.stage = ""

    def start(self, stage: str, message: str = "") -> None:
        self.stop()
        self.stage, self.stage_start = stage, time.perf_counter()
        self.say(message or stage)

    def stop(self) -> None:
        if self.stage:
            self.report.stages[self.stage] = self.report.stages.get(self.stage, 0.0) + \
                time.perf_counter() - self.stage_start
            self.stage = ""

    def say(self, message: str) -> None:
        if self.progress:
            print(f"discover: {message} ({time.perf_counter() - self.report.started:.1f} s)", file=sys.stderr,
                  flush=True)

    def check(self, what: str) -> None:
        if time.perf_counter() > self.deadline:
            self.report.complete = False
            raise BudgetExhausted(f"time budget exhausted before {what}")


def discover(system: str | QuadraticField, degree: int = 2, *, params: Mapping[str, Rational] | None = None,
             seconds: float = 300.0, seed: int = 0, progress: bool = False, max_degree: int = 16,
             max_unknowns: int = 2500) -> DiscoveryReport:
    """Integrals of the Kahan map of `system` whose HK-bases are monomials of degree <= `degree`, certified."""
    if not 1 <= degree <= 6:
        raise ParseError(f"--degree must be between 1 and 6, got {degree}")
    base = get_system(system) if isinstance(system, str) else system
    unknown = sorted(set(params or {}) - set(base.parameters))
    if unknown:
        raise ParseError(f"{unknown} are not parameters of {base.name} ({list(base.parameters)})")
    fixed = base.check_values(params or {})
    original = base.specialize(fixed) if fixed else base
    report = DiscoveryReport(base.name, list(original.variables), list(original.parameters), degree,
                             {k: str(v) for k, v in fixed.items()})
    clock = _Clock(report, seconds, progress)
    full_map = kahan_map(original)
    field, conserved = without_conserved(original)
    rng = random.Random(seed)
    try:
        _conserved(report, full_map, conserved, fixed)
        if len(conserved) == len(original.variables):
            report.covered.append("every coordinate is conserved")
            return report
        _search(report, field, full_map, fixed, degree, rng, clock, max_degree, max_unknowns)
    except BudgetExhausted as exc:
        report.covered.append(str(exc))
    finally:
        _independence(report, full_map, clock)
        clock.stop()
    return report


def _independence(report: DiscoveryReport, full_map: KahanMap, clock: _Clock) -> None:
    """Mark a maximal set of verified integrals with an exact full-rank Jacobian as independent."""
    clock.start("independence", "functional independence (exact Jacobian rank)")
    proven = [i for i in report.integrals if i.status >= Status.VERIFIED_SPECIALIZED and i.frac is not None]
    chosen = independent_subset([i.frac for i in proven if i.frac is not None], list(full_map.variables),
                                jacobian_points(full_map.ring.names))
    for k, i in enumerate(proven):
        i.independent = k in chosen
    for i in report.integrals:
        if i.independent is None:
            i.independent = False


def _conserved(report: DiscoveryReport, kmap: KahanMap, conserved: list[str], fixed) -> None:
    for v in conserved:
        start = time.perf_counter()
        h = Frac.parse(kmap.ring, v)
        status, method = certify(kmap, h, fixed)
        report.conserved.append(v)
        report.integrals.append(FoundIntegral(v, h, status, "conserved coordinate", [], v,
                                              time.perf_counter() - start, method))


def _search(report: DiscoveryReport, field: QuadraticField, full_map: KahanMap, fixed, degree: int,
            rng: random.Random, clock: _Clock, max_degree: int, max_unknowns: int) -> None:
    kmap = kahan_map(field)
    n = len(field.variables)
    weights = scaling_weights(kmap)
    free = [m for m in (EPS,) + field.parameters if m not in weights.normalized]
    # a generic scene: normalized names 1 (as in reconstruction), the others random
    values = {m: flint.fmpq(1) for m in weights.normalized}
    values.update({m: to_fmpq(rng.choice([-1, 1]) * rng.randint(2, 29)) / rng.randint(2, 31) for m in free})
    scene = make_scene(kmap, values)

    clock.start("screening", f"screening monomials of degree <= {degree} mod p (algorithm (N))")
    probes = [screen(scene, n, degree, rng), screen(scene, n, degree, rng)]
    dims = [len(pr.kernels[degree]) for pr in probes]
    if dims[0] != dims[1]:
        probes.append(screen(scene, n, degree, rng))
    probe = min(probes, key=lambda pr: len(pr.kernels[degree]))
    report.probes = [{"prime": pr.p, "point": [str(v) for v in pr.point],
                      "dimensions": {d: len(k) for d, k in pr.kernels.items()}} for pr in probes]
    new_degrees = []
    for d in range(1, degree + 1):
        dim, triv = len(probe.kernels[d]), probe.trivial_rank[d]
        report.kernels.append({"degree": d, "monomials": len(monomial_exponents(n, d)), "dimension": dim,
                               "trivial": triv, "new": dim - triv, "verdict": probe.verdict[d]})
        if dim > triv:
            new_degrees.append(d)
    report.covered.append(f"screened all {len(monomial_exponents(n, degree))} monomials of degree <= {degree} "
                          f"at {len(probes)} points mod p (values {', '.join(f'{k}={v}' for k, v in values.items())})")
    if not new_degrees:
        report.negative = (f"no non-zero polynomial of degree <= {degree} in {', '.join(field.variables)} vanishes on "
                           f"the first {len(monomial_exponents(n, degree)) + 3} points of an orbit (exact: the rank "
                           "mod p bounds the rank over Q), so there is no integral P/Q with deg P, deg Q <= "
                           f"{degree} at these parameter values: evidence(exact)")
        clock.say(report.negative)
        return

    # minimal HK-bases at each degree that adds new kernel dimensions
    clock.start("minimal bases", "minimal HK-bases (circuits of the kernel)")
    candidates: list[Candidate] = []
    for d in new_degrees:
        monos = monomial_exponents(n, d)
        lower = _products(probe.kernels.get(d - 1, []), monomial_exponents(n, d - 1) if d > 1 else [],
                          monos, n)
        kernel = probe.kernels[d]
        width = sum(1 for j in range(len(monos)) if any(v[j] for v in kernel))
        triv_rank = rank_mod(lower, probe.p)
        if triv_rank and math.comb(width, len(kernel) - 1) > FULL_CIRCUITS:
            new_part, eliminated = complement_of_trivial(kernel, lower, monos, probe.p)
        else:
            new_part, eliminated = kernel, []
        supports, complete = circuits(new_part, probe.p)
        if triv_rank and not eliminated:          # circuits of the whole kernel: drop the trivial ones
            supports = [sp for sp in supports
                        if rank_mod(lower + [_support_vector(kernel, sp, probe.p)], probe.p) > triv_rank]
        if eliminated:
            report.trivial.append({"degree": d, "dimension": len(probe.kernels[d]) - len(new_part),
                                   "eliminated": [monomial_text(field.variables, monos[j]) for j in eliminated],
                                   "reason": "products of lower-degree kernel elements with monomials; bases avoid "
                                             "the listed monomials"})
        if not complete:
            report.covered.append(f"degree {d}: circuit enumeration stopped after {MAX_CIRCUIT_TRIALS} trials")
        for s in supports:
            basis = [monos[j] for j in s]
            texts = [monomial_text(field.variables, e) for e in basis]
            for j, sizes in normalizations(kmap, basis, weights, free, probe.p, rng, len(free) + n):
                for cand in ratio_candidates(probe.orbit, basis, j):
                    cand.estimate = sizes[cand.k]
                    candidates.append(cand)
            report.bases.append({"basis": texts, "degree": d})
    candidates.sort(key=lambda c: c.estimate)      # the simplest integrals first (stable: small bases first)
    # how many independent integrals the kernels carry (gradients mod p), and which coordinates show them
    chosen_rank = rank_mod([c.gradient for c in candidates], probe.p) if candidates else 0
    report.expected_independent = chosen_rank
    clock.say(f"{len(report.bases)} minimal HK-bases; their kernel coordinates carry {chosen_rank} independent "
              "integrals (gradients mod p)")

    clock.start("confirm bases", "confirming the minimal HK-bases by algorithm (N)")
    for k, entry in enumerate(report.bases):
        clock.check("confirming every minimal HK-basis")
        entry.update(_confirm(scene, kmap, entry["basis"]) if k < MAX_CONFIRMED else
                     {"dimension": None, "status": Status.UNKNOWN.label, "check": "not confirmed (cap)"})

    _reconstruct_all(report, kmap, full_map, weights, free, candidates, chosen_rank, probe.p, fixed,
                     clock, max_degree, max_unknowns, rng)


def _support_vector(kernel: list[list[int]], support: tuple[int, ...], p: int) -> list[int]:
    """The kernel vector supported on `support` (a circuit), mod p."""
    others = [j for j in range(len(kernel[0])) if j not in support]
    lam = kernel_mod_p([[v[j] for v in kernel] for j in others], p) if others else [[1] + [0] * (len(kernel) - 1)]
    return [sum(lam[0][i] * kernel[i][j] for i in range(len(kernel))) % p for j in range(len(kernel[0]))]


def _confirm(scene: Scene, kmap: KahanMap, texts: list[str]) -> dict:
    """Algorithm (N) on a minimal basis: mod two primes at two points, and exactly over Q at one point."""
    from hkproof.experiments.modular import Modular
    problem = ProfileProblem(scene, [Frac.parse(kmap.ring, t) for t in texts])
    rng = random.Random(len(texts))
    pts = [[flint.fmpq(rng.randint(-60, 60) or 1, rng.randint(1, 50)) for _ in kmap.variables] for _ in range(3)]
    modular = [problem.profile(pt, Modular(seed=i), with_kernel=False) for i, pt in enumerate(pts[:2])]
    exact = problem.profile(pts[2], ExactQ(), with_kernel=False)
    dims = {pr.dimension for pr in modular + [exact] if pr.verdict == HK_BASIS}
    ok = len(dims) == 1 and exact.verdict == HK_BASIS
    return {"dimension": dims.pop() if ok else None,
            "status": Status.EVIDENCE_EXACT.label if ok else Status.UNKNOWN.label,
            "check": "algorithm (N): 2 points mod p, 1 point over Q"}


def _reconstruct_all(report: DiscoveryReport, kmap: KahanMap, full_map: KahanMap, weights: Weights,
                     free: list[str], candidates: list[Candidate], target: int, p: int, fixed,
                     clock: _Clock, max_degree: int, max_unknowns: int, rng: random.Random) -> None:
    """Reconstruct and certify kernel coordinates, one per new independent gradient, simplest bases first."""
    accepted: list[list[int]] = []
    caches: dict[tuple, dict] = {}
    solved: dict[tuple[str, ...], tuple[list[Frac] | None, Status, str, float]] = {}
    inner = list(kmap.variables)
    count = 0
    for cand in candidates:
        if len(accepted) >= target:
            break
        if rank_mod(accepted + [cand.gradient], p) <= len(accepted):
            continue
        texts = [monomial_text(kmap.variables, e) for e in cand.basis]
        if cand.estimate > max_unknowns:
            if _by_relations(report, kmap, full_map, cand, texts, fixed, solved, accepted, clock):
                continue
            report.skipped.append({"basis": texts, "coordinate": f"c{cand.k + 1}/c{cand.j + 1}", "degrees": None,
                                   "reason": f"dense ansatz of about {cand.estimate} unknowns along a line "
                                             f"(limit {max_unknowns})" if cand.estimate < 10**9 else
                                             "degree > 12 along a line"})
            continue
        clock.check(f"reconstructing integral {len(accepted) + 1} of {target}")
        sampler = _sampler(kmap, texts, cand.k, cand.j, weights, free, caches)
        clock.start("reconstruction", f"degrees of coordinate {cand.k + 1} of the kernel of ({', '.join(texts)})")
        start = time.perf_counter()
        fast = _modular_sampler(kmap, cand.basis, (cand.k, cand.j), weights, free, p)
        lines = [line_degrees(fast, free, inner, max_degree=max_degree, seed=rng.randint(0, 10**6), modulus=p)
                 for _ in range(2)]
        measured = [d for d in lines if d is not None]
        degrees = (max(d[0] for d in measured), max(d[1] for d in measured)) if len(measured) == len(lines) else None
        size = None if degrees is None else dense_size(len(free) + len(inner), degrees)
        if degrees is None or size is None or size > max_unknowns:
            if _by_relations(report, kmap, full_map, cand, texts, fixed, solved, accepted, clock):
                continue
            report.skipped.append({"basis": texts, "coordinate": f"c{cand.k + 1}/c{cand.j + 1}",
                                   "degrees": None if degrees is None else list(degrees),
                                   "reason": (f"degree > {max_degree} along a line" if degrees is None else
                                              f"dense ansatz of {size} unknowns (limit {max_unknowns})")})
            continue
        count += 1
        name = f"I{len(report.integrals) + 1}"
        clock.say(f"{name}: coordinate {cand.k + 1} of the kernel of ({', '.join(texts)}), degrees {degrees}, "
                  f"{size} unknowns")
        rec = reconstruct_rational(kmap.ring, free, inner, sampler, degrees, seed=rng.randint(0, 10**6))
        notes = list(rec.notes)
        h = None
        if rec.frac is not None:
            weight = [a - b for a, b in zip(weights.of_monomial(_exps(kmap, cand.basis[cand.j])),
                                            weights.of_monomial(_exps(kmap, cand.basis[cand.k])), strict=True)]
            h = restore_weights(rec.frac, weights, weight)
            notes.append("the interpolant is not weighted homogeneous: not restored" if h is None else
                         f"P/Q with degrees {list(degrees)} from {rec.samples} exact samples, checked at "
                         f"{rec.checks} fresh ones")
        coordinate = f"c{cand.k + 1}/c{cand.j + 1}"
        if h is None:
            report.integrals.append(FoundIntegral(name, None, Status.UNKNOWN, "kernel coordinate", texts, coordinate,
                                                  time.perf_counter() - start, "reconstruction failed", notes))
            continue
        clock.start("proofs", f"{name}: exact substitution h(f(x)) = h(x)")
        status, method = certify(full_map, h, fixed)
        found = FoundIntegral(name, h.to_ring(full_map.ring), status, "kernel coordinate", texts, coordinate,
                              time.perf_counter() - start, method, notes)
        report.integrals.append(found)
        if status >= Status.VERIFIED_SPECIALIZED and not is_phase_constant(h, kmap.variables):
            accepted.append(cand.gradient)
        clock.say(f"{name} = {found.frac}: {status.label}")
    by_relations = sum(1 for i in report.integrals if i.method.startswith("recipe (E)"))
    report.covered.append(f"reconstructed {count} kernel coordinates chosen for new independent gradients and "
                          f"solved {by_relations} by recipe (E); {len(report.skipped)} skipped as too large for "
                          "dense reconstruction")


def _by_relations(report: DiscoveryReport, kmap: KahanMap, full_map: KahanMap, cand: Candidate, texts: list[str],
                  fixed, solved: dict, accepted: list[list[int]], clock: _Clock) -> bool:
    """A kernel coordinate too large for dense interpolation, by the paper's recipe (E) instead: relations among the
    basis's kernel coordinates found exactly (symbolic in eps and the parameters), then the rows i = 0, 1 solved
    and certified by Prop. "prop: even" (hk.discover.solve_by_evenness). True if it gave an integral."""
    key = tuple(texts)
    if key not in solved:
        if len(texts) > MAX_RELATION_BASIS:
            solved[key] = (None, Status.UNKNOWN, "basis too large for the relation search", 0.0)
        else:
            clock.check(f"recipe (E) on ({', '.join(texts)})")
            clock.start("relations", f"recipe (E) on ({', '.join(texts)})")
            start = time.perf_counter()
            basis = [Frac.parse(kmap.ring, t) for t in texts]
            try:
                search = find_relations(kmap, [basis])
                rels = [Relation(r.coefficients, r.rhs) for r in search.relations]
                solved[key] = (*solve_by_evenness(kmap, basis, rels, fixed), time.perf_counter() - start)
            except HKProofError as exc:
                solved[key] = (None, Status.UNKNOWN, f"recipe (E) failed: {exc}", time.perf_counter() - start)
            clock.say(f"recipe (E) on ({', '.join(texts)}): {solved[key][2]}")
    solution, status, method, seconds = solved[key]
    if solution is None:
        return False
    c = [*solution, Frac(kmap.ring, -1)]
    if c[cand.j].is_zero():
        return False
    h = c[cand.k] / c[cand.j]
    name = f"I{len(report.integrals) + 1}"
    found = FoundIntegral(name, h.to_ring(full_map.ring), status, "kernel coordinate", texts,
                          f"c{cand.k + 1}/c{cand.j + 1}", seconds, method,
                          ["too large for dense interpolation along a line; solved symbolically instead"])
    report.integrals.append(found)
    if status >= Status.VERIFIED_SPECIALIZED and not is_phase_constant(h, kmap.variables):
        accepted.append(cand.gradient)
    clock.say(f"{name}: {status.label} by recipe (E)")
    return True


def _exps(kmap: KahanMap, e: Exponents) -> dict[str, int]:
    return {v: k for v, k in zip(kmap.variables, e, strict=True) if k}


def _modular_sampler(kmap: KahanMap, basis: list[Exponents], k: tuple[int, int] | None, weights: Weights,
                     free: list[str], p: int) -> Callable:
    """Values mod p of c_k / c_j, k = (k, j), for the kernel of a minimal basis (the whole vector c with
    c_l = -1 when k is None): cheap degree probes."""
    def sample(outer: dict, points: list[dict]) -> list:
        vals = {m: flint.fmpq(1) for m in weights.normalized} | {m: outer[m] for m in free}
        try:
            scene = make_scene(kmap, vals)
        except HKProofError:
            return [None] * len(points)
        out: list = []
        for pt in points:
            try:
                solved = recipe_b_mod_p(ModularOrbit(scene, [pt[v] for v in kmap.variables], p, len(basis) - 2),
                                        basis)
            except HKProofError:
                solved = None
            if solved is None:
                out.append(None)
            else:
                c = solved[1] + [p - 1]
                out.append(c if k is None else None if c[k[1]] == 0 else c[k[0]] * pow(c[k[1]], -1, p) % p)
        return out
    return sample


def _sampler(kmap: KahanMap, texts: list[str], k: int, j: int, weights: Weights, free: list[str],
             caches: dict) -> Callable:
    """Exact values of c_k / c_j for the kernel of a minimal basis (recipe (B): c_l = -1), at given free values."""
    basis = [Frac.parse(kmap.ring, t) for t in texts]
    cache = caches.setdefault(tuple(texts), {})

    def sample(outer: dict, points: list[dict]) -> list:
        vals = {m: flint.fmpq(1) for m in weights.normalized} | {m: outer[m] for m in free}
        key = tuple(sorted((m, str(v)) for m, v in vals.items()))
        problem = cache.get(key)
        if problem is None:
            try:
                problem = ProfileProblem(make_scene(kmap, vals), basis)
            except HKProofError:
                return [None] * len(points)
            cache.clear()
            cache[key] = problem
        out = []
        for pt in points:
            c = kernel_vector(problem, [pt[v] for v in kmap.variables])
            ok = c is not None and c[-1] == -1 and c[j] != 0          # -1 last: recipe (B)'s normalization
            out.append(c[k] / c[j] if ok and c is not None else None)
        return out
    return sample
