"""`measure`: Darboux polynomials P o f = K P of a Kahan map searched mod p, reconstructed, and proven.

Recipe (after Celledoni, Evripidou, McLaren, Owren, Quispel, Tapley, van der Kamp, "Using discrete Darboux polynomials
to detect and determine preserved measures and integrals of rational maps", 2019): the cofactors K are tried among
the products of the irreducible factors of the numerator and denominator of det Df (hkproof.hk.darboux); for each K
the coefficients of P (all monomials of degree <= D) solve a linear system sampled at random points mod a large
prime at random rational eps and parameters; each kernel vector is reconstructed with eps and the parameters
symbolic (Cramer's rule on its support, at rational points) and then checked exactly by hkproof.hk.darboux.
"""
from __future__ import annotations

import random
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import flint

from hkproof.algebra.sampling import random_point
from hkproof.algebra.fraction import Frac, homogenized_compose, poly_str
from hkproof.algebra.linalg import cramer, lcm
from hkproof.algebra.modular import free_kernel_mod_p, random_prime
from hkproof.algebra.monomials import Exponents, exponents_upto, value, values_mod_p
from hkproof.algebra.ring import Ring, get_ring
from hkproof.dynamics.field import EPS, STEP_CONVENTION
from hkproof.dynamics.kahan import KahanMap
from hkproof.dynamics.modular_map import ModularKahanMap
from hkproof.errors import BudgetExhausted, HKProofError, SingularSystemError
from hkproof.hk.darboux import (Atom, Cofactor, DarbouxPolynomial, candidate_cofactors, check_at_points,
                                check_darboux, cofactor_value, jacobian_atoms)
from hkproof.hk.jacobian import matrix_identity_holds
from hkproof.proof.status import Status, specialized_label

__all__ = ["DarbouxSearch", "JACOBIAN", "MAX_DARBOUX_DEGREE", "ModularScene", "search_darboux"]

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

    @property
    def complete(self) -> bool:
        return not self.stopped

    def densities(self) -> list[tuple[str, Status]]:
        """1/P for each P with cofactor det Df (rho(f(x)) det Df(x) = rho(x)); 1 itself when det Df = 1."""
        lemma = Status.VERIFIED if self.jacobian_lemma else Status.UNKNOWN
        out = [("1", lemma)] if not any(self.jacobian.exponents) else []
        out += [(f"1/({poly_str(d.poly)})", min(d.status, lemma)) for d in self.darboux if d.cofactor == self.jacobian]
        return out

    def integrals(self) -> list[tuple[str, Status]]:
        """P_i / P_0 for Darboux polynomials with equal cofactors, and P itself when its cofactor is 1."""
        groups: dict[tuple[int, ...], list[DarbouxPolynomial]] = {}
        for d in self.darboux:
            groups.setdefault(d.cofactor.exponents, []).append(d)
        out = []
        for exps, group in groups.items():
            if not any(exps):
                out += [(poly_str(d.poly), d.status) for d in group]
                continue
            base = group[0]
            out += [(f"({poly_str(d.poly)})/({poly_str(base.poly)})", min(d.status, base.status)) for d in group[1:]]
        return out


    def to_dict(self) -> dict[str, Any]:
        """The JSON of `hkproof measure` (docs/geometry.md)."""
        label = lambda status: specialized_label(status, self.fixed)  # noqa: E731
        return {"system": self.system, "degree": self.degree, "fixed": {k: str(v) for k, v in self.fixed.items()},
                "eps_convention": STEP_CONVENTION,
                "jacobian": {"formula": JACOBIAN, "identity": "verified" if self.jacobian_lemma else "refuted",
                             "as_atoms": self.jacobian.text(self.atoms)},
                "atoms": {a.name: (f"det M(x, -eps) o f = {poly_str(a.poly)} at x = f(x)" if a.pulled
                                   else poly_str(a.poly)) for a in self.atoms},
                "darboux": [{"expr": poly_str(d.poly), "cofactor": d.cofactor.text(self.atoms),
                             "status": label(d.status), "method": d.detail} for d in self.darboux],
                "densities": [{"expr": e, "status": label(st)} for e, st in self.densities()],
                "integrals": [{"expr": e, "status": label(st)} for e, st in self.integrals()],
                "search": {"values": {k: str(v) for k, v in self.values.items()}, "prime": self.prime,
                           "symbolic": self.symbolic},
                "unverified": self.unverified, "complete": self.complete, "stopped": self.stopped or None}

    def text(self) -> str:
        """The report for a person."""
        payload = self.to_dict()
        lines = [f"Kahan map of {self.system} ({STEP_CONVENTION})",
                 f"{JACOBIAN}: identity {payload['jacobian']['identity']} (exact, in Q(x, eps, parameters not fixed))",
                 f"det Df = {self.jacobian.text(self.atoms)} with"]
        lines += [f"  {k} = {v}" for k, v in payload["atoms"].items()]
        lines.append(f"Darboux polynomials of degree <= {self.degree} (cofactors: products of these factors):")
        lines += [f"  [{d['status']}] K = {d['cofactor']}: P = {d['expr']}" for d in payload["darboux"]] or ["  none"]
        lines.append("invariant measure densities rho = 1/P (rho(f(x)) det Df(x) = rho(x)):")
        lines += [f"  [{d['status']}] {d['expr']}" for d in payload["densities"]] or ["  none found"]
        lines.append("integrals (ratios of Darboux polynomials with equal cofactors):")
        lines += [f"  [{d['status']}] {d['expr']}" for d in payload["integrals"]] or ["  none found"]
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


# ---- modular search --------------------------------------------------------------------------------------------------
class ModularScene:
    """The modular map and the atoms, mod p at fixed eps and parameters: samples (x, f(x), atom values)."""

    def __init__(self, kmap: KahanMap, atoms: Sequence[Atom], values: dict[str, flint.fmpq], prime: int):
        self.kmap, self.atoms, self.prime = kmap, atoms, prime
        self.modular: ModularKahanMap = kmap.mod(prime, values)
        self.atom_polys = [self.modular.reduce(a.poly) for a in atoms]

    def sample(self, rng: random.Random) -> tuple[list[int], list[int], list[int]] | None:
        """(x, f(x), atom values) at a random point, or None where Delta or an atom vanishes."""
        x = [rng.randrange(self.prime) for _ in self.kmap.variables]
        fx = self.modular.evaluate(x)
        if fx is None:
            return None
        vals = [int(q(*(fx if a.pulled else x))) for a, q in zip(self.atoms, self.atom_polys, strict=True)]
        if any(v == 0 for v in vals):
            return None
        return x, fx, vals


def modular_kernels(scene: ModularScene, cofactors: Sequence[Cofactor], monos: Sequence[Exponents],
                    rng: random.Random, extra: int = 8) -> dict[int, list[tuple[int, list[int]]]]:
    """For each cofactor (by index), the rref kernel basis of P -> P o f - K P on the monomials, mod p."""
    p = scene.prime
    samples: list = []
    while len(samples) < len(monos) + extra:
        s = scene.sample(rng)
        if s is not None:
            x, fx, vals = s
            samples.append((values_mod_p(monos, x, p), values_mod_p(monos, fx, p), vals))
    out = {}
    for k, cof in enumerate(cofactors):
        rows = []
        for mx, mf, vals in samples:
            kv = 1
            for v, e in zip(vals, cof.exponents, strict=True):
                if e:
                    kv = kv * pow(v, e % (p - 1), p) % p
            rows.append([(b - kv * a) % p for a, b in zip(mx, mf, strict=True)])
        kernel = free_kernel_mod_p(rows, p, free_value=1)
        if kernel:
            out[k] = kernel
    return out


# ---- reconstruction with eps and parameters symbolic ---------------------------------------------------------
class SymbolicRows:
    """Rows m(f(x)) - K(x) m(x) at rational points x, with eps and the parameters symbolic (ring Z[eps, params])."""

    def __init__(self, kmap: KahanMap, atoms: Sequence[Atom], rng: random.Random):
        self.kmap, self.atoms, self.rng = kmap, atoms, rng
        self.small: Ring = get_ring((EPS,) + kmap.field.parameters)
        self.points: list[dict] = []

    def point(self, k: int) -> dict:
        """The k-th rational point: x, f(x) and the atoms there, as elements of Q(eps, params)."""
        while len(self.points) <= k:
            x = random_point(self.rng, self.kmap.variables, 9, denominator=5, zero=True)
            nums, delta = self.kmap.explicit
            d = self._at(delta, x)
            if d.is_zero():
                continue
            fx = [self._at(n, x) / d for n in nums]
            vals = [self._pulled(a.poly, fx) if a.pulled else self._at(a.poly, x) for a in self.atoms]
            if any(v.is_zero() for v in vals):
                continue
            self.points.append({"x": [Frac.rational(self.small, x[v]) for v in self.kmap.variables], "fx": fx,
                                "atoms": vals})
        return self.points[k]

    def _at(self, p: flint.fmpz_mpoly, x: dict) -> Frac:
        num, den = self.kmap.ring.specialize_poly(p, x, self.small)
        return Frac(self.small, num, self.small.constant(1) * int(den))

    def _pulled(self, q: flint.fmpz_mpoly, fx: Sequence[Frac]) -> Frac:
        """q(f(x)) with q(x, eps, params) and f(x) in Q(eps, params)."""
        big = self.kmap.ring
        den = lcm([c.den for c in fx])
        images = [(c.num * (den / c.den)).project_to_context(big.ctx) for c in fx]
        value, deg = homogenized_compose(big, q, self.kmap.variables, images, den.project_to_context(big.ctx))
        return Frac(self.small, value.project_to_context(self.small.ctx), (den ** deg))

    def row(self, k: int, cofactor: Cofactor, monos: Sequence[Exponents]) -> list[Frac]:
        pt = self.point(k)
        kv = Frac(self.small, 1)
        for v, e in zip(pt["atoms"], cofactor.exponents, strict=True):
            if e:
                kv = kv * v ** e
        return [value(m, pt["fx"]) - kv * value(m, pt["x"]) for m in monos]


def reconstruct(rows: SymbolicRows, scene: ModularScene, cofactor: Cofactor, monos: Sequence[Exponents],
                free: int, vector: Sequence[int]) -> flint.fmpz_mpoly:
    """The kernel vector with eps and the parameters symbolic, on the support of the modular one: the coefficient of
    its free monomial is 1, the others solve square rows (points chosen independent mod p) by Cramer's rule."""
    support = [j for j, c in enumerate(vector) if c]
    unknowns = [j for j in support if j != free]
    if not unknowns:
        return _poly_in_ring(rows.kmap.ring, {monos[free]: Frac(rows.small, 1)}, rows.kmap.variables)
    cols = [support.index(j) for j in unknowns]
    chosen: list[list[Frac]] = []
    k = 0
    while len(chosen) < len(unknowns):
        if k > 4 * len(unknowns) + 20:
            raise SingularSystemError("no independent rows found to reconstruct a Darboux polynomial")
        row = rows.row(k, cofactor, [monos[j] for j in support])
        k += 1
        if _rank_mod(chosen + [row], cols, scene.prime) == len(chosen) + 1:
            chosen.append(row)
    a = [[r[c] for c in cols] for r in chosen]
    b = [-r[support.index(free)] for r in chosen]
    solution, _ = cramer(a, b)
    coeffs = {monos[free]: Frac(rows.small, 1)}
    coeffs.update({monos[j]: c for j, c in zip(unknowns, solution, strict=True)})
    return _poly_in_ring(rows.kmap.ring, coeffs, rows.kmap.variables)


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


def _rank_mod(rows: Sequence[Sequence[Frac]], cols: Sequence[int], p: int) -> int:
    """Rank mod p of the columns `cols` at a random value of eps and the parameters (a lower bound of the rank)."""
    rng = random.Random(p + len(rows))
    while True:
        point = [rng.randrange(1, p) for _ in rows[0][0].ring.names]
        vals = [[r[j].residue_at(point, p) for j in cols] for r in rows]
        if all(v is not None for row in vals for v in row):
            return flint.nmod_mat([[int(v or 0) for v in row] for row in vals], p).rank()


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
def search_darboux(kmap: KahanMap, degree: int = 4, *, seed: int = 0, symbolic_limit: int = 4,
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
    rng = random.Random(seed)
    atoms, jac = jacobian_atoms(kmap, expand_limit=symbolic_limit)
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


def _search(kmap: KahanMap, result: DarbouxSearch, cofactors: Sequence[Cofactor], monos: Sequence[Exponents],
            rng: random.Random, row_rng: random.Random, progress: Callable[[DarbouxPolynomial], None] | None) -> None:
    """The modular kernels per cofactor, then each kernel vector reconstructed and checked (filling `result`)."""
    atoms, symbolic, values = result.atoms, result.symbolic, result.values
    scene = ModularScene(kmap, atoms, values, result.prime)
    kernels = modular_kernels(scene, cofactors, monos, rng)
    rows = SymbolicRows(kmap, atoms, row_rng)
    one = tuple(0 for _ in atoms)
    for k, basis in kernels.items():
        cof = cofactors[k]
        cvalue = cofactor_value(kmap, atoms, cof) if symbolic else None
        for free, vec in basis:
            if cof.exponents == one and sum(monos[free]) == 0:
                continue            # P = 1 with K = 1
            try:
                if symbolic:
                    p = reconstruct(rows, scene, cof, monos, free, vec)
                else:
                    p = reconstruct_at_values(kmap, atoms, cof, values, monos, free, vec, rng)
            except (SingularSystemError, ZeroDivisionError) as exc:
                result.unverified.append(f"K = {cof.text(atoms)}: reconstruction failed ({exc})")
                continue
            if symbolic:
                status, how = check_darboux(kmap, atoms, cof, p, cvalue, rng)
            else:
                ok = check_at_points(kmap, atoms, cof, p, rng, fixed=values)
                status = Status.EVIDENCE_EXACT if ok else Status.REFUTED
                how = (f"at {', '.join(f'{k} = {v}' for k, v in values.items())} only: P(f(x)) = K(x) P(x) at 3 "
                       "random exact points x")
            if status is Status.REFUTED:
                result.unverified.append(f"K = {cof.text(atoms)}: the reconstructed {p} fails the exact check")
                continue
            result.darboux.append(DarbouxPolynomial(p, cof, status, how))
            if progress:
                progress(result.darboux[-1])
