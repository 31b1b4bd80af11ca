"""The second iterate f o f of a Kahan map as a plain composition, and its common factor (sec. 6.2, Table "f2")."""
from __future__ import annotations

import time
from typing import Callable, Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac, homogenized_compose
from hkproof.algebra.linalg import solve_overdetermined
from hkproof.algebra.ring import Rational, Ring, get_ring, to_fmpq
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError
from hkproof.hk.expansion import support_degrees
from hkproof.hk.symmetries import SignedPermutation
from hkproof.hk.translation import ParameterTranslation

__all__ = ["interpolated_gcd", "orbit_samples", "plain_composition"]


def plain_composition(kmap: KahanMap, polys: Mapping[str, flint.fmpz_mpoly]
                      ) -> tuple[dict[str, flint.fmpz_mpoly], dict[str, float]]:
    """P_h(N, Delta) for each P (the numerator of P o f, one homogenized compose each; sec. 6.2 before Table "f2"),
    with the seconds each took."""
    nums, delta = kmap.explicit
    out, seconds = {}, {}
    for key, p in polys.items():
        start = time.perf_counter()
        out[key] = homogenized_compose(kmap.ring, p, kmap.variables, nums, delta)[0]
        seconds[key] = time.perf_counter() - start
    return out, seconds


def interpolated_gcd(kmap: KahanMap, a: flint.fmpz_mpoly, b: flint.fmpz_mpoly,
                     points: Sequence[Sequence[Rational]], form_degree: Callable[[tuple[int, ...]], int],
                     symmetry: SignedPermutation | None = None, translation: ParameterTranslation | None = None
                     ) -> flint.fmpz_mpoly:
    """A candidate for g = gcd(a_h(N, Delta), b_h(N, Delta)) normalized by g(x, 0) = 1 (sec. 6.2, Table "f2"),
    from gcds at eps = 1 and the parameters at `points`; the caller proves it by exact division.

    It rests on the weighted homogeneity of the Kahan map of a homogeneous quadratic field (x -> lambda x,
    eps -> eps/lambda: the eps-degree of a term of g equals its degree in x) and on `form_degree`: the coefficient
    of x^e in g is a form of degree form_degree(e) in the parameters, fixed by its values at the points.
    With `symmetry` (a signed permutation sigma under which g is invariant, as the common factor of a map that
    commutes with sigma is), each gcd at a point w also gives g at the points of w's orbit, x relabeled: one gcd
    per orbit (`orbit_samples`). With `translation` (a shift of every parameter under which g is invariant, as the
    common factor of an invariant map is), each sample is moved to the slice w_pivot = 0 and the forms are
    interpolated in the other parameters only: k + 1 unknowns for a form of degree k in two parameters, against
    (k + 1)(k + 2)/2 in three, so fewer gcds; the candidate is then lifted off the slice.
    """
    r, phase, params = kmap.ring, kmap.variables, kmap.field.parameters
    small = get_ring(tuple(phase))
    nums, delta = kmap.explicit
    generic = [support_degrees(r, q, phase)["degree"] for q in (delta, a, b)]
    samples = []
    for w in points:
        values = {EPS: 1, **dict(zip(params, w, strict=True))}
        n = [r.specialize_poly(p, values, small)[0] for p in nums]
        d = r.specialize_poly(delta, values, small)[0]
        sa = r.specialize_poly(a, values, small)[0]
        sb = r.specialize_poly(b, values, small)[0]
        if [q.total_degree() for q in (d, sa, sb)] != generic:
            raise HKProofError(f"at the parameters {list(w)} the degree of Delta, a or b in {list(phase)} drops "
                               "(an unlucky point: the homogenized composition would change)")
        g = homogenized_compose(small, sa, phase, n, d)[0].gcd(homogenized_compose(small, sb, phase, n, d)[0])
        constant = int(g.coefficient(len(g) - 1))
        if g.monoms()[-1] != (0,) * len(phase) or constant not in (1, -1):
            raise HKProofError(f"the gcd at the parameters {list(w)} has no constant term +-1: no normalization "
                               "g(x, 0) = 1")
        samples.append(g * constant)
    if symmetry is not None:
        points, samples = orbit_samples(symmetry, small, params, points, samples)
    names, out = tuple(params), r
    if translation is not None:
        if translation.velocity or set(translation.names) != set(params):
            raise HKProofError(f"the translation {translation} must shift exactly the parameters {list(params)}")
        pivot = params.index(translation.pivot)
        names, out = tuple(n for n in params if n != translation.pivot), translation.slice_ring(r)
        moved = {tuple(to_fmpq(w[i]) - to_fmpq(w[pivot]) for i in range(len(params)) if i != pivot): g
                 for w, g in zip(points, samples, strict=True)}
        points, samples = list(moved), list(moved.values())
    coefficients = [g.to_dict() for g in samples]
    monomials = {m for g in coefficients for m in g}
    data: dict[tuple[int, ...], int] = {}
    systems: dict[int, flint.fmpq_mat] = {}          # one per form degree
    for m in monomials:
        k = form_degree(m)
        forms = _exponents(len(names), k)
        if k not in systems:
            systems[k] = flint.fmpq_mat([[_power(w, e) for e in forms] for w in points])
        system = systems[k]
        solution = solve_overdetermined(system, [int(g.get(m, 0)) for g in coefficients])
        for e, coefficient in zip(forms, solution, strict=True):
            if coefficient.q != 1:
                raise HKProofError(f"interpolation of the gcd failed at the monomial {m} (unlucky points)")
            if coefficient != 0:
                data[m + (sum(m),) + e] = int(coefficient.p)
    order = tuple(phase) + (EPS,) + names
    place = [order.index(n) if n in order else None for n in out.names]
    g = out.ctx.from_dict({tuple(0 if i is None else key[i] for i in place): c for key, c in data.items()})
    return g if translation is None else translation.lift(Frac(out, g), r).num


def orbit_samples(symmetry: SignedPermutation, small: Ring, params: Sequence[str],
                  points: Sequence[Sequence[Rational]], samples: Sequence[flint.fmpz_mpoly]
                  ) -> tuple[list[tuple[Rational, ...]], list[flint.fmpz_mpoly]]:
    """The samples g(., w) of a sigma-invariant g and their images along each orbit: g(x, w) = g(sigma x, sigma w)
    with sigma(x_v) = s x_v', sigma(a) = a' says that g at u (u_a = w_a') is g(., w) with x_v' -> s x_v. Points
    met twice are kept once."""
    moved = {a: b for a, b in symmetry.parameters}
    relabel = {image: small.gen(v) * sign for v, image, sign in symmetry.variables}
    out_points: list[tuple[Rational, ...]] = []
    out_samples: list[flint.fmpz_mpoly] = []
    for w, g in zip(points, samples, strict=True):
        at = tuple(to_fmpq(v) for v in w)
        while at not in out_points:
            out_points.append(at)
            out_samples.append(g)
            value = dict(zip(params, at, strict=True))
            at = tuple(value[moved.get(a, a)] for a in params)
            g = small.substitute(g, relabel)
    return out_points, out_samples


def _exponents(n: int, k: int) -> list[tuple[int, ...]]:
    """The exponents of the monomials of degree k in n variables."""
    if n == 1:
        return [(k,)]
    return [(a,) + rest for a in range(k, -1, -1) for rest in _exponents(n - 1, k - a)]


def _power(w: Sequence[Rational], e: tuple[int, ...]) -> flint.fmpq:
    """The monomial with exponents e at the point w."""
    out = flint.fmpq(1)
    for v, k in zip(w, e, strict=True):
        out *= to_fmpq(v) ** k
    return out
