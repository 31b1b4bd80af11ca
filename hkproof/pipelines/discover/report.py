"""What `discover` found and how far it got: the integrals with their status, the kernels, the bases, the coverage.

The report is filled stage by stage by hkproof.pipelines.discover.run; it renders itself as text and LaTeX (the
front ends only print it) and as JSON (docs/discover.md).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from hkproof.algebra.fraction import Frac
from hkproof.algebra.printing import SHOWN_TERMS, latex
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

if TYPE_CHECKING:
    from hkproof.dynamics.field import QuadraticField
    from hkproof.pipelines.charts import Chart
    from hkproof.pipelines.slices import Slice
    from hkproof.pipelines.discover.solve import BasisProof

__all__ = ["DiscoveryReport", "FoundIntegral", "SKIPPED_SHOWN"]

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
    certificate: Certificate | None = None       # the proof (for a basis proven whole, the basis's certificate)
    proof: BasisProof | None = field(default=None, repr=False, compare=False)   # the basis's data (Prop. "prop: even")
    searched: Frac | None = field(default=None, repr=False, compare=False)     # the integral on the slice, if lifted
    in_chart: Frac | None = field(default=None, repr=False, compare=False)     # in the normal form's chart, if pulled back

    def too_large(self) -> bool:
        """Whether the formula is too long to print (or to factor for LaTeX) in a report read by a person."""
        return self.frac is not None and len(self.frac.num) + len(self.frac.den) > SHOWN_TERMS

    def summary(self) -> str:
        """What a report read by a person says of a formula too large to print: its size (the whole is in the JSON
        output and in the certificate)."""
        h = self.frac
        if h is None:
            return "not reconstructed"
        return (f"a rational function of {len(h.num)} + {len(h.den)} terms, total degrees {h.num.total_degree()} / "
                f"{h.den.total_degree()}: the formula is in the JSON output and in the certificate")

    def shown(self) -> str:
        """The formula as text, or <its summary> when it is too large to read."""
        if self.frac is None:
            return ""
        return f"<{self.summary()}>" if self.too_large() else str(self.frac)

    def latex(self) -> str:
        if self.frac is None:
            return ""
        import sympy
        return latex(sympy.factor(self.frac.to_sympy()))

    def to_dict(self) -> dict:
        return {"name": self.name, "expr": None if self.frac is None else str(self.frac),
                "status": self.status.label, "kind": self.kind, "basis": self.basis, "coordinate": self.coordinate,
                "seconds": round(self.seconds, 3), "method": self.method, "independent": self.independent,
                "notes": self.notes, "certificate": None if self.certificate is None else self.certificate.to_dict()}


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
    on_slice: Slice | None = field(default=None, repr=False)     # searched on the slice of parameter translations
    searched: QuadraticField | None = field(default=None, repr=False)   # the field the proof steps speak of
    chart: Chart | None = field(default=None, repr=False)       # searched in the chart of the affine normal form

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
                "slice": None if self.on_slice is None else self.on_slice.describe(),
                "chart": None if self.chart is None else self.chart.describe(),
                "seconds": round(time.perf_counter() - self.started, 3)}

    def text(self) -> str:
        """The integrals with their status, the kernels, the bases and what the search covered."""
        fixed = f" at {', '.join(f'{k}={v}' for k, v in self.fixed.items())}" if self.fixed else ""
        lines = [f"discover {self.system}{fixed}: monomials of degree <= {self.degree} in {', '.join(self.variables)}"]
        if self.chart is not None:
            lines.append(f"  {self.chart.describe()}")
        if self.on_slice is not None:
            lines.append(f"  {self.on_slice.describe()}")
        for k in self.kernels:
            lines.append(f"  degree {k['degree']}: {k['monomials']} monomials, kernel dimension {k['dimension']} "
                         f"({k['trivial']} trivial, {k['new']} new)")
        if self.bases:
            lines.append(f"  {len(self.bases)} minimal HK-bases, e.g. " + "; ".join(
                f"({', '.join(b['basis'])}) d={b.get('dimension')}" for b in self.bases[:4]))
        for i in self.integrals:
            expr = "not reconstructed" if i.frac is None else i.shown()
            flag = " [independent]" if i.independent else ""
            lines.append(f"  {i.name} = {expr}: {i.status.label}{flag} ({i.kind}"
                         + (f" of ({', '.join(i.basis)})" if i.basis else "") + ")")
        lines.append(f"{self.independent} functionally independent verified integrals in dimension "
                     f"{len(self.variables)}" + (f"; the kernels carry {self.expected_independent} (gradients mod p)"
                                                 if self.expected_independent is not None else ""))
        if self.negative:
            lines.append(self.negative)
        if self.skipped:
            lines.append(f"{len(self.skipped)} kernel coordinates skipped as too large for dense reconstruction")
        lines.append(("complete: " if self.complete else "budget ran out: ") + "; ".join(self.covered))
        return "\n".join(lines)

    def latex(self) -> str:
        """One LaTeX equation per integral found (reconstructed ones only), with its status as a comment."""
        out = [f"% integrals of the Kahan map of {self.system} (hkproof discover, degree {self.degree})"]
        for i in self.integrals:
            if i.frac is not None and i.too_large():
                out.append(f"% {i.name}: {i.status.label}; {i.summary()}")
            elif i.frac is not None:
                out.append(f"% {i.name}: {i.status.label}\n\\[ \\mathrm{{{i.name}}} = {i.latex()} \\]")
        if len(out) == 1:
            out.append("% no integral found")
        return "\n".join(out)
