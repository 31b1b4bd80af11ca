"""A polynomial identity R = sum_mu T_mu prod_j F_j^mu_j = 0 in Z[x] decided by expansion modulo word-size primes.

Exact, not probabilistic. `coefficient_bound` gives a proven B >= |c| for every coefficient c of R, from the norms of
the T_mu and F_j (R is never expanded over Z), and `primes_beyond` takes primes whose product M exceeds 2B. Each
coefficient c of R is an integer with |c| <= B < M, and the only multiple of M in [-B, B] is 0: so R = 0 mod every
one of these primes proves R = 0 in Z[x], and R != 0 mod one prime refutes it. Each expansion is Horner's scheme
(`lattice_identity.horner`) on nmod_mpoly, one word per coefficient; the primes are shared among forked children.
"""
from __future__ import annotations

from dataclasses import dataclass
from math import isqrt, prod
from typing import Mapping, Sequence

import flint

from hkproof import budget
from hkproof.algebra.lattice_identity import horner
from hkproof.algebra.monomials import Exponents
from hkproof.algebra.ring import flint_threads

__all__ = ["coefficient_bound", "ModularPlan", "plan_modular", "primes_beyond", "vanishes_modulo"]

TOP_PRIME = 2 ** 63           # the primes are the largest below this, in decreasing order (nmod takes moduli < 2^64)
Terms = Mapping[Exponents, flint.fmpz_mpoly]
_PRIMES: list[int] = []


def _norms(p: flint.fmpz_mpoly) -> tuple[int, int, int]:
    """(|p|_1, |p|_2^2, |p|_inf) of the coefficient vector of p."""
    cs = [abs(int(c)) for c in p.coeffs()]
    return sum(cs), sum(c * c for c in cs), max(cs, default=0)


def coefficient_bound(terms: Terms, factors: Sequence[flint.fmpz_mpoly]) -> int:
    """An integer B >= |c| for every coefficient c of R = sum_mu T_mu prod_j F_j^mu_j, from the norms of T_mu and F_j.

    Proof. For P = sum p_a x^a and Q = sum q_b x^b the coefficient of x^m in PQ is sum_{a+b=m} p_a q_b, with at most
    one b for each a. Hence (i) |PQ|_inf <= |P|_1 |Q|_inf (bound each q_b by |Q|_inf), (ii) |PQ|_inf <= |P|_2 |Q|_2
    (Cauchy-Schwarz over the pairs with a + b = m) and (iii) |PQ|_1 <= |P|_1 |Q|_1 (every |p_a q_b| is counted once).
    For a summand S = T prod_j F_j^mu_j and G = prod_j F_j^mu_j, (iii) gives |G|_1 <= g = prod_j |F_j|_1^mu_j, so
    |S|_inf <= |T|_inf g by (i) with P = G; and for each k with mu_k > 0, writing S = (T F_k) (G / F_k) and
    S = (T G / F_k) F_k, |S|_inf <= g_k |T|_2 |F_k|_2 by (ii) then (i), and |S|_inf <= g_k |T|_1 |F_k|_inf by (iii)
    then (i), where g_k = g / |F_k|_1 bounds |G / F_k|_1. Every coefficient of R is a sum of one coefficient of each
    S, so B = sum over mu of the least of these bounds (the square roots rounded up) is a bound.
    """
    norms = [_norms(f) for f in factors]
    total = 0
    for exponents, t in terms.items():
        mu = [int(m) for m in exponents]             # FLINT's exponents are fmpz
        if t.is_zero() or any(m and norms[j][2] == 0 for j, m in enumerate(mu)):
            continue                                    # S = 0
        t1, t2, tinf = _norms(t)
        best = tinf * prod(norms[j][0] ** m for j, m in enumerate(mu))
        for k, m in enumerate(mu):
            if m:
                g_k = prod(norms[j][0] ** (e - (j == k)) for j, e in enumerate(mu))
                squared = t2 * norms[k][1]
                best = min(best, g_k * (isqrt(squared) + (isqrt(squared) ** 2 < squared)), g_k * t1 * norms[k][2])
        total += best
    return total


def primes_beyond(bound: int) -> list[int]:
    """The largest primes below 2^63, as few as make their product exceed 2 * bound (deterministic)."""
    out: list[int] = []
    while prod(out) <= 2 * bound:
        if len(out) == len(_PRIMES):
            n = _PRIMES[-1] - 2 if _PRIMES else TOP_PRIME - 1
            while not flint.fmpz(n).is_prime():
                n -= 2
            _PRIMES.append(n)
        out.append(_PRIMES[len(out)])
    return out


def _reduced(p: flint.fmpz_mpoly, ctx: flint.nmod_mpoly_ctx) -> flint.nmod_mpoly:
    """p mod the modulus of ctx."""
    m = ctx.modulus()
    return ctx.from_dict({e: int(c) % m for e, c in zip(p.monoms(), p.coeffs())})


def _vanishes_mod(terms: Terms, factors: Sequence[flint.fmpz_mpoly], p: int) -> bool:
    """Whether R = 0 mod the prime p, by Horner's scheme over Z/p."""
    ring = factors[0].context() if factors else next(iter(terms.values())).context()
    ctx = flint.nmod_mpoly_ctx.get(ring.names(), p, "degrevlex")  # type: ignore[call-arg, arg-type]  # stubs lag
    reduced = {mu: _reduced(t, ctx) for mu, t in terms.items()}
    return horner(reduced, [_reduced(f, ctx) for f in factors]).is_zero()


@dataclass(frozen=True)
class ModularPlan:
    """The proven coefficient bound of R, the primes (product > 2 bound) and the cost model's estimate (term products
    of one expansion times the expansions a child does)."""

    bound: int
    primes: tuple[int, ...]
    work: int

    def describe(self) -> str:
        return (f"coefficients of the expanded identity bounded by {self.bound.bit_length()} bits (proven from the "
                f"norms of its factors); zero modulo {len(self.primes)} word-size prime(s) whose product exceeds twice "
                "the bound, each by Horner's scheme")


def plan_modular(terms: Terms, factors: Sequence[flint.fmpz_mpoly], horner_work: int, jobs: int = 1) -> ModularPlan:
    """The bound, the primes, and `horner_work` (one expansion) times the primes each of `jobs` children takes."""
    bound = coefficient_bound(terms, factors)
    primes = primes_beyond(bound)
    return ModularPlan(bound, tuple(primes), horner_work * -(-len(primes) // max(1, jobs)))


def vanishes_modulo(terms: Terms, factors: Sequence[flint.fmpz_mpoly], primes: Sequence[int], jobs: int = 1
                    ) -> tuple[bool, int | None]:
    """Whether R = 0 modulo every prime: (True, None), or (False, a prime p with R != 0 mod p). It proves R = 0 over Z
    only when the primes' product exceeds 2 `coefficient_bound` (as `plan_modular`'s do). With jobs > 1 the
    primes are shared among forked children (`Budget.call_each`, under the active deadline); a child with the whole
    machine to itself uses FLINT's threads."""
    if not any(not t.is_zero() for t in terms.values()):
        return True, None
    jobs = max(1, min(jobs, len(primes)))

    def part(k: int) -> int | None:
        with flint_threads(1 if jobs > 1 else None):
            for p in primes[k::jobs]:
                budget.check("checking an identity modulo a prime")
                if not _vanishes_mod(terms, factors, p):
                    return p
        return None

    doing = "checking an identity modulo primes"
    found = budget.current().call_each(doing, part, jobs) if jobs > 1 else [budget.current().call(doing, part, 0)]
    bad = next((p for p in found if p is not None), None)
    return bad is None, bad
