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

from hkproof.algebra.factored import sum_of_products
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import cramer, pivots_at
from hkproof.algebra.ring import flint_threads
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.reduced import Relation
from hkproof.hk.transport import Substitution

__all__ = ["complete_coordinates", "generic_point"]


def generic_point(names: Sequence[str]) -> dict[str, flint.fmpq]:
    """Distinct rational values for `names` (where the relations' pivots are read off)."""
    return {n: flint.fmpq(3 * k + 2, 2 * k + 7) for k, n in enumerate(names)}


def complete_coordinates(kmap: KahanMap, bases: Sequence[Sequence[Frac]], relations: Sequence[Relation],
                         integrals: Mapping[str, Frac], known: tuple[Sequence[int], Frac],
                         wanted: Sequence[int]) -> list[Frac]:
    """The components `wanted` of the unknowns (the bases' kernel coordinates, block after block, each basis with
    its last element normalized to -1) from: the homogeneous `relations` (coefficients over Q(eps, parameters, the
    symbols of `integrals`)), the rows i = 0 of every basis, and sum_{k in known[0]} a_k = known[1].

    The relations must leave exactly len(bases) + 1 unknowns free; the rows i = 0 and the known equation fix them.
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
    found: dict[int, Frac] = {}
    with flint_threads():
        for j in wanted:
            if j in found:
                continue
            a0 = sigma.apply(sum((x * u for x, u in zip(columns[j], particular, strict=True)), zero))
            a1 = sigma.apply(sum((x * u for x, u in zip(columns[j], direction, strict=True)), zero))
            found[j] = sum_of_products([[a0], [known[1], a1]])
            found.update(_from_relations(rows, found, [k for k in wanted if k not in found], sigma))
    return [found[j] for j in wanted]


def _from_relations(rows: Sequence[Sequence[Frac]], found: Mapping[int, Frac], rest: Sequence[int],
                    sigma: Substitution) -> dict[int, Frac]:
    """The remaining components at once, when the relations that involve only found and remaining unknowns fix
    them: rest = W found with W small (Cramer over Q(eps, parameters)[symbols]), then a few products with the big
    found components over factored denominators -- much cheaper than the completion itself. {} if they do not."""
    if not rest:
        return {}
    inside = [row for row in rows if all(c.is_zero() or k in found or k in rest for k, c in enumerate(row))]
    if not inside:
        return {}
    chosen, pivots = pivots_at([[row[k] for k in rest] for row in inside], generic_point(rows[0][0].ring.names))
    if len(pivots) < len(rest):
        return {}
    square = [[inside[i][k] for k in rest] for i in chosen]
    weights = {k: cramer(square, [-inside[i][k] for i in chosen])[0] for k in found}
    out = {}
    for n, r in enumerate(rest):
        terms = [[sigma.apply(weights[k][n]), found[k]] for k in found if not weights[k][n].is_zero()]
        out[r] = sum_of_products(terms) if terms else Frac(sigma.target, 0)
    return out
