"""Darboux polynomials P o f = K P of a Kahan map, invariant measures dx / P, and the integrals P_i / P_j.

Recipe (after Celledoni, Evripidou, McLaren, Owren, Quispel, Tapley, van der Kamp, "Using discrete Darboux polynomials
to detect and determine preserved measures and integrals of rational maps", 2019): the cofactors K are tried among
the products of the irreducible factors of the numerator and denominator of det Df; for each K the coefficients of
P (all monomials of degree <= D) solve a linear system sampled at random points mod a large prime at random rational
eps and parameters; each kernel vector is reconstructed with eps and the parameters symbolic (Cramer's rule on its
support, at rational points) and then checked exactly: P(N/Delta) = K P in Q(x, eps, params).
"""
from __future__ import annotations

import itertools
import random
from dataclasses import dataclass, field
from typing import Sequence

import flint

from hkproof.algebra.fraction import Frac, homogenized_compose, poly_str
from hkproof.algebra.linalg import cramer, lcm
from hkproof.algebra.ring import Ring, get_ring
from hkproof.dynamics.degrees import random_prime
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, ResourceLimitError, SingularSystemError
from hkproof.hk.jacobian import jacobian_determinant, matrix_identity_holds
from hkproof.proof.status import Status


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
    """P with P o f = K P; `status` verified when the identity was checked exactly with everything symbolic."""

    poly: flint.fmpz_mpoly
    cofactor: Cofactor
    status: Status
    detail: str = ""


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


# ---- modular search --------------------------------------------------------------------------------------------------
def monomials(n: int, degree: int) -> list[tuple[int, ...]]:
    """Exponent vectors of total degree <= degree, highest degree first (so that constants are free columns)."""
    out = [m for d in range(degree, -1, -1) for m in _compositions(n, d)]
    return out


def _compositions(n: int, d: int):
    if n == 1:
        yield (d,)
        return
    for first in range(d, -1, -1):
        for rest in _compositions(n - 1, d - first):
            yield (first,) + rest


class ModularScene:
    """The map, the atoms and monomials evaluated mod p at fixed eps and parameters."""

    def __init__(self, kmap: KahanMap, atoms: Sequence[Atom], values: dict[str, flint.fmpq], prime: int):
        self.kmap, self.atoms, self.prime = kmap, atoms, prime
        names = kmap.ring.names
        self.fixed = [(names.index(k), int(v.p) * pow(int(v.q), -1, prime) % prime) for k, v in values.items()]
        self.ctx = flint.nmod_mpoly_ctx.get(kmap.variables, prime, "degrevlex")  # type: ignore[call-arg, arg-type]  # flint's stubs lag the API
        nums, delta = kmap.explicit
        self.nums = [self.reduce(p) for p in nums]
        self.delta = self.reduce(delta)
        self.atom_polys = [self.reduce(a.poly) for a in atoms]

    def reduce(self, p: flint.fmpz_mpoly) -> flint.nmod_mpoly:
        """p with eps and the parameters fixed, mod p, as a polynomial in the phase variables."""
        names = self.kmap.ring.names
        xi = [names.index(v) for v in self.kmap.variables]
        data: dict[tuple[int, ...], int] = {}
        for m, c in p.to_dict().items():
            coeff = int(c) % self.prime
            for j, v in self.fixed:
                coeff = coeff * pow(v, m[j], self.prime) % self.prime
            key = tuple(m[i] for i in xi)
            data[key] = (data.get(key, 0) + coeff) % self.prime
        return self.ctx.from_dict({k: c for k, c in data.items() if c})

    def sample(self, rng: random.Random) -> tuple[list[int], list[int], list[int]] | None:
        """(x, f(x), atom values) at a random point, or None where Delta or an atom vanishes."""
        p = self.prime
        x = [rng.randrange(p) for _ in self.kmap.variables]
        d = int(self.delta(*x))
        if d == 0:
            return None
        inv = pow(d, -1, p)
        fx = [int(n(*x)) * inv % p for n in self.nums]
        vals = [int(q(*(fx if a.pulled else x))) for a, q in zip(self.atoms, self.atom_polys, strict=True)]
        if any(v == 0 for v in vals):
            return None
        return x, fx, vals


def _monomial_values(point: Sequence[int], monos: Sequence[tuple[int, ...]], p: int) -> list[int]:
    out = []
    for m in monos:
        v = 1
        for xi, e in zip(point, m, strict=True):
            if e:
                v = v * pow(xi, e, p) % p
        out.append(v)
    return out


def modular_kernels(scene: ModularScene, cofactors: Sequence[Cofactor], monos: Sequence[tuple[int, ...]],
                    rng: random.Random, extra: int = 8) -> dict[int, list[tuple[int, list[int]]]]:
    """For each cofactor (by index), the rref kernel basis of P -> P o f - K P on the monomials, mod p."""
    p = scene.prime
    samples: list = []
    while len(samples) < len(monos) + extra:
        s = scene.sample(rng)
        if s is not None:
            x, fx, vals = s
            samples.append((_monomial_values(x, monos, p), _monomial_values(fx, monos, p), vals))
    out = {}
    for k, cof in enumerate(cofactors):
        rows = []
        for mx, mf, vals in samples:
            kv = 1
            for v, e in zip(vals, cof.exponents, strict=True):
                if e:
                    kv = kv * pow(v, e % (p - 1), p) % p
            rows.append([(b - kv * a) % p for a, b in zip(mx, mf, strict=True)])
        kernel = _kernel_mod_p(rows, len(monos), p)
        if kernel:
            out[k] = kernel
    return out


def _kernel_mod_p(rows: list[list[int]], ncols: int, p: int) -> list[tuple[int, list[int]]]:
    """rref kernel basis mod p: (free column, vector) with 1 at that column, 0 at the other free columns."""
    r, rank = flint.nmod_mat(rows, p).rref()
    pivots = [next(j for j in range(ncols) if int(r[i, j]) != 0) for i in range(rank)]
    basis = []
    for free in (j for j in range(ncols) if j not in pivots):
        v = [0] * ncols
        v[free] = 1
        for i, pj in enumerate(pivots):
            v[pj] = (-int(r[i, free])) % p
        basis.append((free, v))
    return basis


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
            x = {v: flint.fmpq(self.rng.randint(-9, 9), self.rng.randint(1, 5)) for v in self.kmap.variables}
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

    def row(self, k: int, cofactor: Cofactor, monos: Sequence[tuple[int, ...]]) -> list[Frac]:
        pt = self.point(k)
        kv = Frac(self.small, 1)
        for v, e in zip(pt["atoms"], cofactor.exponents, strict=True):
            if e:
                kv = kv * v ** e
        return [_monomial(pt["fx"], m) - kv * _monomial(pt["x"], m) for m in monos]


def _monomial(values: Sequence[Frac], m: tuple[int, ...]) -> Frac:
    out = Frac(values[0].ring, 1)
    for v, e in zip(values, m, strict=True):
        if e:
            out = out * v ** e
    return out


def reconstruct(rows: SymbolicRows, scene: ModularScene, cofactor: Cofactor, monos: Sequence[tuple[int, ...]],
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
                          monos: Sequence[tuple[int, ...]], free: int, vector: Sequence[int],
                          rng: random.Random) -> flint.fmpz_mpoly:
    """The kernel vector over Q at the search's fixed eps and parameters (for maps too large for the symbolic
    reconstruction): rows at rational points x, on the modular vector's support, solved exactly."""
    support = [j for j, c in enumerate(vector) if c]
    unknowns = [j for j in support if j != free]
    rows: list[list[flint.fmpq]] = []
    rank = 0
    while rank < len(unknowns):
        x = {v: flint.fmpq(rng.randint(-9, 9), rng.randint(1, 5)) for v in kmap.variables}
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
        row = [_monomial_q(fs, monos[j]) - k * _monomial_q(xs, monos[j]) for j in support]
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
    ring = kmap.ring
    small = get_ring((EPS,) + kmap.field.parameters)
    return _poly_in_ring(ring, {m: Frac.rational(small, c) for m, c in coeffs.items()}, kmap.variables)


def _monomial_q(values: Sequence[flint.fmpq], m: tuple[int, ...]) -> flint.fmpq:
    out = flint.fmpq(1)
    for v, e in zip(values, m, strict=True):
        if e:
            out *= v ** e
    return out


def _rank_mod(rows: Sequence[Sequence[Frac]], cols: Sequence[int], p: int) -> int:
    """Rank mod p of the columns `cols` at a random value of eps and the parameters (a lower bound of the rank)."""
    rng = random.Random(p + len(rows))
    small = rows[0][0].ring
    while True:
        point = [rng.randrange(1, p) for _ in small.names]
        try:
            vals = [[_mod(r[j], point, p) for j in cols] for r in rows]
        except ZeroDivisionError:
            continue
        return flint.nmod_mat(vals, p).rank()


def _mod(f: Frac, point: Sequence[int], p: int) -> int:
    den = int(f.den(*point)) % p
    if den == 0:
        raise ZeroDivisionError
    return int(f.num(*point)) % p * pow(den, -1, p) % p


def _poly_in_ring(ring: Ring, coeffs: dict[tuple[int, ...], Frac], variables: Sequence[str]
                  ) -> flint.fmpz_mpoly:
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
        pt = {n: flint.fmpq(rng.randint(-9, 9) or 1, rng.randint(1, 7)) for n in ring.names}
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


def check_darboux(kmap: KahanMap, atoms: Sequence[Atom], cofactor: Cofactor, p: flint.fmpz_mpoly,
                  value: Frac | None = None, rng: random.Random | None = None) -> tuple[Status, str]:
    """Is P o f = K P? Verified (or refuted) exactly in Q(x, eps, params) when K's `value` is given (see
    cofactor_value); otherwise evidence(exact) (or refuted) at three random exact points."""
    if value is not None:
        pf = Frac(kmap.ring, p)
        ok = kmap.pullback(pf) == value * pf
        return (Status.VERIFIED if ok else Status.REFUTED), "P(N/Delta) = K P in Q(x, eps, params)"
    ok = check_at_points(kmap, atoms, cofactor, p, rng or random.Random(0))
    return ((Status.EVIDENCE_EXACT if ok else Status.REFUTED),
            "P(f(x)) = K(x) P(x) at 3 random exact points (x, eps, params)")


def search_darboux(kmap: KahanMap, degree: int = 4, *, seed: int = 0, symbolic_limit: int = 4,
                   progress=None) -> DarbouxSearch:
    """Darboux polynomials of degree <= `degree` with cofactors among the products of the factors of det Df, each
    reconstructed with eps and the parameters symbolic and checked exactly (verified) when the system has at most
    `symbolic_limit` phase variables; otherwise reconstructed at the search's rational eps and parameters and checked
    at random exact points there (evidence(exact) at those values only)."""
    if degree < 1:
        raise HKProofError(f"the degree must be at least 1, got {degree}")
    rng = random.Random(seed)
    atoms, jac = jacobian_atoms(kmap, expand_limit=symbolic_limit)
    cofactors = candidate_cofactors(jac)
    monos = monomials(len(kmap.variables), degree)
    symbolic = len(kmap.variables) <= symbolic_limit
    if symbolic:        # values for the modular search only: large random rationals avoid special cases
        values = {n: flint.fmpq(rng.randint(2, 40) * rng.choice((-1, 1)), rng.randint(1, 40))
                  for n in (EPS,) + kmap.field.parameters}
    else:               # the results hold at these values: small ones give readable polynomials
        ints = rng.sample([k for k in range(-9, 10) if k], len(kmap.field.parameters))
        values = {EPS: flint.fmpq(1, rng.randint(3, 11)), **dict(zip(kmap.field.parameters, map(flint.fmpq, ints), strict=True))}
    prime = random_prime(rng)
    scene = ModularScene(kmap, atoms, values, prime)
    kernels = modular_kernels(scene, cofactors, monos, rng)
    result = DarbouxSearch(kmap.field.name, degree, atoms, jac, values=values, prime=prime,
                           jacobian_lemma=matrix_identity_holds(kmap), symbolic=symbolic)
    rows = SymbolicRows(kmap, atoms, random.Random(seed + 1))
    one = tuple(0 for _ in atoms)
    for k, basis in kernels.items():
        cof = cofactors[k]
        value = cofactor_value(kmap, atoms, cof) if symbolic else None
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
                status, how = check_darboux(kmap, atoms, cof, p, value, rng)
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
    return result
