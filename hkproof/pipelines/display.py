"""How the reports of discover, measure and poisson show in Jupyter (Markdown with LaTeX) and convert to sympy.

The report classes live with their pipelines; IPython learns these renderers through its formatters (`register`),
the way it learns the display of any class it does not own.
"""
from __future__ import annotations

from typing import Any

from hkproof.algebra.printing import latex, markdown_table, poly_to_sympy
from hkproof.hk.poisson import pairs
from hkproof.pipelines.darboux import DarbouxSearch
from hkproof.pipelines.discover.report import DiscoveryReport
from hkproof.pipelines.poisson import PoissonReport
from hkproof.pipelines.poisson_candidates import Denominator

__all__ = ["darboux_markdown", "discovery_markdown", "poisson_markdown", "register", "report_to_sympy"]


def discovery_markdown(report: DiscoveryReport) -> str:
    """The integrals (LaTeX, status, kind), the kernels and what the search covered."""
    fixed = f" at {', '.join(f'{k} = {v}' for k, v in report.fixed.items())}" if report.fixed else ""
    lines = [f"**discover {report.system}**{fixed}: HK-bases among monomials of degree <= {report.degree}", ""]
    rows = [[i.name, i.summary() if i.frac is None or i.too_large() else f"${i.latex()}$",
             i.status.label, "yes" if i.independent else "", i.kind, f"{i.seconds:.2f} s"] for i in report.integrals]
    lines.append(markdown_table(["integral", "formula", "status", "independent", "found as", "time"], rows)
                 if rows else "no integral found")
    lines += ["", *(f"- degree {k['degree']}: {k['monomials']} monomials, kernel dimension {k['dimension']}"
                    for k in report.kernels)]
    lines.append(f"- {report.independent} functionally independent verified integrals in dimension "
                 f"{len(report.variables)}")
    lines.append(("- complete: " if report.complete else "- budget ran out: ") + "; ".join(report.covered))
    if report.stages:
        lines.append("- time: " + ", ".join(f"{k} {v:.2f} s" for k, v in report.stages.items()))
    return "\n".join(lines)


def darboux_markdown(search: DarbouxSearch) -> str:
    """Darboux polynomials with their cofactors, invariant measures and integrals, each with its status."""
    import sympy
    payload = search.to_dict()
    polys = [[f"${latex(sympy.factor(poly_to_sympy(d.poly)))}$", d.cofactor.text(search.atoms), p["status"]]
             for d, p in zip(search.darboux, payload["darboux"], strict=True)]
    lines = [f"**measure {search.system}**: Darboux polynomials P o f = K P of degree <= {search.degree}", "",
             markdown_table(["P", "cofactor K", "status"], polys) if polys else "no Darboux polynomial found", ""]
    lines += [f"- density {d['expr']}: {d['status']}" for d in payload["densities"]]
    lines += [f"- integral {d['expr']}: {d['status']}" for d in payload["integrals"]]
    return "\n".join(lines)


def poisson_markdown(report: PoissonReport) -> str:
    """Each invariant bivector (its brackets in LaTeX, status, Jacobi, rank, Casimirs) and each excluded class."""
    import sympy
    payload = report.to_dict()
    lines = [f"**poisson {report.system}**: invariant bivectors Q/D with deg Q <= {report.degree}", ""]
    for s, p in zip(report.structures, payload["structures"], strict=True):
        fracs = s.bivector.fracs()
        brackets = [f"$\\{{{a}, {b}\\}} = {latex(sympy.factor(fracs[i][j].to_sympy()))}$"
                    for i, j in pairs(len(report.variables)) if not fracs[i][j].is_zero()
                    for a, b in [(latex(sympy.Symbol(report.variables[i])), latex(sympy.Symbol(report.variables[j])))]]
        jacobi = {True: "Poisson", False: "not Poisson", None: "Jacobi not decided"}[s.poisson]
        lines += [f"- {p['name']} ({p['status']}, {jacobi}, rank {s.rank}, Casimirs "
                  f"{', '.join(p['casimir_names']) or 'none among the integrals'}): " + ", ".join(brackets)]
    rows = [[e.name, _short_latex(Denominator(e.name, e.denominator)), e.degree, p["status"]]
            for e, p in zip(report.excluded, payload["excluded"], strict=True)]
    if rows:
        lines += ["", "Excluded classes (no invariant Q/D: full column rank mod p)", "",
                  markdown_table(["D", "formula", "deg Q <=", "status"], rows)]
    lines += [f"- D = {k['denominator_name']}: a kernel of dimension {k['dimension']} mod p at degree {k['degree']} "
              f"({k['status']}, not rebuilt)" for k in payload["kernels"]]
    lines += [f"- {n}" for n in report.notes]
    if report.stopped:
        lines.append(f"- budget ran out: {report.stopped}")
    return "\n".join(lines)


def _short_latex(d: Denominator, limit: int = 40) -> str:
    """D factored in LaTeX, or its degree and size when it has more than `limit` terms (never printed to measure)."""
    import sympy
    return f"${latex(sympy.factor(poly_to_sympy(d.poly)))}$" if len(d.poly) <= limit else d.formula()


def report_to_sympy(report: DiscoveryReport | DarbouxSearch) -> dict[str, Any]:
    """The reconstructed integrals of discover ({name: expression}), or measure's Darboux polynomials."""
    if isinstance(report, DiscoveryReport):
        return {i.name: i.frac.to_sympy() for i in report.integrals if i.frac is not None}
    return {"darboux": [poly_to_sympy(d.poly) for d in report.darboux]}


def register(shell: Any) -> None:
    """Teach an IPython shell to show discover, measure and poisson reports as Markdown."""
    markdown = shell.display_formatter.formatters["text/markdown"]
    markdown.for_type(DiscoveryReport, discovery_markdown)
    markdown.for_type(DarbouxSearch, darboux_markdown)
    markdown.for_type(PoissonReport, poisson_markdown)
