"""Kernel coordinates of several HK-bases at once, with all parameters symbolic, from linear relations whose
coefficients involve integrals (recipe (E) with integral columns), the rows i = 0 and one equation with a known
integral (the sum of one coordinate over the bases, e.g. a Theta kernel coordinate).

Only a *candidate*: the caller proves it (rows with iterates, evenness, uniqueness: Prop. "prop: even"). The
integrals enter as symbols first, so that every elimination runs over Q(eps, parameters)[L] with small entries;
they are substituted once, and the known integral last, over factored denominators (`algebra.factored`).
"""
from __future__ import annotations

from typing import Mapping, Sequence

import flint

from hkproof.algebra.factored import Quotient, sum_of_products
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import cramer, pivots_at
from hkproof.algebra.ring import flint_threads
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.block_system import BlockSymmetry
from hkproof.hk.reduced import Relation
from hkproof.hk.transport import Substitution

__all__ = ["complete_coordinates", "generic_point"]


def generic_point(names: Sequence[str]) -> dict[str, flint.fmpq]:
    """Distinct rational values for `names` (where the relations' pivots are read off)."""
    return {n: flint.fmpq(3 * k + 2, 2 * k + 7) for k, n in enumerate(names)}


def complete_coordinates(kmap: KahanMap, bases: Sequence[Sequence[Frac]], relations: Sequence[Relation],
                         integrals: Mapping[str, Frac], known: tuple[Sequence[int], Frac],
                         wanted: Sequence[int], symmetry: BlockSymmetry | None = None) -> list[Frac]:
    """The components `wanted` of the unknowns (the bases' kernel coordinates, block after block, each basis with
    its last element normalized to -1) from: the homogeneous `relations` (coefficients over Q(eps, parameters, the
    symbols of `integrals`)), the rows i = 0 of every basis, and sum_{k in known[0]} a_k = known[1].

    The relations must leave exactly len(bases) + 1 unknowns free; the rows i = 0 and the known equation fix them.
    Each wanted component is completed (the expensive step) only when the relations do not fix it from those found
    so far; with `symmetry` (tau o f = f o tau carrying block to block, `BlockSymmetry`) the images of the found
    components count as found too, assuming the solution is equivariant (the caller proves the candidate anyway).
    """
    if not relations:
        raise HKProofError("no relations: the rows i = 0 and one known integral cannot fix the coordinates")
    if any(not rel.rhs.is_zero() for rel in relations):
        raise HKProofError("the relations must be homogeneous (right-hand side 0); put a known value in `known`")
    lifted = relations[0].rhs.ring
    width = sum(len(b) - 1 for b in bases)
    if any(len(rel.coefficients) != width for rel in relations):
        raise HKProofError(f"relation rows of length {len(relations[0].coefficients)}, but the bases have "
                           f"{width} unknowns")
    rows = [list(rel.coefficients) for rel in relations]
    chosen, pivots = pivots_at(rows, generic_point(lifted.names))
    free = [j for j in range(width) if j not in pivots]
    if len(free) != len(bases) + 1:
        raise HKProofError(f"the relations have rank {len(pivots)}: they leave {len(free)} unknowns free, and the "
                           f"{len(bases)} rows i = 0 and the known integral fix {len(bases) + 1}")
    minor = [[rows[k][j] for j in pivots] for k in chosen]
    solved = {fj: dict(zip(pivots, cramer(minor, [-rows[k][fj] for k in chosen])[0], strict=True)) for fj in free}
    zero = Frac(lifted, 0)
    columns = [[Frac(lifted, int(j == fj)) if j in free else solved[fj][j] for fj in free] for j in range(width)]
    system, targets, start = [], [], 0
    for basis in bases:
        lifted_basis = [phi.to_ring(lifted) for phi in basis]
        block = range(start, start + len(basis) - 1)
        system.append([sum((lifted_basis[k - start] * columns[k][c] for k in block), zero) for c in range(len(free))])
        targets.append(lifted_basis[-1])
        start += len(basis) - 1
    system.append([sum((columns[k][c] for k in known[0]), zero) for c in range(len(free))])
    particular = cramer(system, [*targets, zero])[0]
    direction = cramer(system, [zero] * len(bases) + [Frac(lifted, 1)])[0]
    sigma = Substitution(lifted, kmap.ring, dict(integrals))
    point = generic_point(lifted.names)
    found: dict[int, Frac] = {}
    with flint_threads():
        for j in wanted:
            if j in found:
                continue
            a0, a1 = (Quotient(kmap.ring, *sigma.apply_cancelled(sum((x * u for x, u in zip(columns[j], t, strict=True)),
                                                                     zero)))
                      for t in (particular, direction))
            found[j] = sum_of_products([[a0], [known[1], a1]])
            if symmetry is not None:
                found.update(_carried(found, [len(b) - 1 for b in bases], symmetry))
            found.update(_determined(columns, found, [k for k in wanted if k not in found], sigma, point))
    return [found[j] for j in wanted]


def _carried(found: Mapping[int, Frac], sizes: Sequence[int], symmetry: BlockSymmetry) -> dict[int, Frac]:
    """The images of the found components under the symmetry (block source -> target, in the order of its images),
    those not found yet: more known components for `_determined`, each one substitution."""
    starts = [sum(sizes[:b]) for b in range(len(sizes))]
    out = dict(found)
    for source, target, perm in symmetry.images:
        for k, j in enumerate(perm[:-1]):
            there, here = starts[source] + j, starts[target] + k
            if j < sizes[source] and there in out and here not in out:
                out[here] = symmetry.apply(out[there])
    return {k: v for k, v in out.items() if k not in found}


def _determined(columns: Sequence[Sequence[Frac]], found: Mapping[int, Frac], rest: Sequence[int],
                sigma: Substitution, point: Mapping[str, flint.fmpq]) -> dict[int, Frac]:
    """The components of `rest` that the found ones fix. Every solution of the relations is u_j = columns[j] . t
    (t the free unknowns), so u_j is fixed when its row of `columns` lies in the span of the found components' rows
    (ranks at a generic point); then u_j = sum_k W_k u_k over independent found rows, W by Cramer's rule over
    Q(eps, parameters)[symbols] (small), and a few products with the big found components over factored
    denominators -- much cheaper than the completion itself."""
    if not rest:
        return {}
    known = list(found)
    chosen, pivots = pivots_at([list(columns[k]) for k in known], point)
    if not pivots:          # the found components vanish at the point: they fix nothing that can be solved for
        return {}
    base = [known[i] for i in chosen]
    square = [[columns[k][c] for k in base] for c in pivots]     # square W = columns[j] at the pivot columns
    out = {}
    for j in rest:
        if len(pivots_at([list(columns[k]) for k in (*base, j)], point)[0]) > len(base):
            continue
        weights = cramer(square, [columns[j][c] for c in pivots])[0]
        terms = [[sigma.apply(w), found[k]] for w, k in zip(weights, base, strict=True) if not w.is_zero()]
        out[j] = sum_of_products(terms) if terms else Frac(sigma.target, 0)
    return out
