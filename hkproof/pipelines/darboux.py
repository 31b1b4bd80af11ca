"""`measure`: Darboux polynomials P o f = K P of a Kahan map searched mod p, reconstructed, and proven.

Recipe (after Celledoni, Evripidou, McLaren, Owren, Quispel, Tapley, van der Kamp, "Using discrete Darboux polynomials
to detect and determine preserved measures and integrals of rational maps", 2019): the cofactors K are tried among
the products of the irreducible factors of the numerator and denominator of det Df (hkproof.hk.darboux); for each K
the coefficients of P (all monomials of degree <= D) solve a linear system sampled at random points mod a large
prime at random rational eps and parameters; each kernel vector is reconstructed with eps and the parameters
symbolic (from its kernels mod primes at shared values, on its support) and then checked exactly by
hkproof.hk.darboux.
"""
from __future__ import annotations

import itertools
import random
import time
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Mapping, Sequence

import flint

from hkproof.algebra.sampling import random_point
from hkproof.algebra.fraction import Frac, poly_str
from hkproof.algebra.printing import SHOWN_TERMS
from hkproof.algebra.linalg import lcm
from hkproof.algebra.modular import free_kernel_mod_p, random_prime
from hkproof.algebra.monomials import Exponents, columns_mod_p, exponents_upto, value
from hkproof.algebra.ring import Rational, Ring, get_ring
from hkproof.algebra.rational_lifting import CoefficientLifter
from hkproof.algebra.reconstruction import reconstruct as rebuild
from hkproof.dynamics.field import EPS, STEP_CONVENTION
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.kahan import KahanMap
from hkproof.dynamics.modular_map import ModularKahanMap
from hkproof.experiments.weights import Weights, scaling_weights
from hkproof.budget import current
from hkproof.errors import BudgetExhausted, HKProofError, SingularSystemError
from hkproof.hk.darboux import (IDENTITY, Atom, Cofactor, DarbouxPolynomial, candidate_cofactors, check_darboux,
                                darboux_certificate, darboux_identity_checks, jacobian_atoms)
from hkproof.hk.jacobian import matrix_identity_holds
from hkproof.pipelines.slices import Slice
from hkproof.proof.status import Status, specialized_label

__all__ = ["DarbouxSearch", "JACOBIAN", "MAX_DARBOUX_DEGREE", "ModularScene", "search_darboux"]

EXPAND_LIMIT = 4            # above this many phase variables det M(x, -eps) o f stays one atom (factoring: minutes)
MAX_DARBOUX_DEGREE = 8      # C(n + 8, 8) monomials times the cofactors: already 12 870 unknowns per cofactor for n = 8

JACOBIAN = "det Df(x) = det M(f(x), -eps) / det M(x, eps), from M(x, eps) Df(x) = M(f(x), -eps)"


@dataclass
class DarbouxSearch:
    """Everything `hkproof measure` reports."""

    system: str
    degree: int
    atoms: list[Atom]
    jacobian: Cofactor
    darboux: list[DarbouxPolynomial] = field(default_factory=list)
    unverified: list[str] = field(default_factory=list)
    values: dict[str, flint.fmpq] = field(default_factory=dict)
    prime: int = 0
    jacobian_lemma: bool = False
    symbolic: bool = True
    fixed: dict[str, flint.fmpq] = field(default_factory=dict)     # parameters the user fixed (specialized map)
    stopped: str = ""       # why the search stopped early (a budget ran out); "" when it covered everything
    on_slice: str = ""      # the slice of a parameter translation searched, if any (the results are lifted)

    @property
    def complete(self) -> bool:
        return not self.stopped

    def densities(self, brief: bool = False) -> list[tuple[str, Status]]:
        """1/P for each P with cofactor det Df (rho(f(x)) det Df(x) = rho(x)); 1 itself when det Df = 1. `brief`:
        a P of more than SHOWN_TERMS terms is given by its size."""
        lemma = Status.VERIFIED if self.jacobian_lemma else Status.UNKNOWN
        out = [("1", lemma)] if not any(self.jacobian.exponents) else []
        out += [(f"1/({_shown(d.poly, brief)})", min(d.status, lemma)) for d in self.darboux
                if d.cofactor == self.jacobian]
        return out

    def integrals(self, brief: bool = False) -> list[tuple[str, Status]]:
        """P_i / P_0 for Darboux polynomials with equal cofactors, and P itself when its cofactor is 1 (`brief`: as
        for densities)."""
        groups: dict[tuple[int, ...], list[DarbouxPolynomial]] = {}
        for d in self.darboux:
            groups.setdefault(d.cofactor.exponents, []).append(d)
        out = []
        for exps, group in groups.items():
            if not any(exps):
                out += [(_shown(d.poly, brief), d.status) for d in group]
                continue
            base = group[0]
            out += [(f"({_shown(d.poly, brief)})/({_shown(base.poly, brief)})", min(d.status, base.status))
                    for d in group[1:]]
        return out

    def _label(self, status: Status) -> str:
        """The status as reported: "verified(specialized)" for a search at fixed parameter values."""
        return specialized_label(status, self.fixed)

    def to_dict(self) -> dict[str, Any]:
        """The JSON of `hkproof measure` (docs/geometry.md)."""
        label = self._label
        return {"system": self.system, "degree": self.degree, "fixed": {k: str(v) for k, v in self.fixed.items()},
                "eps_convention": STEP_CONVENTION,
                "jacobian": {"formula": JACOBIAN, "identity": "verified" if self.jacobian_lemma else "refuted",
                             "as_atoms": self.jacobian.text(self.atoms)},
                "atoms": {a.name: _atom_text(a, brief=False) for a in self.atoms},
                "darboux": [{"expr": poly_str(d.poly), "cofactor": d.cofactor.text(self.atoms),
                             "status": label(d.status), "method": d.detail} for d in self.darboux],
                "densities": [{"expr": e, "status": label(st)} for e, st in self.densities()],
                "integrals": [{"expr": e, "status": label(st)} for e, st in self.integrals()],
                "search": {"values": {k: str(v) for k, v in self.values.items()}, "prime": self.prime,
                           "symbolic": self.symbolic},
                "unverified": self.unverified, "complete": self.complete, "stopped": self.stopped or None,
                "slice": self.on_slice or None}

    def text(self) -> str:
        """The report for a person."""
        label = self._label
        identity = "verified" if self.jacobian_lemma else "refuted"
        lines = [f"Kahan map of {self.system} ({STEP_CONVENTION})", *([self.on_slice] if self.on_slice else []),
                 f"{JACOBIAN}: identity {identity} (exact, in Q(x, eps, parameters not fixed))",
                 f"det Df = {self.jacobian.text(self.atoms)} with"]
        lines += [f"  {a.name} = {_atom_text(a, brief=True)}" for a in self.atoms]
        lines.append(f"Darboux polynomials of degree <= {self.degree} (cofactors: products of these factors):")
        lines += [f"  [{label(d.status)}] K = {d.cofactor.text(self.atoms)}: P = {_shown(d.poly, True)}"
                  for d in self.darboux] or ["  none"]
        lines.append("invariant measure densities rho = 1/P (rho(f(x)) det Df(x) = rho(x)):")
        lines += [f"  [{label(st)}] {e}" for e, st in self.densities(brief=True)] or ["  none found"]
        lines.append("integrals (ratios of Darboux polynomials with equal cofactors):")
        lines += [f"  [{label(st)}] {e}" for e, st in self.integrals(brief=True)] or ["  none found"]
        if any(len(a.poly) > SHOWN_TERMS for a in self.atoms) or any(len(d.poly) > SHOWN_TERMS for d in self.darboux):
            lines.append(f"(a polynomial of more than {SHOWN_TERMS} terms is shown by its size; --json prints every "
                         "formula whole)")
        for u in self.unverified:
            lines.append(f"  not reported: {u}")
        lines.append("searched at " + ", ".join(f"{k} = {v}" for k, v in self.values.items())
                     + f", reduced mod p = {self.prime}; " + (
                         "every P above reconstructed with eps and the parameters symbolic" if self.symbolic else
                         "the system is too large for the symbolic reconstruction: every P above holds at these "
                         "values only (evidence)"))
        if self.stopped:
            lines.append(f"INCOMPLETE: {self.stopped}")
        return "\n".join(lines)


def _shown(p: flint.fmpz_mpoly, brief: bool) -> str:
    """p as text, or by its size when `brief` and it has more than SHOWN_TERMS terms (a report read by a person)."""
    if brief and len(p) > SHOWN_TERMS:
        return f"<a polynomial of {len(p)} terms, total degree {p.total_degree()}>"
    return poly_str(p)


def _atom_text(a: Atom, brief: bool) -> str:
    """An atom of det Df as the reports give it (a pulled atom as q o f)."""
    return f"det M(x, -eps) o f = {_shown(a.poly, brief)} at x = f(x)" if a.pulled else _shown(a.poly, brief)


# ---- modular search --------------------------------------------------------------------------------------------------
Sample = tuple[list[int], list[int], list[int]]       # x, f(x), the atoms' values (ModularScene.sample)


class ModularScene:
    """The modular map and the atoms, mod p at fixed eps and parameters: samples (x, f(x), atom values). The atoms
    may come reduced already (`atoms_mod_p`, once per prime for scenes that share it)."""

    def __init__(self, kmap: KahanMap, atoms: Sequence[Atom], values: Mapping[str, Rational], prime: int,
                 reduced: Sequence[flint.nmod_mpoly] | None = None):
        self.kmap, self.atoms, self.prime = kmap, atoms, prime
        self.modular: ModularKahanMap = kmap.mod(prime, values)
        self.atom_polys = list(reduced) if reduced is not None else atoms_mod_p(kmap, atoms, prime)
        self.slots = [kmap.ring.index(v) for v in kmap.variables]
        self.args = [self.modular.values.get(n, 0) for n in kmap.ring.names]

    def sample(self, rng: random.Random) -> Sample | None:
        """(x, f(x), atom values) at a random point, or None where Delta or an atom vanishes."""
        x = [rng.randrange(self.prime) for _ in self.kmap.variables]
        fx = self.modular.evaluate(x)
        if fx is None:
            return None
        vals = [int(q(*self._at(fx if a.pulled else x))) for a, q in zip(self.atoms, self.atom_polys, strict=True)]
        if any(v == 0 for v in vals):
            return None
        return x, fx, vals

    def _at(self, x: Sequence[int]) -> list[int]:
        args = list(self.args)
        for slot, v in zip(self.slots, x, strict=True):
            args[slot] = v
        return args


def atoms_mod_p(kmap: KahanMap, atoms: Sequence[Atom], p: int) -> list[flint.nmod_mpoly]:
    """The atoms mod p as polynomials in every name of the ring (phase variables, eps, parameters)."""
    ctx = flint.nmod_mpoly_ctx.get(kmap.ring.names, p, "degrevlex")  # type: ignore[call-arg, arg-type]  # stubs lag
    return [ctx.from_dict({m: int(c) % p for m, c in a.poly.to_dict().items() if int(c) % p}) for a in atoms]


def modular_kernels(scene: ModularScene, cofactors: Sequence[Cofactor], monos: Sequence[Exponents],
                    rng: random.Random, extra: int = 8) -> dict[int, list[tuple[int, list[int]]]]:
    """For each cofactor (by index), the rref kernel basis of P -> P o f - K P on the monomials, mod p."""
    samples: list[Sample] = []
    while len(samples) < len(monos) + extra:
        s = scene.sample(rng)
        if s is not None:
            samples.append(s)
    values = _monomial_values(monos, samples, scene.prime)
    out = {}
    for k, cof in enumerate(cofactors):
        kernel = free_kernel_mod_p(_rows(values, samples, cof, scene.prime), scene.prime, free_value=1)
        if kernel:
            out[k] = kernel
    return out


MonomialValues = list[tuple[tuple[int, ...], tuple[int, ...]]]


def _monomial_values(monos: Sequence[Exponents], samples: Sequence[Sample], p: int) -> MonomialValues:
    """For each sample (x, f(x), atoms), the values mod p of the monomials at x and at f(x): one product per
    monomial and point, over all the samples at once (per point, the bookkeeping cost as much as the products)."""
    if not samples:
        return []
    at_x = columns_mod_p(monos, [x for x, _, _ in samples], p)
    at_fx = columns_mod_p(monos, [fx for _, fx, _ in samples], p)
    return list(zip(zip(*at_x), zip(*at_fx)))


def _rows(values: MonomialValues, samples: Sequence[Sample], cofactor: Cofactor, p: int) -> list[list[int]]:
    """The rows m(f(x)) - K(x) m(x) mod p for the monomials m, one per sample, from the monomials' values at x and
    f(x) and the atoms' values (K is a product of atoms)."""
    rows = []
    for (mx, mf), (_, _, atoms) in zip(values, samples, strict=True):
        k = 1
        for v, e in zip(atoms, cofactor.exponents, strict=True):
            if e:
                k = k * pow(v, e % (p - 1), p) % p
        rows.append([(b - k * a) % p for a, b in zip(mx, mf, strict=True)])
    return rows


# ---- reconstruction with eps and parameters symbolic ---------------------------------------------------------
def _support_vector_mod_p(kmap: KahanMap, atoms: Sequence[Atom], reduced: Sequence[flint.nmod_mpoly],
                          cofactor: Cofactor, support: Sequence[Exponents], free: int, p: int,
                          controls: Mapping[str, int], rng: random.Random) -> list[int] | None:
    """The kernel vector of P -> P o f - K P on the monomials `support` mod p at the given residues of eps and the
    parameters, its coefficient at `support[free]` set to 1 (the others in order); None when that kernel is not a
    line there (a special value or an unlucky prime)."""
    scene = ModularScene(kmap, atoms, controls, p, reduced)
    samples: list[Sample] = []
    for _ in range(4 * len(support) + 20):
        if len(samples) == len(support) + 3:
            break
        s = scene.sample(rng)
        if s is not None:
            samples.append(s)
    kernel = free_kernel_mod_p(_rows(_monomial_values(support, samples, p), samples, cofactor, p), p, free_value=1)
    if len(kernel) != 1 or kernel[0][0] != free:
        return None
    vector = kernel[0][1]
    return [c for j, c in enumerate(vector) if j != free]


def reconstruct(kmap: KahanMap, atoms: Sequence[Atom], cofactor: Cofactor, monos: Sequence[Exponents], free: int,
                vector: Sequence[int], rng: random.Random, weights: Weights | None = None) -> flint.fmpz_mpoly:
    """The kernel vector with eps and the parameters symbolic, on the support of the modular one (its free
    monomial's coefficient 1): every other coefficient is a rational function of eps and the parameters, rebuilt from
    kernels mod primes at shared values (hkproof.algebra.reconstruction, method "dense"). With the `weights` of a scaling
    symmetry under which the cofactor has weight 0, the unique kernel vector is weighted homogeneous: the
    coefficient of x^m has the weight of x^free / x^m, so the normalized names are set to 1 in the probes and
    restored afterwards. A candidate: check_darboux proves it."""
    support = [monos[j] for j, c in enumerate(vector) if c]
    at = support.index(monos[free])
    ring = kmap.ring
    normalized = weights.normalized if weights is not None else ()
    names = [n for n in kmap.field.control_names if n not in normalized]
    one = Frac(ring, 1)
    if len(support) == 1:
        return _poly_in_ring(ring, {support[0]: one}, kmap.variables)

    reduced: dict[int, list[flint.nmod_mpoly]] = {}

    def box(p: int, t: Sequence[int]) -> list[int] | None:
        controls = {**{n: 1 for n in normalized}, **dict(zip(names, t, strict=True))}
        if p not in reduced:
            reduced[p] = atoms_mod_p(kmap, atoms, p)
        return _support_vector_mod_p(kmap, atoms, reduced[p], cofactor, support, at, p, controls, rng)
    if names:
        values = [r.to_frac(ring, names) for r in
                  rebuild(lambda p, ts: [box(p, t) for t in ts], len(names), len(support) - 1, method="dense",
                          rng=rng)]
    else:
        values = [Frac.rational(ring, c) for c in _rational_vector(box, rng)]
    coeffs = {support[at]: one}
    others = [m for j, m in enumerate(support) if j != at]
    for m, h in zip(others, values, strict=True):
        if weights is not None:
            weight = [a - b for a, b in zip(_weight(weights, kmap, support[at]), _weight(weights, kmap, m),
                                            strict=True)]
            restored = weights.restore_frac(h, weight)
            if restored is None:
                raise SingularSystemError(f"the coefficient {h} of a Darboux polynomial is not weighted homogeneous of "
                                          "the weight its monomial asks for")
            h = restored
        coeffs[m] = h
    return _poly_in_ring(ring, coeffs, kmap.variables)


def _weight(weights: Weights, kmap: KahanMap, m: Exponents) -> list[flint.fmpq]:
    return weights.of_monomial(dict(zip(kmap.variables, m, strict=True)))


def _rational_vector(box: Callable[[int, Sequence[int]], list[int] | None], rng: random.Random,
                     max_primes: int = 12) -> list[flint.fmpq]:
    """Constants (no name left to sample) from their residues modulo primes until the rational reconstruction is
    stable."""
    lifter: CoefficientLifter[int] = CoefficientLifter()
    for _ in range(max_primes):
        p = random_prime(rng, 50)
        values = box(p, [])
        if values is None:
            continue
        _, missing = lifter.add(dict(enumerate(values)), p)
        if not missing and lifter.changed == 0:                # every constant confirmed by one more prime
            return [lifter.rationals[k] for k in range(len(values))]
    raise SingularSystemError("the coefficients of a Darboux polynomial did not stabilize over the primes tried")


def reconstruct_at_values(kmap: KahanMap, atoms: Sequence[Atom], cofactor: Cofactor, values: dict[str, flint.fmpq],
                          monos: Sequence[Exponents], free: int, vector: Sequence[int],
                          rng: random.Random) -> flint.fmpz_mpoly:
    """The kernel vector over Q at the search's fixed eps and parameters (for maps too large for the symbolic
    reconstruction): rows at rational points x, on the modular vector's support, solved exactly."""
    support = [j for j, c in enumerate(vector) if c]
    unknowns = [j for j in support if j != free]
    rows: list[list[flint.fmpq]] = []
    rank = 0
    while rank < len(unknowns):
        x = random_point(rng, kmap.variables, 9, denominator=5, zero=True)
        point = {**values, **x}
        try:
            fx = {**point, **kmap.step_exact(point)}
        except HKProofError:
            continue
        k = flint.fmpq(1)
        for a, e in zip(atoms, cofactor.exponents, strict=True):
            if e:
                k *= kmap.ring.evaluate(a.poly, fx if a.pulled else point) ** e
        xs, fs = [x[v] for v in kmap.variables], [fx[v] for v in kmap.variables]
        row = [value(monos[j], fs) - k * value(monos[j], xs) for j in support]
        cols = [support.index(j) for j in unknowns]
        if flint.fmpq_mat([[r[c] for c in cols] for r in rows + [row]]).rank() > rank:
            rows.append(row)
            rank += 1
    coeffs = {monos[free]: flint.fmpq(1)}
    if unknowns:
        lhs = flint.fmpq_mat([[r[support.index(j)] for j in unknowns] for r in rows])
        rhs = flint.fmpq_mat([[-r[support.index(free)]] for r in rows])
        sol = lhs.solve(rhs)
        coeffs.update({monos[j]: sol[i, 0] for i, j in enumerate(unknowns)})
    small = get_ring((EPS,) + kmap.field.parameters)
    return _poly_in_ring(kmap.ring, {m: Frac.rational(small, c) for m, c in coeffs.items()}, kmap.variables)


def _poly_in_ring(ring: Ring, coeffs: dict[Exponents, Frac], variables: Sequence[str]) -> flint.fmpz_mpoly:
    """sum c_m x^m with c_m in Q(eps, params), denominators cleared, content removed: a polynomial of `ring`."""
    common = lcm([c.den for c in coeffs.values()])
    total = ring.ctx.constant(0)
    for m, c in coeffs.items():
        mono = ring.ctx.constant(1)
        for v, e in zip(variables, m, strict=True):
            mono = mono * ring.gen(v) ** e
        total += (c.num * (common / c.den)).project_to_context(ring.ctx) * mono
    content = flint.fmpz(0)
    for coefficient in total.coeffs():
        content = content.gcd(coefficient)
    total = total / content if content > 1 else total
    return total if total.coefficient(0) > 0 else -total


# ---- the search and its exact checks -----------------------------------------------------------------------------
def search_darboux(kmap: KahanMap, degree: int = 4, *, seed: int = 0, symbolic_limit: int = 6,
                   progress: Callable[[DarbouxPolynomial], None] | None = None,
                   fixed: Mapping[str, flint.fmpq] | None = None) -> DarbouxSearch:
    """Darboux polynomials of degree <= `degree` with cofactors among the products of the factors of det Df, each
    reconstructed with eps and the parameters symbolic and checked exactly (verified) when the system has at most
    `symbolic_limit` phase variables; otherwise reconstructed at the search's rational eps and parameters and checked
    at random exact points there (evidence(exact) at those values only). `fixed`: the parameter values that made
    `kmap` a specialization (its results are then verified(specialized))."""
    if not 1 <= degree <= MAX_DARBOUX_DEGREE:
        raise HKProofError(f"the degree of the Darboux polynomials must be between 1 and {MAX_DARBOUX_DEGREE}, got "
                           f"{degree}")
    where = Slice.of(kmap.field) if len(kmap.variables) <= symbolic_limit else None
    if where is not None and where.shifts:           # step 0 of discover: the slice of a parameter translation
        found = search_darboux(kahan_map(where.searched), degree, seed=seed, symbolic_limit=symbolic_limit,
                               fixed=fixed)
        return _lifted(found, where, kmap, progress)
    rng = random.Random(seed)
    atoms, jac = jacobian_atoms(kmap, expand_limit=min(symbolic_limit, EXPAND_LIMIT))
    cofactors = candidate_cofactors(jac)
    monos = exponents_upto(len(kmap.variables), degree)
    symbolic = len(kmap.variables) <= symbolic_limit
    if symbolic:        # values for the modular search only: large random rationals avoid special cases
        values = random_point(rng, (EPS,) + kmap.field.parameters, 40)
    else:               # the results hold at these values: small ones give readable polynomials
        ints = rng.sample([k for k in range(-9, 10) if k], len(kmap.field.parameters))
        values = {EPS: flint.fmpq(1, rng.randint(3, 11)),
                  **dict(zip(kmap.field.parameters, map(flint.fmpq, ints), strict=True))}
    prime = random_prime(rng)
    result = DarbouxSearch(kmap.field.name, degree, atoms, jac, values=values, prime=prime,
                           jacobian_lemma=matrix_identity_holds(kmap), symbolic=symbolic, fixed=dict(fixed or {}))
    try:
        _search(kmap, result, cofactors, monos, rng, random.Random(seed + 1), progress)
    except BudgetExhausted as exc:
        result.stopped = f"{exc}; the polynomials listed were found before it ran out"
    return result


def _lifted(found: DarbouxSearch, where: Slice, kmap: KahanMap,
            progress: Callable[[DarbouxPolynomial], None] | None) -> DarbouxSearch:
    """The search on the slice, lifted to `kmap`: the factors of det Df and the Darboux polynomials (an identity
    P o f = K P of invariant functions holds iff it holds on the slice; each certificate records the invariance)."""
    ring = kmap.ring
    out = replace(found, system=kmap.field.name, on_slice=where.describe(),
                  atoms=[replace(a, poly=where.lift_poly(a.poly, ring)) for a in found.atoms], darboux=[])
    for d in found.darboux:
        where.record_lift(d.certificate, ring)
        out.darboux.append(DarbouxPolynomial(where.lift_poly(d.poly, ring), d.cofactor, d.certificate))
        if progress:
            progress(out.darboux[-1])
    return out


def _search(kmap: KahanMap, result: DarbouxSearch, cofactors: Sequence[Cofactor], monos: Sequence[Exponents],
            rng: random.Random, row_rng: random.Random, progress: Callable[[DarbouxPolynomial], None] | None) -> None:
    """The modular kernels per cofactor, then per cofactor each kernel vector reconstructed and all of them checked
    (filling `result`)."""
    atoms, symbolic, values = result.atoms, result.symbolic, result.values
    scene = ModularScene(kmap, atoms, values, result.prime)
    kernels = modular_kernels(scene, cofactors, monos, rng)
    one = tuple(0 for _ in atoms)
    weights = scaling_weights(kmap) if symbolic else None
    tasks = [(cofactors[k], free, vec) for k, basis in kernels.items() for free, vec in basis
             if cofactors[k].exponents != one or sum(monos[free]) > 0]          # not P = 1 with K = 1
    done = 0
    for cof, group in itertools.groupby(tasks, key=lambda task: task[0].exponents):
        members = list(group)
        cof = members[0][0]
        homogeneous = weights if weights is not None and _weight_zero(kmap, weights, atoms, cof) else None
        built: list[tuple[flint.fmpz_mpoly, float]] = []
        for _, free, vec in members:
            start = time.perf_counter()
            try:
                built.append((reconstruct(kmap, atoms, cof, monos, free, vec, row_rng, homogeneous) if symbolic else
                              reconstruct_at_values(kmap, atoms, cof, values, monos, free, vec, rng),
                              time.perf_counter() - start))
            except BudgetExhausted as exc:
                raise _not_covered(exc, atoms, monos, tasks[done:], "reconstructed") from None
            except (HKProofError, ZeroDivisionError) as exc:
                result.unverified.append(f"K = {cof.text(atoms)}: reconstruction failed ({exc})")
            done += 1
        start = time.perf_counter()
        checks = [check_darboux(kmap, atoms, cof, p, exact=False, rng=rng, fixed=None if symbolic else values)
                  for p, _ in built]
        stopped = None
        if symbolic:          # exact where the points did not refute; evidence(exact) if the budget stops it
            try:
                exact = iter(current().call(f"checking P o f = K P exactly for K = {cof.text(atoms)}",
                                            _checked_exactly, kmap, atoms, cof,
                                            [p for (p, _), (s, _) in zip(built, checks) if s is not Status.REFUTED]))
                checks = [c if c[0] is Status.REFUTED else next(exact) for c in checks]
            except BudgetExhausted as exc:
                stopped = _not_covered(exc, atoms, monos, members, "checked exactly (listed as evidence)")
                checks = [(s, f"{how}; the exact check was stopped by the time budget") for s, how in checks]
        share = (time.perf_counter() - start) / max(1, len(built))
        for (p, seconds), (status, how) in zip(built, checks, strict=True):
            if status is Status.REFUTED:
                result.unverified.append(f"K = {cof.text(atoms)}: the reconstructed {p} fails the exact check")
                continue
            cert = darboux_certificate(kmap, p, cof.text(atoms), status, how, seconds + share,
                                       values if not symbolic else result.fixed)
            result.darboux.append(DarbouxPolynomial(p, cof, cert))
            if progress:
                progress(result.darboux[-1])
        if stopped is not None:
            raise stopped


def _weight_zero(kmap: KahanMap, weights: Weights, atoms: Sequence[Atom], cofactor: Cofactor) -> bool:
    """Whether K has weight 0 under every scaling of the field, read from its atoms (a pulled atom q o f has the
    weight of q, since f commutes with the scalings): no composition with f."""
    total = [flint.fmpq(0)] * len(weights.basis)
    for a, e in zip(atoms, cofactor.exponents, strict=True):
        if e:
            total = [t + e * w for t, w in zip(total, weights.of_frac(Frac(kmap.ring, a.poly)), strict=True)]
    return not any(total)


def _checked_exactly(kmap: KahanMap, atoms: Sequence[Atom], cofactor: Cofactor, polys: Sequence[flint.fmpz_mpoly]
                     ) -> list[tuple[Status, str]]:
    """P o f = K P exactly for each P (polynomial identities; a pulled atom composed with f once), with the route
    that decided it (expanded, lattice or modulo primes) in the method text."""
    return [(Status.VERIFIED if check.holds else Status.REFUTED, f"{IDENTITY}; route: {check.route}")
            for check in darboux_identity_checks(kmap, atoms, cofactor, polys)]


def _not_covered(exc: BudgetExhausted, atoms: Sequence[Atom], monos: Sequence[Exponents],
                 left: Sequence[tuple[Cofactor, int, Any]], what: str) -> BudgetExhausted:
    """The budget's message and what it left: the Darboux polynomials found mod p, their degrees and cofactors."""
    degrees = sorted({max(sum(m) for m, c in zip(monos, v, strict=True) if c) for _, _, v in left})
    cofactors = ", ".join(sorted({c.text(atoms) for c, _, _ in left}))
    return BudgetExhausted(f"{exc}; {len(left)} Darboux polynomial(s) found mod p were not {what} (degrees "
                           f"{', '.join(map(str, degrees))}; cofactors {cofactors}): give more time, a smaller "
                           "degree, or fixed parameters", limit=exc.limit, raise_with=exc.raise_with)

