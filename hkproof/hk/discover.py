"""`discover`, the exact half: certify reconstructed integrals, sort out trivial ones, prove independence, report.

The search (algorithm (N) on monomial bases, kernels, reconstruction) lives in hkproof.experiments.discovery;
everything it finds passes through here before it is called an integral: h o f = h by substitution
(`check_integral`, every remaining parameter symbolic) and functional independence by an exact Jacobian rank at
a rational point (a full rank at one point proves independence).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Mapping, Sequence

import flint
import sympy

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import SingularPointError, SingularSystemError
from hkproof.hk.independence import jacobian_rank_at
from hkproof.hk.integrals import check_integral
from hkproof.hk.linear_relations import relation_rank
from hkproof.hk.reduced import Relation, solve_reduced_system
from hkproof.hk.row_check import check_solution_by_rows
from hkproof.proof.status import Status


SKIPPED_SHOWN = 40       # kernel coordinates too large to reconstruct: the first ones are listed, all are counted


@dataclass
class FoundIntegral:
    """A candidate integral: its formula (None if not reconstructed), its status and where it came from."""

    name: str
    frac: Frac | None
    status: Status
    kind: str                     # "kernel coordinate" or "conserved coordinate"
    basis: list[str] = field(default_factory=list)
    coordinate: str = ""
    seconds: float = 0.0
    method: str = ""
    notes: list[str] = field(default_factory=list)
    independent: bool | None = None

    def latex(self) -> str:
        if self.frac is None:
            return ""
        return sympy.latex(sympy.factor(self.frac.to_sympy()), symbol_names={sympy.Symbol("eps"): r"\varepsilon"})

    def to_dict(self) -> dict:
        return {"name": self.name, "expr": None if self.frac is None else str(self.frac),
                "status": self.status.label, "kind": self.kind, "basis": self.basis, "coordinate": self.coordinate,
                "seconds": round(self.seconds, 3), "method": self.method, "independent": self.independent,
                "notes": self.notes}


def certify(kmap: KahanMap, h: Frac, fixed: Mapping[str, Rational] | None = None) -> tuple[Status, str]:
    """Exact substitution h(N/Delta) - h = 0 in Q(x, eps, parameters): verified (or verified(specialized) when
    some parameters were fixed by the user), refuted otherwise."""
    verdict = check_integral(kmap, h.to_ring(kmap.ring))
    where = f"in {verdict.ring}" + (f" at {', '.join(f'{k}={v}' for k, v in fixed.items())}" if fixed else "")
    if verdict.status is not Status.VERIFIED:
        return Status.REFUTED, f"{verdict.method} is not zero {where} ({verdict.difference_terms} terms)"
    return (Status.VERIFIED_SPECIALIZED if fixed else Status.VERIFIED), f"{verdict.method} = 0 {where}"


def solve_by_evenness(kmap: KahanMap, basis: Sequence[Frac], relations: Sequence[Relation],
                      fixed: Mapping[str, Rational] | None = None) -> tuple[list[Frac] | None, Status, str]:
    """Recipe (E) with Prop. "prop: even" for a basis with a one-dimensional kernel (last coordinate -1): the rows
    i = 0, 1 and independent relations with eps-even constant coefficients, solved by Cramer's rule; a unique
    solution that is even in eps and satisfies every equation consists of integrals. (None, status, why) when the
    relations are too few or the hypotheses fail."""
    unknowns = len(basis) - 1
    chosen: list[Relation] = []
    for rel in relations:
        if len(chosen) == unknowns - 2:
            break
        if relation_rank(chosen + [rel]) > len(chosen):
            chosen.append(rel)
    if len(chosen) < unknowns - 2:
        return None, Status.UNKNOWN, (f"{len(chosen)} independent relations for {unknowns} unknowns: the rows "
                                      "i = 0, 1 cannot fix the rest")
    if not all(c.is_even_in(EPS) for rel in chosen for c in (*rel.coefficients, rel.rhs)):
        return None, Status.UNKNOWN, "a relation's coefficient is not even in eps: Prop. \"prop: even\" does not apply"
    try:
        solution = solve_reduced_system(kmap, basis[:-1], basis[-1], (0, 1), chosen)
    except SingularSystemError:
        return None, Status.UNKNOWN, "the rows i = 0, 1 and the relations are singular"
    if not all(c.is_even_in(EPS) for c in solution):
        return None, Status.UNKNOWN, "the solution is not even in eps: Prop. \"prop: even\" does not apply"
    if not check_solution_by_rows(kmap, basis[:-1], basis[-1], (0, 1), chosen, solution):
        return None, Status.REFUTED, "the solution fails a row or a relation"
    where = f" at {', '.join(f'{k}={v}' for k, v in fixed.items())}" if fixed else ""
    return solution, (Status.VERIFIED_SPECIALIZED if fixed else Status.VERIFIED), (
        f"recipe (E): rows i = 0, 1 and {len(chosen)} relation(s) found exactly, unique solution (Cramer), even in "
        f"eps, substituted back: integrals by Prop. \"prop: even\"{where}")


def is_phase_constant(h: Frac, variables: Sequence[str]) -> bool:
    """True when h involves no phase variable (a constant integral: trivial)."""
    return not (h.variables() & set(variables))


def independent_subset(functions: Sequence[Frac], variables: Sequence[str],
                       points: Sequence[Mapping[str, Rational]]) -> list[int]:
    """Indices of a maximal subset whose Jacobian has full rank at one of `points` (exact; proves independence)."""
    chosen: list[int] = []
    for i in range(len(functions)):
        trial = [functions[j] for j in chosen + [i]]
        for point in points:
            try:
                if jacobian_rank_at(trial, variables, point) == len(trial):
                    chosen.append(i)
                    break
            except SingularPointError:
                continue
    return chosen


@dataclass
class DiscoveryReport:
    """What `discover` found and how far it got (JSON: see docs/discover.md)."""

    system: str
    variables: list[str]
    parameters: list[str]
    degree: int
    fixed: dict[str, str] = field(default_factory=dict)
    integrals: list[FoundIntegral] = field(default_factory=list)
    bases: list[dict] = field(default_factory=list)
    kernels: list[dict] = field(default_factory=list)
    conserved: list[str] = field(default_factory=list)
    trivial: list[dict] = field(default_factory=list)
    skipped: list[dict] = field(default_factory=list)
    expected_independent: int | None = None
    negative: str = ""
    covered: list[str] = field(default_factory=list)
    complete: bool = True
    stages: dict[str, float] = field(default_factory=dict)
    probes: list[dict] = field(default_factory=list)
    started: float = field(default_factory=time.perf_counter)

    @property
    def independent(self) -> int:
        return sum(1 for i in self.integrals if i.independent)

    @property
    def verified(self) -> list[FoundIntegral]:
        return [i for i in self.integrals if i.status >= Status.VERIFIED_SPECIALIZED]

    def to_dict(self) -> dict:
        return {"system": self.system, "degree": self.degree, "dimension": len(self.variables),
                "variables": self.variables, "parameters": self.parameters, "fixed": self.fixed,
                "integrals": [i.to_dict() for i in self.integrals], "independent": self.independent,
                "independent_expected_from_kernels": self.expected_independent,
                "bases": self.bases, "kernels": self.kernels, "conserved": self.conserved, "trivial": self.trivial,
                "skipped": self.skipped[:SKIPPED_SHOWN], "skipped_total": len(self.skipped),
                "negative_result": self.negative or None, "covered": self.covered, "complete": self.complete,
                "stages": {k: round(v, 3) for k, v in self.stages.items()}, "probes": self.probes,
                "seconds": round(time.perf_counter() - self.started, 3)}


def jacobian_points(names: Sequence[str], count: int = 3, seed: int = 11) -> list[dict[str, flint.fmpq]]:
    """A few reproducible rational points fixing every name (for exact Jacobian ranks)."""
    import random
    rng = random.Random(seed)
    return [{n: flint.fmpq(rng.choice([-1, 1]) * rng.randint(1, 97), rng.randint(1, 89)) for n in names}
            for _ in range(count)]
