"""Algorithm (N) mod large primes: a second prime checks the first, and an unlucky prime is replaced."""
from __future__ import annotations

import random
from typing import Sequence

import flint

from hkproof.algebra.modular import kernel_mod_p, random_prime, residue
from hkproof.errors import SingularPointError, UnluckyPrimeError
from hkproof.experiments.arithmetics import Arithmetic, FieldArithmetic, Prepared, RawProfile, pivot_columns, \
    ranks_from_pivots

__all__ = ["ModP", "Modular", "UnluckyPrimeError"]


class ModP(FieldArithmetic):
    """Arithmetic in Z/p for one prime p (Python ints reduced mod p, nmod_mat for solves and ranks)."""

    def __init__(self, p: int):
        super().__init__()
        self.p = p
        self.name = f"mod {p}"

    def number(self, q: flint.fmpq) -> int:
        return residue(q, self.p)

    def prepare(self, scene, basis) -> Prepared:
        prep = super().prepare(scene, basis)
        if prep.matrices is None:
            prep.matrices = scene.kmap.mod(self.p, scene.fixed)
        return prep

    def step(self, prep: Prepared, x: Sequence[int]) -> list[int]:
        """x~ by the modular Kahan map (one nmod_mat solve)."""
        return prep.matrices.step(x)

    def _solve(self, m: flint.nmod_mat, b: flint.nmod_mat) -> list[int]:
        try:
            sol = m.solve(b)
        except ZeroDivisionError:
            raise UnluckyPrimeError(f"det M(x, eps) = 0 mod {self.p}") from None
        return [int(sol[i, 0]) for i in range(b.nrows())]

    def evaluate(self, poly, x: Sequence[int]) -> int:
        """A compiled polynomial at x mod p (powers by modular exponentiation: x1**100000 costs 17 squarings)."""
        total = 0
        for c, exps in poly:
            for i, e in exps:
                c = c * pow(x[i], e, self.p) % self.p
            total += c
        return total % self.p

    def basis_row(self, prep: Prepared, x: Sequence[int]) -> list[int]:
        row = []
        for num, den in prep.basis:
            d = self.evaluate(den, x) % self.p
            if d == 0:
                raise UnluckyPrimeError(f"a basis denominator vanishes mod {self.p} on the orbit")
            row.append(self.evaluate(num, x) * pow(d, -1, self.p) % self.p)
        return row

    def solve(self, m: list[list[int]], b: list[int]) -> list[int]:
        return self._solve(flint.nmod_mat(m, self.p), flint.nmod_mat([[v] for v in b], self.p))

    def prefix_ranks(self, rows: list[list[int]]) -> tuple[list[int | None], dict]:
        r, rank = flint.nmod_mat(rows, self.p).transpose().rref()
        return ranks_from_pivots(pivot_columns(r, rank), len(rows)), {"prime": self.p}

    def kernel(self, raw: RawProfile, d: int) -> list[list[int]]:
        return kernel_mod_p(raw.rows[:len(raw.rows[0]) - d], self.p)


class Modular(Arithmetic):
    """Ranks mod large random primes: a second prime checks the first; an unlucky prime is replaced.

    Ranks mod p never exceed ranks over Q, so when two primes disagree the larger ranks are kept and the
    other prime is reported as unlucky and replaced.
    """

    name = "modular"

    def __init__(self, primes: Sequence[int] = (), *, seed: int = 0, checks: int = 1, bits: int = 62,
                 max_primes: int = 6):
        self.pool = list(primes)
        self._rng = random.Random(seed)
        self.checks = checks
        self.bits = bits
        self.max_primes = max_primes
        self._fields: dict[int, ModP] = {}

    def field(self, index: int) -> ModP:
        """The index-th prime of the pool (drawn at random when the pool is exhausted)."""
        while len(self.pool) <= index:
            self.pool.append(random_prime(self._rng, self.bits))
        p = self.pool[index]
        if p not in self._fields:
            self._fields[p] = ModP(p)
        return self._fields[p]

    def profile(self, scene, basis, point) -> RawProfile:
        results: list[tuple[int, RawProfile]] = []
        unlucky: list[dict] = []
        for index in range(self.max_primes):
            f = self.field(index)
            try:
                raw = f.profile(scene, basis, point)
            except UnluckyPrimeError as exc:
                unlucky.append({"prime": f.p, "reason": str(exc)})
                continue
            results.append((f.p, raw))
            best = max(results, key=lambda pr: sum(r or 0 for r in pr[1].ranks))[1].ranks
            agree = [q for q, r in results if r.ranks == best]
            if len(agree) > self.checks:
                unlucky += [{"prime": q, "reason": f"ranks {r.ranks} below {best}"}
                            for q, r in results if r.ranks != best]
                raw_best = next(r for q, r in results if q == agree[0])
                certainty = {"arithmetic": self.name, "method": f"ranks mod {len(agree)} primes agree",
                             "primes": agree, "unlucky_primes": unlucky, "prime": agree[0]}
                return RawProfile(raw_best.ranks, raw_best.rows, certainty)
        if not results:
            raise SingularPointError(
                f"det M vanishes or a denominator is divisible by p for {self.max_primes} primes: "
                "the orbit most likely meets Delta = 0")
        raise UnluckyPrimeError(f"{self.max_primes} primes gave no two agreeing rank profiles: {unlucky}")

    def kernel(self, raw: RawProfile, d: int) -> list[list[int]]:
        return self._fields[raw.certainty["prime"]].kernel(raw, d)
