"""A basis's kernel coordinates and its relations with proven integrals, made exact with eps and the parameters
symbolic (the candidates that hkproof.pipelines.discover.solve hands to Prop. "prop: even").

- The coordinates c_k (c_l = -1) by sparse functional reconstruction over prime fields
  (hkproof.algebra.reconstruction, method "sparse"), the black box being recipe (B) on batches of orbits mod p
  (hkproof.pipelines.discover.blackbox); the names that scaling symmetries allow are set to 1 while sampling and
  restored by weighted homogeneity.
- The relations l.c = R(K') of a plan found mod p (hkproof.pipelines.discover.relation_plan): the entries of l and the
  coefficients of R are small functions of eps and the parameters, rebuilt together on shared probes
  (method "dense"), each restored to its weight; R is then composed with the proven
  integrals (one homogenized compose, hkproof.hk.transport.Substitution).
Everything here is a candidate; the proof checks each identity exactly.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Callable, Iterator, Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.reconstruction import Mapper, Rebuilt, reconstruct
from hkproof.algebra.factored import sum_of_products
from hkproof.algebra.formula import rename
from hkproof.algebra.monomials import Exponents, text
from hkproof.algebra.ring import Ring
from hkproof.budget import Budget
from hkproof.errors import HKProofError
from hkproof.pipelines.discover.blackbox import KernelBlackBox
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.relation_plan import ModularPlan, ModularRelation, evaluate_plan

__all__ = ["PRIME_BITS", "SymbolicRelation", "coordinate_weights", "coordinates", "lift_relations", "restored"]

PRIME_BITS = 50      # the batch black box reduces products exactly below 2^50 (hkproof.dynamics.batch_map)
BATCH = 2048         # probes per call of the batch black box (numpy's per-call cost is amortized)
Weight = list[flint.fmpq]


@dataclass
class SymbolicRelation:
    """l.c = rhs with l free of x (in Q(eps, parameters)) and rhs = R(K') a function of proven integrals; `formula` is
    R as text over the names of K' (for the certificate)."""

    combination: list[Frac]
    rhs: Frac
    formula: str
    knowns: list[str]


def _weight_of_exponents(ctx: SearchContext, e: Exponents) -> Weight:
    return ctx.weights.of_monomial({v: k for v, k in zip(ctx.kmap.variables, e, strict=True) if k})


def coordinate_weights(ctx: SearchContext, basis: Sequence[Exponents]) -> list[Weight]:
    """[c_k] = [phi_l] - [phi_k] for the coordinates of recipe (B) (c_l = -1)."""
    last = _weight_of_exponents(ctx, basis[-1])
    return [[a - b for a, b in zip(last, _weight_of_exponents(ctx, e), strict=True)] for e in basis[:-1]]


def restored(ctx: SearchContext, rebuilt: Rebuilt, names: Sequence[str], weight: Weight) -> Frac:
    """A rebuilt function of `names` (the normalized names were 1), made weighted homogeneous of `weight` again."""
    h = rebuilt.to_frac(ctx.kmap.ring, names)
    restored = ctx.weights.restore_frac(h, weight)
    if restored is None:
        raise HKProofError(f"{h} is not weighted homogeneous of the expected weight: the reconstruction is wrong")
    return restored


def _free_residues(ctx: SearchContext, t: Sequence[int]) -> dict[str, int]:
    return {**{n: 1 for n in ctx.weights.normalized}, **dict(zip(ctx.free, t, strict=True))}


def coordinates(ctx: SearchContext, basis: Sequence[Exponents], rng: random.Random, *, budget: Budget | None = None,
                mapper: Mapper | None = None, progress: Callable[[dict], None] | None = None) -> list[Frac]:
    """c_1, ..., c_(l-1) of the kernel of `basis` (c_l = -1) with eps and the parameters symbolic, by sparse
    reconstruction over prime fields (a candidate)."""
    last = len(basis) - 1
    seed = rng.randrange(2 ** 63)       # one for the basis: its coordinates probe shared points (KernelBlackBox)
    return [-kernel_ratio(ctx, basis, k, last, random.Random(seed), budget=budget, mapper=mapper,  # c_k/c_l = -c_k
                          progress=progress) for k in range(last)]


def kernel_ratio(ctx: SearchContext, basis: Sequence[Exponents], k: int, j: int, rng: random.Random, *,
                 budget: Budget | None = None, mapper: Mapper | None = None,
                 progress: Callable[[dict], None] | None = None) -> Frac:
    """c_k / c_j of the kernel of `basis` with eps and the parameters symbolic, by sparse reconstruction over prime
    fields (the normalized names set to 1 and restored to the weight [phi_j] - [phi_k]): a candidate."""
    inputs = list(ctx.free) + list(ctx.kmap.variables)
    box = KernelBlackBox(ctx.kmap, basis, k, j, inputs, {n: 1 for n in ctx.weights.normalized})
    rec = reconstruct(box, len(inputs), rng=rng, budget=budget or ctx.budget, bits=PRIME_BITS,
                      mapper=mapper or ctx.mapper, progress=progress, batch_size=BATCH)[0]
    weight = [a - b for a, b in zip(_weight_of_exponents(ctx, basis[j]), _weight_of_exponents(ctx, basis[k]),
                                    strict=True)]
    return restored(ctx, rec, inputs, weight)


def _flat(relations: Sequence[ModularRelation]) -> list[int]:
    """The values that vary with eps and the parameters: the entries of l beside its pivot, the coefficients of N and
    of D beside D's first (normalized) one."""
    out: list[int] = []
    for r in relations:
        out += [c for k, c in enumerate(r.combination) if c and k != r.pivot]
        out += [r.numerator[m] for m in sorted(r.numerator)]
        out += [r.denominator[m] for m in sorted(r.denominator) if m != r.lead]
    return out


def lift_relations(ctx: SearchContext, basis: Sequence[Exponents], known: Mapping[str, Frac], plan: ModularPlan,
                   rng: random.Random) -> list[SymbolicRelation]:
    """The relations of `plan` with eps and the parameters symbolic: l and R rebuilt on shared probes and restored
    to their weights, R composed with the proven integrals (and the relations before it)."""
    width = len(_flat(plan.relations))

    def box(p: int, t: Sequence[int]) -> list[int] | None:
        controls = {n: v for n, v in _free_residues(ctx, t).items()}
        found = evaluate_plan(ctx.kmap, basis, known, plan, p, controls, rng)
        return None if found is None else _flat(found)

    flat = reconstruct(lambda p, ts: [box(p, t) for t in ts], len(ctx.free), width, method="dense",
                       rng=rng) if width else []
    return _assemble(ctx, basis, known, plan, iter(flat))


def _assemble(ctx: SearchContext, basis: Sequence[Exponents], known: Mapping[str, Frac], plan: ModularPlan,
              flat: Iterator[Rebuilt]) -> list[SymbolicRelation]:
    """The symbolic relations from the rebuilt values, in the order of `_flat`, each restored to its weight."""
    ring = ctx.kmap.ring
    weights = coordinate_weights(ctx, basis)
    free = list(ctx.free)
    values: dict[str, Frac] = dict(known)
    value_weights = {n: ctx.weights.of_frac(h) for n, h in known.items()}
    out: list[SymbolicRelation] = []
    for i, rel in enumerate(plan.relations):
        target = weights[rel.pivot]
        combination = []
        for k, c in enumerate(rel.combination):
            if not c:
                combination.append(Frac(ring, 0))
            elif k == rel.pivot:
                combination.append(Frac(ring, 1))
            else:
                combination.append(restored(ctx, next(flat), free, [a - b for a, b in
                                                                     zip(target, weights[k], strict=True)]))
        knowns = rel.knowns
        kw = [value_weights[n] for n in knowns]

        def weight(m: Exponents) -> Weight:
            total = [flint.fmpq(0)] * len(target)
            for e, w in zip(m, kw, strict=True):
                total = [a + e * b for a, b in zip(total, w, strict=True)]
            return total
        lead = weight(rel.lead)
        num_coeffs = {m: restored(ctx, next(flat), free, [a + b - c for a, b, c in zip(target, lead, weight(m),
                                                                                          strict=True)])
                      for m in sorted(rel.numerator)}
        den_coeffs = {rel.lead: Frac(ring, 1)}
        den_coeffs.update({m: restored(ctx, next(flat), free, [a - b for a, b in zip(lead, weight(m), strict=True)])
                           for m in sorted(rel.denominator) if m != rel.lead})
        rhs, formula = _compose(ring, knowns, num_coeffs, den_coeffs, values)
        name = f"_l{i}"
        values[name] = rhs
        value_weights[name] = target
        out.append(SymbolicRelation(combination, rhs, formula, list(knowns)))
    return out


def _compose(ring: Ring, knowns: Sequence[str], num: Mapping[Exponents, Frac], den: Mapping[Exponents, Frac],
             values: Mapping[str, Frac]) -> tuple[Frac, str]:
    """R = N/D over the names `knowns` (coefficients in Q(eps, parameters)) composed with their values: N(K') and D(K')
    each as a sum of products over factored denominators (hkproof.algebra.factored: no gcd of a big numerator, no
    common denominator raised to a power), then one division."""
    def poly(coeffs: Mapping[Exponents, Frac]) -> Frac:
        terms = [[c, *[values[n] for n, e in zip(knowns, m, strict=True) for _ in range(e)]]
                 for m, c in coeffs.items() if not c.is_zero()]
        return sum_of_products(terms) if terms else Frac(ring, 0)
    source = ring.extend([f"y_{n}" for n in knowns])
    ys = [f"y_{n}" for n in knowns]

    def text_of(coeffs: Mapping[Exponents, Frac]) -> str:
        return " + ".join(f"({c})*{text(ys, m)}" for m, c in coeffs.items()) or "0"
    formula = rename(str(Frac.parse(source, text_of(num)) / Frac.parse(source, text_of(den))),
                     dict(zip(ys, knowns, strict=True)))
    return poly(num) / poly(den), formula
