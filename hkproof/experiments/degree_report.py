"""Degree growth as `hkproof degrees` reports it: deg f^n on random lines mod large primes (evidence), the first
degrees made exact by symbolic iterates, the growth fitted on the best sequence, and the status this earns."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from hkproof.algebra.printing import markdown_table
from hkproof.algebra.ring import Rational
from hkproof.dynamics.degree_growth import DegreeGrowth, degree_growth, fit_growth, symbolic_degree
from hkproof.dynamics.kahan import KahanMap
from hkproof.proof.certificate import Certificate, Step
from hkproof.proof.status import Status

__all__ = ["DegreeReport", "degree_report"]


@dataclass
class DegreeReport:
    """The degrees found (modular runs, with the symbolic degrees in place where computed) and their growth."""

    found: DegreeGrowth
    requested: int
    symbolic: list[int]         # deg f^n from the symbolic iterates, n = 1..len(symbolic): exact
    symbolic_agree: bool        # the modular runs gave the same first degrees

    @property
    def stopped(self) -> bool:
        """Fewer degrees than asked for: the next step's degree limit or the time budget stopped the runs."""
        return len(self.found.degrees) < self.requested

    @property
    def certificate(self) -> Certificate:
        """The report in the proof kernel's terms: a step for the degrees of the symbolic iterates (exact, eps and the
        parameters symbolic) and, for the degrees beyond them or when the two disagree, a step for the runs mod p
        (evidence: restrictions to random lines at random values)."""
        found, k = self.found, len(self.symbolic)
        steps = []
        if self.symbolic:
            steps.append(Step(f"deg f^n for n = 1..{k}", "symbolic iterates f^n = f^(n-1) o f composed exactly, the "
                              "common gcd cancelled", "Q[x, eps, parameters]", Status.VERIFIED,
                              detail=f"{self.symbolic}"))
        if k < self.requested or not self.symbolic_agree:
            steps.append(Step(f"deg f^n for n = {k + 1 if self.symbolic_agree else 1}..{len(found.degrees)}",
                              f"restriction to random lines over large prime fields, {len(found.runs)} runs "
                              + ("that agree" if found.agree else "that DISAGREE (the largest degree kept)"),
                              "Z/p at random eps and parameters", Status.EVIDENCE_EXACT,
                              detail=f"{found.degrees}" + ("" if self.symbolic_agree else
                                                           "; the symbolic iterates disagreed and replace them")))
        return Certificate(f"degrees:{found.system}", f"degree growth of the Kahan map of {found.system}",
                           "algebraic entropy, docs/geometry.md", f"deg f^n = {found.degrees} for n = 1..."
                           f"{len(found.degrees)}", steps)

    @property
    def status(self) -> Status:
        """verified when every degree asked for comes from the symbolic iterates and the modular runs agree with
        them, evidence(exact) otherwise (degrees mod p at random values: not a proof): the certificate's status."""
        return self.certificate.status

    @property
    def status_reason(self) -> str:
        """Why the degrees earn their status, for the report."""
        if self.status is Status.VERIFIED:
            return "every degree from the symbolic iterates"
        return ("degrees computed mod p on random lines at random values, not a proof"
                + (f" beyond n = {len(self.symbolic)}" if self.symbolic else ""))

    @property
    def degrees(self) -> list[int]:
        """deg f^n for n = 1, 2, ... (the symbolic ones where computed)."""
        return self.found.degrees

    def _repr_markdown_(self) -> str:
        """The degrees, the growth and the status: how Jupyter shows the report."""
        found = self.found
        how = (f"the first {len(self.symbolic)} from the symbolic iterates, " if self.symbolic else "") + (
            f"{len(found.runs)} runs mod p on random lines at random values "
            + ("(they agree)" if found.agree else "(they DISAGREE: the largest degree is kept)"))
        table = markdown_table(["n", *range(1, len(found.degrees) + 1)], [["deg f^n", *found.degrees]])
        return "\n".join([f"**[{self.status.label}] degree growth of the Kahan map of {found.system}**", "", table,
                          "", *(f"- {line.strip()}" for line in found.growth.describe()), f"- degrees: {how}",
                          *([f"- stopped after {len(found.degrees)} iterates: {found.stopped}"] if self.stopped else [])])


def degree_report(kmap: KahanMap, iterates: int, fixed: Mapping[str, Rational] | None = None, *, seed: int = 0,
                  runs: int = 2, symbolic_up_to: int = 0) -> DegreeReport:
    """deg f^n for n = 1..iterates by `runs` modular runs, the first `symbolic_up_to` also from the symbolic
    iterates (eps and parameters symbolic); where these disagree they replace the modular values and the growth is
    fitted again."""
    found = degree_growth(kmap, iterates, fixed, seed=seed, runs=runs)
    exact = [symbolic_degree(kmap, n) for n in range(1, min(symbolic_up_to, len(found.degrees)) + 1)]
    agree = exact == found.degrees[:len(exact)]
    if not agree:
        found.degrees[:len(exact)] = exact
        found.growth = fit_growth(found.degrees)
    return DegreeReport(found, iterates, exact, agree)
