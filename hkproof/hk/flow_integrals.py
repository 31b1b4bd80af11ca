"""The polynomial integrals of the continuous flow x' = F(x) of bounded degree, exactly, and their circuits (the
integrals of minimal support, which do not depend on a choice of basis): the functions the paper builds bases from
(Th. "dC Theta": I1, I2, I3 and H4), and `discover`'s last stage too."""
from __future__ import annotations

import itertools
import random

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import cramer, lcm
from hkproof.algebra.modular import kernel_mod_p, random_prime, rank_mod_p
from hkproof.algebra.monomials import exponents_upto, text
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.integrals import lie_derivative

__all__ = ["MAX_CIRCUITS", "continuous_integral_circuits"]

MAX_CIRCUITS = 16    # integral circuits tried (smallest support first)


def continuous_integral_circuits(kmap: KahanMap, degree: int, rng: random.Random) -> list[Frac]:
    """The polynomial integrals of x' = F(x) of degree <= `degree` with minimal support (circuits of the kernel of
    the Lie derivative), exact over Q(parameters), each checked exactly (L_F I = 0)."""
    ring, field = kmap.ring, kmap.field
    n = len(kmap.variables)
    monos = [e for e in exponents_upto(n, degree) if any(e)]
    scale = Frac(ring, lcm([f.to_ring(ring).den for f in field.rhs]))   # a constant time scale clears denominators
    derivs = [lie_derivative(field, Frac.parse(field.ring, text(kmap.variables, e))).to_ring(ring) * scale
              for e in monos]
    phase = [ring.index(v) for v in kmap.variables]
    rows: dict[tuple[int, ...], dict[int, dict]] = {}
    for col, d in enumerate(derivs):
        if not d.den.is_one():
            raise HKProofError("the Lie derivative of a monomial has a denominator in the phase variables: the "
                               "field is not polynomial")
        for m, c in d.num.to_dict().items():
            key = tuple(m[i] for i in phase)
            rest = tuple(0 if i in phase else e for i, e in enumerate(m))
            rows.setdefault(key, {}).setdefault(col, {})[rest] = c
    matrix = [[Frac(ring, ring.ctx.from_dict(row[c])) if c in row else Frac(ring, 0) for c in range(len(monos))]
              for row in rows.values()]
    p = random_prime(rng, 62)
    controls = [rng.randrange(1, p) if i not in phase else 0 for i in range(len(ring.names))]
    mod = [[int(e.residue_at(controls, p) or 0) for e in r] for r in matrix]
    kernel = kernel_mod_p(mod, p)
    if not kernel:
        return []
    support = [c for c in range(len(monos)) if any(v[c] for v in kernel)]
    supports: set[tuple[int, ...]] = set()
    for zeros in itertools.combinations(support, len(kernel) - 1):
        extra = [[1 if c == z else 0 for c in range(len(monos))] for z in zeros]
        restricted = kernel_mod_p(mod + extra, p)
        if len(restricted) == 1:
            supports.add(tuple(c for c in range(len(monos)) if restricted[0][c]))
    minimal = sorted((s for s in supports if not any(set(t) < set(s) for t in supports)), key=len)
    out = []
    for s in minimal[:MAX_CIRCUITS]:
        sub = [[r[c] for c in s] for r in mod]
        chosen: list[int] = []
        for i, r in enumerate(sub):
            if rank_mod_p([sub[k] for k in chosen] + [r], p) > len(chosen):
                chosen.append(i)
        if len(chosen) != len(s) - 1:
            continue
        square = [[matrix[i][c] for c in s[1:]] for i in chosen]
        rhs = [-matrix[i][s[0]] for i in chosen]
        try:
            coeffs = [Frac(ring, 1)] + cramer(square, rhs)[0]
        except (HKProofError, ZeroDivisionError):
            continue
        total = sum((a * Frac.parse(ring, text(kmap.variables, monos[c])) for a, c in zip(coeffs, s, strict=True)),
                    Frac(ring, 0))
        integral = Frac(ring, total.num)
        if not integral.is_zero() and lie_derivative(field, integral.to_ring(field.ring)).is_zero():
            out.append(integral)
    return out
