"""The Python API for notebooks and scripts (`import hkproof as hk`): systems, maps, and the user commands as
functions returning the same results the command line prints; each result shows itself in Jupyter (Markdown with
LaTeX) and converts to sympy (`hk.to_sympy`).

>>> import hkproof as hk
>>> rotation = hk.system(["x", "y"], ["-y", "x"], name="rotation")
>>> cert = hk.check_integral(rotation, "x**2 + y**2")
>>> cert.status.label, cert.to_sympy()["h"]
('verified', x**2 + y**2)
>>> "| verified |" in cert._repr_markdown_()
True
>>> orbit = hk.orbit(rotation, "1, 0", steps=3, values={"eps": "1/2"})
>>> orbit.to_sympy()[1]
(3/5, 4/5)
>>> hk.degrees("lotka-volterra", 4).degrees
[2, 4, 8, 16]
"""
from __future__ import annotations

import random
import sys
from contextlib import suppress
from typing import TYPE_CHECKING, Any, Mapping, Sequence

from hkproof.algebra.ring import Rational
from hkproof.budget import Budget
from hkproof.dynamics.catalogue import get_system
from hkproof.dynamics.catalogue import kahan_map as _catalogue_map
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.dynamics.orbits import ExactOrbit, exact_orbit
from hkproof.dynamics.values import parse_point
from hkproof.experiments.degree_report import DegreeReport, degree_report
from hkproof.experiments.orbit_plot import orbit_figure as _orbit_figure
from hkproof.experiments.points import random_values
from hkproof.experiments.scan import ScanResult
from hkproof.experiments.scan import scan as _scan
from hkproof.hk.integrals import check_integral as _check_integral
from hkproof.orchestration.registry import select
from hkproof.orchestration.runner import RunOptions, execute
from hkproof.pipelines import display
from hkproof.pipelines.darboux import DarbouxSearch, search_darboux
from hkproof.pipelines.poisson import PoissonReport, with_integrals
from hkproof.pipelines.discover import DiscoveryReport
from hkproof.pipelines.discover import discover as _discover
from hkproof.pipelines.stages import Progress
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["check_integral", "degrees", "discover", "kahan_map", "measure", "orbit", "orbit_figure", "poisson", "prove",
           "scan", "system", "to_sympy"]

System = str | QuadraticField


def system(source: System | Sequence[str], rhs: Sequence[str] | None = None, *, parameters: Sequence[str] = (),
           name: str = "my-system") -> QuadraticField:
    """A quadratic vector field: a catalogue name, a TOML file, a QuadraticField, or variables and right-hand sides
    given as strings (read by hkproof's exact parser, never evaluated)."""
    if rhs is None:
        if isinstance(source, QuadraticField):
            return source
        if isinstance(source, str):
            return get_system(source)
        raise TypeError("give a catalogue name, a TOML path, a QuadraticField, or variables together with rhs")
    if isinstance(source, QuadraticField):
        raise TypeError("a QuadraticField already has its right-hand sides: drop rhs")
    variables = (source,) if isinstance(source, str) else tuple(source)
    return QuadraticField(name, variables, tuple(parameters), tuple(rhs))


def kahan_map(source: System) -> KahanMap:
    """The Kahan map of a system (eq. "Kahan gen"; eps is half the time step)."""
    return _catalogue_map(system(source))


def _specialized(source: System, params: Mapping[str, Rational] | None) -> tuple[KahanMap, dict]:
    field = system(source)
    fixed = field.check_values(dict(params or {}))
    return kahan_map(field.specialize(fixed) if fixed else field), fixed


def discover(source: System, degree: int = 2, *, params: Mapping[str, Rational] | None = None,
             seconds: float | None = None, seed: int = 0, progress: Progress | None = None) -> DiscoveryReport:
    """Integrals of the Kahan map whose HK-bases are monomials of degree <= `degree`, certified (docs/discover.md)."""
    _show_reports_in_ipython()
    return _discover(system(source), degree, params=params, seed=seed, progress=progress,
                     budget=Budget(seconds, raise_with="a larger `seconds`"))


def measure(source: System, degree: int = 4, *, params: Mapping[str, Rational] | None = None,
            seed: int = 0) -> DarbouxSearch:
    """Darboux polynomials, invariant measures dx/P and integrals P_i/P_j of degree <= `degree` (docs/geometry.md)."""
    f, fixed = _specialized(source, params)
    _show_reports_in_ipython()
    return search_darboux(f, degree, seed=seed, fixed=fixed)


def poisson(source: System, degree: int = 3, *, params: Mapping[str, Rational] | None = None,
            denominators: Sequence[str] = (), integrals_degree: int = 2, darboux_degree: int = 4,
            seconds: float | None = None, seed: int = 0) -> PoissonReport:
    """Invariant Poisson bivectors Q/D with deg Q <= `degree`, proven, or their classes excluded (docs/poisson.md)."""
    f, fixed = _specialized(source, params)
    _show_reports_in_ipython()
    dens = [f.field.parse(d) for d in denominators]
    return with_integrals(f, degree, dens, integrals_degree, darboux_degree=darboux_degree, seed=seed, fixed=fixed,
                          budget=Budget(seconds, raise_with="a larger `seconds`"))


def degrees(source: System, iterates: int = 8, *, values: Mapping[str, Rational] | None = None, seed: int = 0,
            runs: int = 2, symbolic_up_to: int = 0) -> DegreeReport:
    """deg f^n, n = 1..iterates, on random lines mod large primes (evidence; the first `symbolic_up_to` exact), and
    its growth."""
    return degree_report(kahan_map(source), iterates, values, seed=seed, runs=runs, symbolic_up_to=symbolic_up_to)


def scan(source: System, basis: str | Sequence[str], *, points: int = 10, values: Mapping[str, Rational] | None = None,
         arithmetic: str = "exact", seed: int = 0) -> ScanResult:
    """Algorithm (N): the kernel-dimension profile of a candidate HK-basis at random points (evidence)."""
    return _scan(kahan_map(source), basis, points=points, values=values, arithmetic=arithmetic, seed=seed)


def orbit(source: System, point: str | Sequence[Rational], steps: int = 20, *,
          values: Mapping[str, Rational] | None = None, seed: int = 0, max_digits: int = 100_000) -> ExactOrbit:
    """The exact orbit of a rational point over Q, stopped when it closes; eps and parameters from `values`, the
    others random (seeded)."""
    f = kahan_map(source)
    fixed = random_values(f, random.Random(seed), values)
    return exact_orbit(f, parse_point(f.field, point), fixed, steps, max_digits)


def orbit_figure(source: System, point: str | Sequence[Rational], values: Mapping[str, Rational], *,
                 steps: int = 3000) -> Figure:
    """A matplotlib figure of the float64 orbit of `point` at eps and parameters `values` (e.g. an orbit's)."""
    f = kahan_map(source)
    start = parse_point(f.field, point)
    return _orbit_figure(f, f.field.check_values(values), [start[v] for v in f.variables], steps)[0]


def check_integral(source: System, expr: str, *, params: Mapping[str, Rational] | None = None) -> Certificate:
    """Is `expr` an integral of the Kahan map? A certificate of the exact substitution h(N/Delta) - h = 0, every
    parameter not in `params` symbolic (verified, or refuted with the size of the difference)."""
    f, fixed = _specialized(source, params)
    h = system(source).parse(expr)
    h = h.specialize(fixed, f.ring) if fixed else h
    cert = Certificate("integral", f"an integral of the Kahan map of {f.field.name}", "hk.check_integral",
                       f"h = {h} satisfies h(f(x)) = h(x)", fixed={k: str(v) for k, v in fixed.items()})
    cert.formula("h", h)
    with suppress(ProofStopped), cert.step("h(f(x)) - h(x) = 0", "exact substitution h(N/Delta) - h", f.ring) as s:
        verdict = _check_integral(f, h)
        s.require(verdict.status is Status.VERIFIED, f"h(f(x)) - h(x) is not zero: {verdict.difference_terms} terms")
    return cert


def prove(*ids: str, groups: Sequence[str] = (), include_slow: bool = True, jobs: int = 1) -> list[Certificate]:
    """Certificates of the paper's theorems (by id or group; all of them when none is given)."""
    run = execute(select(ids=ids, groups=groups, include_slow=include_slow), RunOptions(jobs=jobs))
    return [cert for _, cert in run.finished]


def to_sympy(result: Any) -> Any:
    """A result as sympy objects: a certificate's exact formulas, an orbit's points, the integrals of discover or the
    Darboux polynomials of measure, a rational function."""
    if isinstance(result, (DiscoveryReport, DarbouxSearch)):
        return display.report_to_sympy(result)
    if hasattr(result, "to_sympy"):
        return result.to_sympy()
    raise TypeError(f"{type(result).__name__} has no sympy form")


def _show_reports_in_ipython() -> None:
    """In a running IPython (Jupyter), show discover, measure and poisson reports as Markdown (idempotent)."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None
    if shell is not None:
        display.register(shell)
