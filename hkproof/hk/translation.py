"""A translation symmetry of the parameters (w -> w + c(1, ..., 1)): prove a reduced HK system on the slice
w_pivot = 0 and lift the result, so that every parameter stays symbolic with one variable fewer in the work."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational, Ring
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.reduced import Relation, prove_by_evenness, verify_by_evenness
from hkproof.proof.certificate import Certificate


@dataclass(frozen=True)
class ParameterTranslation:
    """The shift of the parameters `names` by one common c; `pivot` (one of them) is 0 on the slice.

    A rational function h is invariant iff sum_n dh/dn = 0 (over Q the infinitesimal invariance integrates).
    An invariant h is determined by its restriction h0 to the slice: h(w) = h0(w - w_pivot (1, ..., 1)).
    """

    names: tuple[str, ...]
    pivot: str

    def __post_init__(self) -> None:
        if self.pivot not in self.names:
            raise HKProofError(f"the pivot {self.pivot!r} is not one of the shifted parameters {self.names}")

    def is_invariant(self, h: Frac) -> bool:
        """sum_n dh/dw_n == 0 over the shifted parameters, exactly: D(num) den == num D(den), no gcd."""
        shifted = [n for n in self.names if n in h.ring.names]

        def d(p):
            return sum((p.derivative(n) for n in shifted), p - p)

        return d(h.num) * h.den == h.num * d(h.den)

    def slice_ring(self, ring: Ring) -> Ring:
        return ring.drop([self.pivot])

    def restrict(self, h: Frac) -> Frac:
        """h on the slice w_pivot = 0."""
        return h.specialize({self.pivot: 0}, self.slice_ring(h.ring))

    def lift(self, h0: Frac, ring: Ring) -> Frac:
        """The invariant function of `ring` whose restriction is h0: w_n -> w_n - w_pivot (an automorphism, so
        lowest terms are kept)."""
        pivot = ring.gen(self.pivot)
        args = [ring.gen(n) - pivot if n in self.names else ring.gen(n) for n in h0.ring.names]
        return Frac(ring, h0.num.compose(*args), h0.den.compose(*args), reduced=True)

    def restrict_relation(self, rel: Relation) -> Relation:
        return Relation([self.restrict(c) for c in rel.coefficients], self.restrict(rel.rhs), rel.source)

    def slice_map(self, kmap: KahanMap) -> KahanMap:
        """The Kahan map of the field with w_pivot = 0."""
        return kahan_map(kmap.field.specialize({self.pivot: 0}))


def verify_on_slice(cert: Certificate, kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac],
                    target: Frac, names: Sequence[str], candidate: Sequence[Frac], point: Mapping[str, Rational],
                    iterates: Sequence[int] = (0, 1), relations: Sequence[Relation] = ()) -> list[Frac]:
    """Prop. "prop: even" for a candidate, checked on the slice w_pivot = 0 of a translation-invariant system.

    If f, the basis, the target, the relations and the candidate are invariant, the residual of every equation
    is invariant, and so is the system's determinant: both vanish identically iff they vanish on the slice.
    Parity in eps is untouched by the shift. So `verify_by_evenness` on the slice proves the full statement.
    """
    _require_invariant(cert, kmap, shift, basis, target, relations, dict(zip(names, candidate)))
    small, sbasis, starget, srelations = _restricted(kmap, shift, basis, target, relations)
    verify_by_evenness(cert, small, sbasis, starget, names, [shift.restrict(a) for a in candidate],
                       {k: v for k, v in point.items() if k != shift.pivot}, iterates, srelations)
    for n, a in zip(names, candidate):
        cert.formula(n, a)
    return list(candidate)


def prove_on_slice(cert: Certificate, kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac],
                   target: Frac, names: Sequence[str], iterates: Sequence[int] = (0, 1),
                   relations: Sequence[Relation] = ()) -> list[Frac]:
    """Prop. "prop: even" / recipe (D) on the slice w_pivot = 0 of a translation-invariant system, lifted.

    The system being invariant, so is its unique solution: it is the lift of the slice's solution, and every
    check of `prove_by_evenness` made on the slice holds for all parameters.
    """
    _require_invariant(cert, kmap, shift, basis, target, relations, {})
    small, sbasis, starget, srelations = _restricted(kmap, shift, basis, target, relations)
    solution = prove_by_evenness(cert, small, sbasis, starget, names, iterates, srelations)
    lifted = [shift.lift(a, kmap.ring) for a in solution]
    for n, a in zip(names, lifted):
        cert.formula(n, a)
    return lifted


def _restricted(kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac], target: Frac,
                relations: Sequence[Relation]) -> tuple[KahanMap, list[Frac], Frac, list[Relation]]:
    return (shift.slice_map(kmap), [shift.restrict(b) for b in basis], shift.restrict(target),
            [shift.restrict_relation(rel) for rel in relations])


def _require_invariant(cert: Certificate, kmap: KahanMap, shift: ParameterTranslation, basis: Sequence[Frac],
                       target: Frac, relations: Sequence[Relation], candidate: Mapping[str, Frac]) -> None:
    """The step that licenses working on the slice: everything the system is made of is invariant."""
    with cert.step(f"the system is invariant under ({', '.join(shift.names)}) -> (..) + c",
                   "sum of the partial derivatives in the shifted parameters is 0, exactly", kmap.ring) as s:
        parts: dict[str, Frac] = {f"component {i + 1} of f": c for i, c in enumerate(kmap.components())}
        parts.update({f"basis function {k + 1}": b for k, b in enumerate(basis)})
        parts["the target"] = target
        for k, rel in enumerate(relations):
            parts.update({f"relation {k + 1}, coefficient {j + 1}": c for j, c in enumerate(rel.coefficients)})
            parts[f"relation {k + 1}, right-hand side"] = rel.rhs
        parts.update({f"candidate {n}": a for n, a in candidate.items()})
        for what, h in parts.items():
            if not shift.is_invariant(h):
                s.inconclusive(f"{what} is not invariant under the shift, so the slice {shift.pivot} = 0 does "
                               f"not decide the claim (prove it without the slice): {h}")
        s.note(f"so every residual and the determinant are invariant: checking them at {shift.pivot} = 0 proves "
               f"them for all {', '.join(shift.names)}")
