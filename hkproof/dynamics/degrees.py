"""Degree growth of a Kahan map (algebraic entropy): deg f^n on a random line over a large prime field."""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from fractions import Fraction
from itertools import pairwise
from typing import Mapping, Sequence

import flint

from hkproof import budget
from hkproof.algebra.modular import random_prime, residue_or_none
from hkproof.algebra.ring import Rational
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import ParseError

__all__ = ["degree_growth", "DegreeGrowth", "DegreeRun", "degrees_on_line", "differences", "fit_growth", "Growth",
           "MAX_DEGREE", "NAMES", "symbolic_degree"]

MAX_DEGREE = 50_000       # polynomials in t of higher degree are not computed (Lotka-Volterra stops at n = 15)


def degrees_on_line(kmap: KahanMap, values: Mapping[str, int], prime: int, iterates: int,
                    rng: random.Random, max_degree: int = MAX_DEGREE) -> list[int]:
    """deg f^n, n = 1..iterates: the map iterated on x = a + t b (a, b random mod p), common factors in t cancelled;
    stops early when the next degree could exceed max_degree (d times the last one)."""
    hom, d = kmap.mod(prime, values).homogenized()
    tctx = flint.nmod_mpoly_ctx.get(("t",), prime, "lex")  # type: ignore[call-arg, arg-type]  # flint's stubs lag the API
    t = tctx.gen(0)
    point = [rng.randrange(prime) + rng.randrange(1, prime) * t for _ in kmap.variables] + [tctx.constant(1)]
    degrees: list[int] = []
    for _ in range(iterates):
        budget.check("iterating the map on a line mod p")
        if degrees and degrees[-1] * d > max_degree:
            break
        point = [h.compose(*point, ctx=tctx) for h in hom]
        g = point[0]
        for q in point[1:]:
            g = g.gcd(q)
        if g.is_zero():
            raise ParseError(f"the map collapses the random line to a point mod {prime} (every coordinate vanishes)")
        if int(g.total_degree()) > 0:
            point = [q / g for q in point]
        degrees.append(int(max(q.total_degree() for q in point)))
    return degrees


def symbolic_degree(kmap: KahanMap, n: int) -> int:
    """deg f^n from the symbolic iterate (eps and parameters symbolic, common gcd cancelled): an exact value."""
    nums, den = kmap.iterate(n)
    idx = [kmap.ring.index(v) for v in kmap.variables]
    return int(max(max((sum(int(m[i]) for i in idx) for m in p.monoms()), default=0) for p in (*nums, den)))


@dataclass
class DegreeRun:
    """One computation: the prime, the values of eps and the parameters mod p, the degrees found."""

    prime: int
    values: dict[str, int]
    degrees: list[int]


@dataclass
class Growth:
    """Fitted growth of a degree sequence: polynomial of degree k (k-th differences constant, or periodic with a
    small period: a quasi-polynomial) or exponential with lambda and the algebraic entropy log lambda."""

    kind: str
    order: int | None = None
    period: int | None = None
    pattern: list[int] = field(default_factory=list)
    polynomial: list[Fraction] = field(default_factory=list)
    lam: float | None = None

    @property
    def entropy(self) -> float | None:
        """log lambda for exponential growth, 0 for polynomial growth."""
        if self.kind == "exponential" and self.lam is not None:
            return math.log(self.lam)
        return 0.0 if self.order is not None else None

    def formula(self, var: str = "n") -> str:
        if self.kind == "exponential":
            return f"~ {self.lam:.6g}^{var}"
        if self.kind == "undecided":
            return "?"
        if self.period and self.period > 1 and self.order is not None:
            lead = Fraction(sum(self.pattern), self.period * math.factorial(self.order))
            return (f"{lead} {var}^{self.order} + O({var}^{self.order - 1}) (differences of order {self.order} "
                    f"periodic: {self.pattern})")
        terms = []
        for k, c in reversed(list(enumerate(self.polynomial))):
            if c == 0:
                continue
            mono = "" if k == 0 else var if k == 1 else f"{var}^{k}"
            coef = str(c) if (k == 0 or c not in (1, -1)) else ("-" if c == -1 else "")
            terms.append(f"{coef}{'*' if coef not in ('', '-') and mono else ''}{mono}")
        return " + ".join(terms).replace("+ -", "- ") or "0"

    def to_dict(self) -> dict:
        return {"growth": self.kind, "order": self.order, "period": self.period, "formula": self.formula(),
                "lambda": self.lam, "entropy": self.entropy}


NAMES = {0: "bounded", 1: "linear", 2: "quadratic", 3: "cubic"}


def differences(seq: Sequence[int], order: int) -> list[int]:
    """The order-th finite differences of seq."""
    out = list(seq)
    for _ in range(order):
        out = [b - a for a, b in pairwise(out)]
    return out


def fit_growth(degrees: Sequence[int], max_order: int = 3, max_period: int = 3, confirm: int = 3) -> Growth:
    """The least k <= max_order whose k-th differences are periodic (period q <= max_period, each value seen again
    `confirm` - 1 times in all): polynomial growth of degree k (q = 1: the exact interpolant in n); otherwise
    exponential with lambda = d_N / d_(N-1) and entropy log lambda ("undecided" when too few terms rule out
    polynomial growth of degree max_order). A fit on finitely many terms is a guess."""
    for k in range(max_order + 1):
        diff = differences(degrees, k)
        for q in range(1, max_period + 1):
            if len(diff) >= q + confirm and all(diff[i] == diff[i + q] for i in range(len(diff) - q)):
                poly = _interpolate(degrees, k) if q == 1 else []
                return Growth(NAMES.get(k, f"polynomial of degree {k}"), k, q, diff[-q:], poly)
    if len(differences(degrees, max_order)) < 1 + confirm or degrees[-2] == 0:
        return Growth("undecided")
    return Growth("exponential", lam=degrees[-1] / degrees[-2])


def _interpolate(degrees: Sequence[int], k: int) -> list[Fraction]:
    """Coefficients c_0..c_k of the polynomial P(n) with P(n) = degrees[n - 1] at n = 1..k+1 (exact)."""
    rows = [[flint.fmpq(n) ** j for j in range(k + 1)] for n in range(1, k + 2)]
    sol = flint.fmpq_mat(rows).solve(flint.fmpq_mat([[d] for d in degrees[:k + 1]]))
    return [Fraction(int(sol[j, 0].p), int(sol[j, 0].q)) for j in range(k + 1)]


@dataclass
class DegreeGrowth:
    """The degree sequence of f^n (evidence(exact): computed mod p at random values), runs and growth."""

    system: str
    degrees: list[int]
    runs: list[DegreeRun]
    growth: Growth
    agree: bool

    @property
    def second_differences(self) -> list[int]:
        return differences(self.degrees, 2)


def degree_growth(kmap: KahanMap, iterates: int, fixed: Mapping[str, Rational] | None = None, *,
                  seed: int = 0, runs: int = 2) -> DegreeGrowth:
    """deg f^n for n = 1..iterates by `runs` independent (prime, line, eps, parameters); the largest value wins (a
    special choice can only lower a degree), and `agree` says whether all runs gave the same sequence."""
    if iterates < 1:
        raise ParseError(f"the number of iterates must be at least 1, got {iterates}")
    fixed = kmap.field.check_values(fixed or {})
    names = (EPS,) + kmap.field.parameters
    rng = random.Random(seed)
    done: list[DegreeRun] = []
    while len(done) < runs:
        prime = random_prime(rng)
        values = {}
        for name in names:
            v = residue_or_none(fixed[name], prime) if name in fixed else rng.randrange(1, prime)
            if v is None:
                break
            values[name] = v
        else:
            done.append(DegreeRun(prime, values, degrees_on_line(kmap, values, prime, iterates, rng)))
    count = min(len(r.degrees) for r in done)
    best = [max(r.degrees[i] for r in done) for i in range(count)]
    agree = all(r.degrees[:count] == best for r in done)
    return DegreeGrowth(kmap.field.name, best, done, fit_growth(best), agree)
