"""Recipe (E): constant-coefficient linear relations among kernel coordinates, found exactly with symbolic
coefficients (null spaces of exact samples, then polynomial interpolation in eps and the parameters)."""
from __future__ import annotations

import itertools
import math
import random
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Callable, Mapping, Sequence

import flint
import numpy as np

from hkproof import budget
from hkproof.algebra.formula import check_new_names
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import nullspace_q, q_matrix
from hkproof.algebra.modular import EchelonModP, random_prime
from hkproof.algebra.monomials import exponents_upto, value as monomial_value
from hkproof.algebra.ring import Rational, Ring, to_fmpq
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import RelationSearchError
from hkproof.algebra.sampling import random_rational, random_rationals
from hkproof.experiments.profiles import BasisFamily, ProfileProblem, parse_basis
from hkproof.experiments.scene import make_scene
from hkproof.experiments.weights import Weights, scaling_weights
from hkproof.hk.reduced import Relation

if TYPE_CHECKING:
    import sympy

__all__ = ["CoordinateSampler", "find_relations", "FoundRelation", "Polynomial", "RelationSearch"]



@dataclass
class FoundRelation(Relation):
    """A relation found by recipe (E): the row sum_k coefficients[k] * names[k] = rhs of the reduced systems
    (hk.reduced.Relation, coefficients and rhs in Q(eps, parameters)) with the names of its unknowns and how
    often it was checked at fresh samples."""

    names: list[str] = field(default_factory=list)
    checked: int = 0
    normalized_name: str | None = None   # the coordinate set to -1, when named: shown projectively

    def text(self) -> str:
        import sympy
        lhs = sympy.Add(*[sympy.factor(c.to_sympy()) * sympy.Symbol(n)
                          for n, c in zip(self.names, self.coefficients, strict=True) if not c.is_zero()])
        rhs = sympy.factor(self.rhs.to_sympy())
        if self.normalized_name:
            return f"{lhs + rhs * sympy.Symbol(self.normalized_name)} = 0"
        return f"{lhs} = {rhs}"

    def row_at(self, values: Mapping[str, Rational]) -> list[flint.fmpq]:
        """(a_1, ..., a_m, -rhs) at given eps and parameters: the relation as a constant vector."""
        ring = self.rhs.ring
        at = {n: 0 for n in ring.names} | dict(values)
        return [c.evaluate(at) for c in self.coefficients] + [-self.rhs.evaluate(at)]

    def to_dict(self) -> dict:
        return {"relation": self.text(), "coefficients": {n: str(c) for n, c in zip(self.names, self.coefficients, strict=True)},
                "rhs": str(self.rhs), "checked_at_fresh_samples": self.checked}


@dataclass
class RelationSearch:
    """The columns searched, the relations found and how they were found."""

    names: list[str]
    relations: list[FoundRelation] = field(default_factory=list)
    dimension: int = 0
    normalized: list[str] = field(default_factory=list)
    samples: int = 0
    degree: int = 0
    notes: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"columns": self.names, "dimension": self.dimension, "relations": [r.to_dict() for r in self.relations],
                "normalized_to_one": self.normalized, "samples": self.samples, "degree": self.degree,
                "notes": self.notes}


class CoordinateSampler:
    """Kernel coordinates of one or more HK-bases with d = 1 (last coordinate -1) at exact sample points.

    `integrals` are functions h with h o f = h (the caller cites their proofs). A basis that is an earlier one with
    its last function multiplied by such an h has that basis's kernel coordinates times h(x) (sum_k c_k phi_k o f^i
    = phi_l o f^i gives sum_k h c_k phi_k o f^i = (h phi_l) o f^i), so it is not profiled: one evaluation of h."""

    def __init__(self, kmap: KahanMap, bases: Sequence[Sequence[Frac]], rng: random.Random,
                 integrals: Sequence[Frac] = ()):
        self.kmap = kmap
        self.bases = [list(b) for b in bases]
        self.rng = rng
        self.derived: dict[int, tuple[int, Frac]] = {}       # basis j = basis i with its last function times h
        for j, b in enumerate(self.bases):
            source = next(((i, h) for i in range(j) if i not in self.derived and self.bases[i][:-1] == b[:-1]
                           for h in integrals if h * self.bases[i][-1] == b[-1]), None)
            if source is not None:
                self.derived[j] = source
        self.profiled = [j for j in range(len(self.bases)) if j not in self.derived]

    @property
    def width(self) -> int:
        """Columns: the first l_b - 1 coordinates of each kernel, then the constant 1."""
        return sum(len(b) - 1 for b in self.bases) + 1

    def row(self, family: BasisFamily) -> list[flint.fmpq] | None:
        """(c^(1)_1, ..., c^(1)_(l1-1), c^(2)_1, ..., 1) at a random point, or None at a bad point."""
        point = random_rationals(self.rng, len(self.kmap.variables), 99)
        kernels: dict[int, list[flint.fmpq]] = {}
        for j, problem, c in zip(self.profiled, family.problems, family.kernel_vectors(point), strict=True):
            if c is None:
                return None
            if c[-1] != -1:
                raise RelationSearchError(
                    f"the last coordinate of K_Phi vanishes for ({', '.join(map(str, problem.basis))}): "
                    "put last a function whose coefficient is not zero (recipe (B) sets it to -1)")
            kernels[j] = c[:-1]
        at = {**family.scene.fixed, **dict(zip(self.kmap.variables, point, strict=True))}
        for j, (i, h) in self.derived.items():
            if Frac(self.kmap.ring, h.den).evaluate(at) == 0:     # h undefined here: a bad point
                return None
            value = h.evaluate(at)
            kernels[j] = [value * c for c in kernels[i]]
        return [c for j in range(len(self.bases)) for c in kernels[j]] + [flint.fmpq(1)]

    def relation_space(self, values: Mapping[str, Rational], extra: int = 2) -> list[list[flint.fmpq]] | None:
        """Rows spanning the annihilator of the sampled coordinate vectors at these eps and parameter values."""
        scene = make_scene(self.kmap, values)
        family = BasisFamily([ProfileProblem(scene, self.bases[j]) for j in self.profiled])
        rows: list[list[flint.fmpq]] = []
        ranks = EchelonModP()
        stable, tries = 0, 0
        while tries < 4 * self.width + 8:
            budget.check("sampling kernel vectors for recipe (E)")
            tries += 1
            r = self.row(family)
            if r is None:
                continue
            rows.append(r)
            stable = 0 if ranks.add(r) else stable + 1
            if stable == extra:     # the rank mod p stood still for `extra` rows; over Q too, if the two agree
                echelon, rank = q_matrix(rows).rref()
                if rank == ranks.rank:
                    return [[echelon[i, j] for j in range(self.width)] for i in range(rank)]
                ranks, stable = EchelonModP(random_prime(self.rng)), 0     # p divided a minor: another prime
                for row in rows:
                    ranks.add(row)
        return None


def find_relations(kmap: KahanMap, bases: Sequence[str | Sequence[Frac]], *, names: Sequence[str] | None = None,
                   values: Mapping[str, Rational] | None = None, max_degree: int = 6, checks: int = 3,
                   seed: int = 0, integrals: Sequence[Frac] = ()) -> RelationSearch:
    """Recipe (E) exactly: sample the relation space at random rational eps/parameters (some set to 1 by
    weighted homogeneity), interpolate polynomial relation vectors of rising degree, check them at fresh
    samples and restore the normalized names. `integrals`: proven integrals h (`CoordinateSampler`): a basis that
    is an earlier one with its last function times h is sampled as that one's coordinates times h."""
    rng = random.Random(seed)
    fixed = {k: to_fmpq(v) for k, v in (values or {}).items()}
    parsed = [parse_basis(kmap.ring, b) if isinstance(b, str) else list(b) for b in bases]
    names = check_new_names(names, kmap.ring.names, "coordinate name") if names else _default_names(parsed)
    sampler = CoordinateSampler(kmap, parsed, rng, integrals)
    normalized_name = None
    if len(parsed) == 1 and len(names) == len(parsed[0]):
        names, normalized_name = names[:-1], names[-1]
    if len(names) != sampler.width - 1:
        raise RelationSearchError(f"{len(names)} names for {sampler.width - 1} kernel coordinates "
                                  "(name all but the last coordinate of each basis, which is -1)")
    weights = scaling_weights(kmap, [phi for b in parsed for phi in b], list(fixed))
    free = [n for n in (EPS,) + kmap.field.parameters if n not in fixed and n not in weights.normalized]
    search = RelationSearch(names, normalized=list(weights.normalized))

    def sample() -> tuple[list[flint.fmpq], list[list[flint.fmpq]]]:
        for _ in range(20):
            t = [random_rational(rng, 30) for _ in free]
            vals = {**fixed, **{n: flint.fmpq(1) for n in weights.normalized}, **dict(zip(free, t, strict=True))}
            space = sampler.relation_space(vals)
            if space is not None:
                search.samples += 1
                return t, space
        raise RelationSearchError("no sample with a one-dimensional kernel: is every basis an HK-basis with d = 1?")

    width = sampler.width
    generic_t, generic_space = sample()
    search.dimension = width - len(generic_space)
    if search.dimension == 0:
        return search
    fit = _Interpolation(sample, free, width, generic_t)
    found, search.degree = fit.relations(range(width), [], search.dimension, max_degree)
    if len(found) < search.dimension:
        search.notes.append(f"only {len(found)} of {search.dimension} relations up to degree {max_degree}")
    found = _sparsest(fit, found, max_degree)
    fresh = [sample() for _ in range(checks)]
    for rel in found:
        checked = sum(1 for t, space in fresh if all(
            sum((row[k] * _eval(rel[k], t) for k in range(width)), flint.fmpq(0)) == 0 for row in space))
        if checked != len(fresh):
            search.notes.append("an interpolated relation failed a fresh check and was dropped")
            continue
        lifted = _restore(kmap, weights, free, rel, parsed, search)
        search.relations.append(_as_relation(kmap.ring, names, lifted, checked, normalized_name))
    return search


Polynomial = dict[tuple[int, ...], flint.fmpq]      # {exponents of the free parameters: coefficient}


class _Interpolation:
    """Polynomial relation vectors in the free parameters that lie in the sampled relation spaces."""

    def __init__(self, sample, free: Sequence[str], width: int, generic_t: Sequence[flint.fmpq]):
        self.sample = sample
        self.free = list(free)
        self.width = width
        self.generic_t = generic_t
        self.samples: list[tuple[list[flint.fmpq], list[list[flint.fmpq]]]] = []

    def relations(self, columns: Sequence[int], found: list[list[Polynomial]], target: int,
                  max_degree: int) -> tuple[list[list[Polynomial]], int]:
        """Add relations supported on `columns`, of rising degree (fewest terms first), until `target` are
        independent."""
        columns = list(columns)
        found = list(found)
        for degree in range(max_degree + 1):
            monos = exponents_upto(len(self.free), degree, highest_first=False)
            while sum(len(s) for _, s in self.samples) < len(columns) * len(monos) + 8:
                budget.check("interpolating relation coefficients (recipe (E))")
                self.samples.append(self.sample())
            equations = []
            for t, space in self.samples:
                mvals = [monomial_value(m, t) for m in monos]
                for row in space:
                    equations.append([row[k] * mv for k in columns for mv in mvals])
            for vec in sorted(nullspace_q(equations), key=lambda v: sum(1 for c in v if c != 0)):
                candidate: list[Polynomial] = [{} for _ in range(self.width)]
                for ci, k in enumerate(columns):
                    candidate[k] = {m: vec[ci * len(monos) + i] for i, m in enumerate(monos)
                                    if vec[ci * len(monos) + i] != 0}
                if _rank_at(found + [candidate], self.generic_t) > len(found):
                    found.append(candidate)
                if len(found) == target:
                    return found, degree
        return found, max_degree

    def value(self, relation: list[Polynomial]) -> list[flint.fmpq]:
        return [_eval(col, self.generic_t) for col in relation]


def _sparsest(fit: _Interpolation, found: list[list[Polynomial]], max_degree: int,
              max_support: int = 4) -> list[list[Polynomial]]:
    """The same relation space spanned by the simplest relations: every support of at most `max_support`
    columns that carries a relation (seen at a generic sample) is fitted alone, and the fits are taken by
    lowest degree, then fewest columns, while they add to the span; `found` completes the span if needed."""
    if not found:
        return found
    carrying = _carrying_supports([fit.value(r) for r in found], fit.width)
    candidates = []
    for size in range(2, max_support + 1):
        budget.check("choosing the sparsest relations (recipe (E))")
        for support in carrying(size):
            rel, degree = fit.relations(support, [], 1, max_degree)
            if rel:
                candidates.append((degree, size, rel[0]))
    chosen: list[list[Polynomial]] = []
    for _, _, one in sorted(candidates, key=lambda c: c[:2]) + [(0, 0, r) for r in found]:
        if len(chosen) < len(found) and _rank_at(chosen + [one], fit.generic_t) > len(chosen):
            chosen.append(one)
    return chosen


def _carrying_supports(values: Sequence[Sequence[flint.fmpq]], width: int
                       ) -> Callable[[int], list[tuple[int, ...]]]:
    """The supports S of a given size (columns of `width`) for which the span W of the relation vectors `values`
    holds a non-zero vector supported in S. With K a basis of the annihilator of W (integer rows), that is
    rank K_S < |S|. Screened for all S of one size at once: det (G K)_S != 0 mod a prime, for a random G, proves
    K_S of full rank (no vector); the others are decided by the rank mod p of K_S, then over Q."""
    integral = []
    for row in nullspace_q(values):
        scale = math.lcm(*(int(c.q) for c in row))
        integral.append([int(c.p) * (scale // int(c.q)) for c in row])
    prime = 2 ** 61 - 1
    columns_mod = [[v % prime for v in col] for col in zip(*integral)]
    small = 2 ** 31 - 1       # products of two residues fit in int64
    rng = np.random.default_rng(0)
    projection = rng.integers(0, small, size=(min(4, len(integral)), len(integral)), dtype=np.int64)
    reduced = np.array([[v % small for v in row] for row in integral], dtype=np.int64).reshape(len(integral), width)
    projected = np.zeros((len(projection), width), dtype=np.int64)
    for k in range(len(integral)):     # G K mod small, one row of K at a time (no overflow)
        projected = (projected + projection[:, k:k + 1] * reduced[k]) % small

    def exact(support: Sequence[int]) -> bool:
        if flint.nmod_mat([columns_mod[j] for j in support], prime).rank() == len(support):
            return False
        return flint.fmpq_mat([[flint.fmpq(row[j]) for j in support] for row in integral]).rank() < len(support)

    def carrying(size: int) -> list[tuple[int, ...]]:
        supports = list(itertools.combinations(range(width), size))
        if not integral or size >= width:
            return supports
        screened = np.zeros(len(supports), dtype=bool) if size > len(projection) else \
            _determinants_mod(projected[:size], np.array(supports, dtype=np.int64), small) != 0
        return [s for s, full in zip(supports, screened) if not full and exact(s)]

    return carrying


def _determinants_mod(rows: np.ndarray, supports: np.ndarray, prime: int) -> np.ndarray:
    """det rows[:, S] mod `prime` for each row S of `supports` (Leibniz's formula, vectorized over the supports)."""
    size = supports.shape[1]
    total = np.zeros(len(supports), dtype=np.int64)
    for perm in itertools.permutations(range(size)):
        term = np.ones(len(supports), dtype=np.int64)
        for i, j in enumerate(perm):
            term = term * rows[i, supports[:, j]] % prime
        inversions = sum(perm[a] > perm[b] for a in range(size) for b in range(a + 1, size))
        total = (total + (prime - term if inversions % 2 else term)) % prime
    return total


def _default_names(bases: Sequence[Sequence[Frac]]) -> list[str]:
    if len(bases) == 1:
        return [f"c{k + 1}" for k in range(len(bases[0]) - 1)]
    letters = "abcdefghijklmnopqrstuvwxyz"
    return [f"{letters[i]}{k + 1}" for i, b in enumerate(bases) for k in range(len(b) - 1)]


def _eval(poly: dict[tuple[int, ...], flint.fmpq], t: Sequence[flint.fmpq]) -> flint.fmpq:
    return sum((c * monomial_value(m, t) for m, c in poly.items()), flint.fmpq(0))


def _rank_at(relations, t) -> int:
    if not relations:
        return 0
    return q_matrix([[_eval(col, t) for col in rel] for rel in relations]).rank()


def _column_weights(weights: Weights, bases: Sequence[Sequence[Frac]]) -> list[list[flint.fmpq]]:
    """[c_k] = [phi_l] - [phi_k] for each kernel coordinate; the constant column has weight 0."""
    out = []
    for b in bases:
        last = weights.of_frac(b[-1])
        out += [[a - c for a, c in zip(last, weights.of_frac(phi), strict=True)] for phi in b[:-1]]
    return out + [[flint.fmpq(0)] * len(weights.basis)]


def _restore(kmap: KahanMap, weights: Weights, free: Sequence[str], rel, bases, search: RelationSearch):
    """Multiply each term by the monomial in the normalized names that makes the relation weighted homogeneous."""
    ring = kmap.ring
    offsets = _column_weights(weights, bases)
    terms = [(k, dict(zip(free, m, strict=True)), c) for k, col in enumerate(rel) for m, c in col.items()]
    k0, e0, _ = terms[0]
    target = [a + b for a, b in zip(weights.of_monomial(e0), offsets[k0], strict=True)]
    extra: list[dict] = []
    for k, exps, _ in terms:
        e = weights.restore(exps, offsets[k], target)
        if e is None or any(v.q != 1 for v in e.values()):
            search.notes.append("a relation is not weighted homogeneous: shown with "
                                + ", ".join(f"{n} = 1" for n in weights.normalized))
            extra = [{} for _ in terms]
            break
        extra.append(e)
    shift = {n: min((e.get(n, 0) for e in extra), default=0) for n in weights.normalized}
    den = flint.fmpz(1)
    for _, _, c in terms:
        den = den.lcm(c.q)
    columns = [ring.ctx.from_dict({}) for _ in rel]
    for (k, exps, c), e in zip(terms, extra, strict=True):
        mono = [0] * len(ring.names)
        for n, v in exps.items():
            mono[ring.index(n)] += v
        for n, v in e.items():
            mono[ring.index(n)] += int(v - shift[n])
        columns[k] = columns[k] + ring.ctx.from_dict({tuple(mono): int(c * den)})
    content = flint.fmpz(0)
    for p in columns:
        for c in p.coeffs():
            content = content.gcd(c)
    return [p / ring.ctx.constant(int(content)) if content > 1 else p for p in columns]


def _as_relation(ring: Ring, names: Sequence[str], columns, checked: int,
                 normalized_name: str | None) -> FoundRelation:
    """sum a_k c_k + a_0 = 0 shown as sum a_k c_k = -a_0, the first coefficient with a positive leading term."""
    first = next(p for p in columns if not p.is_zero())
    sign = -1 if first.coefficient(0) < 0 else 1
    coefficients = [Frac(ring, sign * p) for p in columns[:-1]]
    return FoundRelation(coefficients, Frac(ring, -sign * columns[-1]), names=list(names), checked=checked,
                         normalized_name=normalized_name)
