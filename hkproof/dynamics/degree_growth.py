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
from hkproof.dynamics.line_iterates import Line, LineKahanMap, degree
from hkproof.errors import BudgetExhausted, ParseError

__all__ = ["degree_growth", "DegreeGrowth", "DegreeRun", "degrees_on_line", "differences", "fit_growth", "Growth",
           "LineRun", "MAX_DEGREE", "NAMES", "symbolic_degree", "walk"]

MAX_DEGREE = 200_000
"""A step whose polynomials in t could pass this degree (n times the last deg f^k, n the dimension) is not taken: the
largest step allowed costs about 20 s and a hundred MB (Volterra N = 6 stops after deg f^7 = 97 656, whose next step
would work at degree 585 936 for a minute; docs/geometry.md)."""


@dataclass
class LineRun:
    """One run on a line: the map mod p on polynomials in t, the reduced image f^k(line), deg f^1..f^k, and the
    random source of its gcds."""

    line_map: LineKahanMap
    point: Line
    rng: random.Random
    degrees: list[int] = field(default_factory=list)

    @classmethod
    def start(cls, kmap: KahanMap, values: Mapping[str, int], prime: int, rng: random.Random) -> LineRun:
        """A random line x = a + t b at eps and the parameters fixed to `values` mod `prime`."""
        line_map = LineKahanMap(kmap.mod(prime, values))
        return cls(line_map, line_map.line(rng), rng)

    def coefficients_of_next(self, seed: int) -> list[list[int]]:
        """The reduced f^(k+1)(line) as coefficient lists (picklable: it may be computed in a forked child)."""
        return [[int(c) for c in q.coeffs()] for q in self.line_map.next(self.point, random.Random(seed))]

    def advance(self, coefficients: list[list[int]]) -> None:
        self.point = [flint.nmod_poly(c, self.line_map.p) for c in coefficients]
        self.degrees.append(degree(self.point))


def walk(runs: Sequence[LineRun], iterates: int, max_degree: int = MAX_DEGREE) -> str | None:
    """Advance every run to deg f^iterates in step, each step of each run in a forked child held to the active
    budget (`Budget.call_each`: side by side on the cores, and stopped at the deadline even inside one FLINT call,
    BudgetExhausted); None when done, else why the runs stopped early (a step's degree above max_degree)."""
    while runs and len(runs[0].degrees) < iterates:
        budget.check("iterating the map on a line mod p")
        last = max(degree(r.point) for r in runs)
        if last * runs[0].line_map.n > max_degree:
            return (f"the step to f^{len(runs[0].degrees) + 1} works with polynomials in t of degree up to "
                    f"{last * runs[0].line_map.n} > {max_degree}")
        seeds = [r.rng.getrandbits(64) for r in runs]
        doing = f"computing f^{len(runs[0].degrees) + 1} on a line mod p"
        jobs = budget.current()
        found = ([jobs.call(doing, runs[0].coefficients_of_next, seeds[0])] if len(runs) == 1 else
                 jobs.call_each(doing, lambda k: runs[k].coefficients_of_next(seeds[k]), len(runs)))
        for run, coefficients in zip(runs, found, strict=True):
            run.advance(coefficients)
    return None


def degrees_on_line(kmap: KahanMap, values: Mapping[str, int], prime: int, iterates: int,
                    rng: random.Random, max_degree: int = MAX_DEGREE) -> list[int]:
    """deg f^n, n = 1..iterates: the map iterated on x = a + t b (a, b random mod p), common factors in t cancelled
    (`LineKahanMap`); stops early when a step's polynomials could exceed max_degree (n times the last degree)."""
    run = LineRun.start(kmap, values, prime, rng)
    walk([run], iterates, max_degree)
    return run.degrees


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
    """The growth class of a degree sequence, with the evidence it was judged on: polynomial of degree k (k-th
    differences constant, or periodic: a quasi-polynomial), exponential with lambda = lim d_n / d_(n-1) (within
    `lam_error`) and algebraic entropy log lambda, or "undecided" with the reason."""

    kind: str
    order: int | None = None
    period: int | None = None
    pattern: list[int] = field(default_factory=list)
    polynomial: list[Fraction] = field(default_factory=list)
    lam: float | None = None
    lam_error: float | None = None
    evidence: str = ""

    @property
    def entropy(self) -> float | None:
        """log lambda for exponential growth, 0 for polynomial growth, None when undecided."""
        if self.kind == "exponential" and self.lam is not None:
            return math.log(self.lam)
        return 0.0 if self.order is not None else None

    def describe(self) -> list[str]:
        """The growth class: the formula of deg f^n (or lambda and the entropy) and what it was judged on, or
        "undecided" and why."""
        if self.kind == "undecided":
            return [f"growth: undecided: {self.evidence}"]
        if self.kind == "exponential":
            head = (f"growth: exponential, deg f^n ~ lambda^n with lambda = {self.lam:.6g} +- {self.lam_error:.2g}, "
                    f"algebraic entropy log lambda = {self.entropy:.6g}")
        else:
            head = f"growth: {self.kind}, deg f^n = {self.formula()} (algebraic entropy 0)"
        return [head, f"  (judged on the sequence: {self.evidence})"]

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
                "lambda": self.lam, "lambda_error": self.lam_error, "entropy": self.entropy,
                "growth_evidence": self.evidence}


NAMES = {0: "bounded", 1: "linear", 2: "quadratic", 3: "cubic"}
ORDINALS = {0: "the degrees themselves", 1: "the first differences", 2: "the second differences",
            3: "the third differences"}


def differences(seq: Sequence[int], order: int) -> list[int]:
    """The order-th finite differences of seq."""
    out = list(seq)
    for _ in range(order):
        out = [b - a for a, b in pairwise(out)]
    return out


def least_period(values: Sequence[int], confirm: int = 3) -> int | None:
    """The least q with values[i] = values[i + q] for every i, among the periods that the data can show: q at most
    half the length (each value of a period seen at least twice) and at least `confirm` values beyond one period.

    >>> least_period([1, 1, 1, 2, 1] * 2), least_period([4, 4, 4]), least_period([4, 4, 4, 4])
    (5, None, 1)
    """
    for q in range(1, min(len(values) // 2, len(values) - confirm) + 1):
        if all(values[i] == values[i + q] for i in range(len(values) - q)):
            return q
    return None


def fit_growth(degrees: Sequence[int], max_order: int = 3, confirm: int = 3, window: int = 4,
               contraction: float = 0.5, precision: float = 0.1, strides: int = 2) -> Growth:
    """The growth class of deg f^n, n = 1..N, judged on the sequence alone (a guess from finitely many terms):

    - polynomial of degree k for the least k <= max_order whose k-th differences are periodic (`least_period`:
      periods up to half of them); period 1 gives the exact interpolating polynomial in n;
    - exponential when the ratios r_n = d_n / d_(n-1) have converged: the last `window` of them are equal, or, for
      the least stride q <= `strides`, each of the last `window` changes |r_n - r_(n-1)| is at most c = `contraction`
      times the change q steps before (geometric convergence; stride 2 lets the ratios alternate, as a bounded part
      (-1)^n of d_n makes them: if it goes on, lambda lies within e = (sum of the last q changes) * c / (1 - c) of
      the last ratio), with e at most `precision` times lambda - 1 (lambda told apart from 1, which polynomial growth
      approaches) and the last differences d_n - d_(n-1) growing by the same lambda (polynomial growth does not);
    - undecided otherwise, saying why.

    >>> [fit_growth([2 ** n for n in range(1, 7)]).lam, fit_growth([3 ** n for n in range(1, 6)]).lam]
    [2.0, 3.0]
    >>> fit_growth([2, 4, 7, 11, 16]).kind
    'undecided'
    >>> round(fit_growth([5, 21, 85, 321, 1205, 4501, 16805, 62721]).lam, 4)   # alternating ratios: stride 2
    3.7323
    """
    for k in range(max_order + 1):
        diff = differences(degrees, k)
        q = least_period(diff, confirm)
        if q is not None:
            poly = _interpolate(degrees, k) if q == 1 else []
            how = (f"constant ({diff[0]})" if q == 1 else f"periodic with period {q} ({diff[:q]})")
            return Growth(NAMES.get(k, f"polynomial of degree {k}"), k, q, diff[:q], poly,
                          evidence=f"{ORDINALS.get(k, f'the differences of order {k}')} are {how} over all "
                                   f"{len(diff)} values")
    return _exponential(degrees, max_order, window, contraction, precision, strides)


def _exponential(degrees: Sequence[int], max_order: int, window: int, contraction: float, precision: float,
                 strides: int) -> Growth:
    """Exponential growth if the ratios d_n / d_(n-1) have converged (see fit_growth), else undecided."""
    no_period = (f"no differences of order <= {max_order} are periodic within {len(degrees)} terms (a period must "
                 "show twice)")
    ratios = [Fraction(b, a) for a, b in pairwise(degrees) if a > 0]
    if len(ratios) >= window and len(set(ratios[-window:])) == 1:
        lam = float(ratios[-1])
        return Growth("exponential", lam=lam, lam_error=0.0,
                      evidence=f"the last {window} ratios d_n/d_(n-1) are all {lam:.6g} (d_n geometric)")
    if len(ratios) < window + 2 or len(ratios) < len(degrees) - 1:
        return Growth("undecided", evidence=f"{no_period}, and {window + 3} positive terms are needed to see the "
                                            f"ratios d_n/d_(n-1) converge ({window + 1} for an exactly geometric "
                                            "run)")
    factors = {q: _contraction(ratios, window, q) for q in range(1, strides + 1) if len(ratios) >= window + q + 1}
    q = min((q for q, c in factors.items() if c <= contraction), default=None)
    tail = ratios[-window - 1 - (q or 1):]
    shown = ", ".join(f"{float(r):.6g}" for r in tail)
    if q is None:
        by = ", ".join(f"{c:.2g}" + (f" over {k} steps" if k > 1 else "") for k, c in factors.items())
        return Growth("undecided", evidence=f"{no_period}, and the ratios d_n/d_(n-1) ({shown}) have not converged: "
                                            f"their changes shrink by a factor of {by} > {contraction}")
    changes = [abs(b - a) for a, b in pairwise(tail)]
    c, lam = factors[q], float(tail[-1])
    error = float(sum(changes[-q:])) * contraction / (1 - contraction)
    if lam <= 1 or error > precision * (lam - 1):
        return Growth("undecided", evidence=f"{no_period}, and the ratios d_n/d_(n-1) ({shown}) cannot yet tell "
                                            f"lambda from 1 (lambda = {lam:.6g} +- {error:.2g})")
    steps = differences(degrees[-3:], 1)
    step = steps[1] / steps[0] if steps[0] > 0 else math.inf
    if abs(step - lam) > precision * (lam - 1):
        return Growth("undecided", evidence=f"{no_period}; the ratios d_n/d_(n-1) ({shown}) seem to converge, but "
                                            f"the differences grow by {step:.6g}, not by the same lambda (polynomial "
                                            "growth looks so)")
    every = "" if q == 1 else f" every {q} steps (the ratios alternate)"
    return Growth("exponential", lam=lam, lam_error=error,
                  evidence=f"the ratios d_n/d_(n-1) ({shown}) converge: their changes shrink by a factor <= "
                           f"{c:.2g}{every}, so lambda = {lam:.6g} +- {error:.2g}; the differences grow by "
                           f"{step:.6g} alike")


def _contraction(ratios: Sequence[Fraction], window: int, q: int) -> float:
    """The largest factor by which one of the last `window` changes of the ratios shrinks against the change q steps
    before (inf where that one is 0 and this one is not)."""
    changes = [abs(b - a) for a, b in pairwise(ratios[-window - q - 1:])]
    return max(float(b / a) if a else (0.0 if b == 0 else math.inf) for a, b in zip(changes, changes[q:]))


def _interpolate(degrees: Sequence[int], k: int) -> list[Fraction]:
    """Coefficients c_0..c_k of the polynomial P(n) with P(n) = degrees[n - 1] at n = 1..k+1 (exact)."""
    rows = [[flint.fmpq(n) ** j for j in range(k + 1)] for n in range(1, k + 2)]
    sol = flint.fmpq_mat(rows).solve(flint.fmpq_mat([[d] for d in degrees[:k + 1]]))
    return [Fraction(int(sol[j, 0].p), int(sol[j, 0].q)) for j in range(k + 1)]


@dataclass
class DegreeGrowth:
    """The degree sequence of f^n (evidence(exact): computed mod p at random values), runs and growth; `stopped`
    says why there are fewer degrees than asked for (None: all of them)."""

    system: str
    degrees: list[int]
    runs: list[DegreeRun]
    growth: Growth
    agree: bool
    stopped: str | None = None
    budget_ran_out: bool = False

    @property
    def second_differences(self) -> list[int]:
        return differences(self.degrees, 2)


def degree_growth(kmap: KahanMap, iterates: int, fixed: Mapping[str, Rational] | None = None, *,
                  seed: int = 0, runs: int = 2, max_degree: int = MAX_DEGREE) -> DegreeGrowth:
    """deg f^n for n = 1..iterates by `runs` independent (prime, line, eps, parameters), side by side (`walk`); the
    largest value wins (a special choice can only lower a degree), and `agree` says whether all runs gave the same
    sequence. When the active budget runs out, the degrees computed so far are kept and `stopped` says so."""
    if iterates < 1:
        raise ParseError(f"the number of iterates must be at least 1, got {iterates}")
    fixed = kmap.field.check_values(fixed or {})
    names = (EPS,) + kmap.field.parameters
    rng = random.Random(seed)
    started: list[tuple[int, dict[str, int], LineRun]] = []
    while len(started) < runs:
        prime = random_prime(rng)
        values = {}
        for name in names:
            v = residue_or_none(fixed[name], prime) if name in fixed else rng.randrange(1, prime)
            if v is None:
                break
            values[name] = v
        else:
            started.append((prime, values, LineRun.start(kmap, values, prime, rng)))
    lines = [run for _, _, run in started]
    ran_out = False
    try:
        stopped = walk(lines, iterates, max_degree)
    except BudgetExhausted as exc:
        stopped, ran_out = f"{exc}", True
    done = [DegreeRun(prime, values, run.degrees) for prime, values, run in started]
    count = min(len(r.degrees) for r in done)
    best = [max(r.degrees[i] for r in done) for i in range(count)]
    agree = all(r.degrees[:count] == best for r in done)
    return DegreeGrowth(kmap.field.name, best, done, fit_growth(best), agree, stopped, ran_out)
