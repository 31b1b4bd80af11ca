"""The Python API for notebooks and scripts (`import hkproof as hk`): systems, maps, and the user commands as
functions returning the same results the command line prints.

>>> import hkproof as hk
>>> f = hk.kahan_map(hk.system(["x", "y"], ["-y", "x"], name="rotation"))
>>> hk.check_integral(f.field, "x**2 + y**2").status.label
'verified'
"""
from __future__ import annotations

from typing import Mapping, Sequence

from hkproof.algebra.ring import Rational
from hkproof.budget import Budget
from hkproof.dynamics.catalogue import get_system
from hkproof.dynamics.catalogue import kahan_map as _catalogue_map
from hkproof.dynamics.degrees import DegreeGrowth, degree_growth
from hkproof.dynamics.field import QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.integrals import IntegralVerdict
from hkproof.hk.integrals import check_integral as _check_integral
from hkproof.orchestration.registry import select
from hkproof.orchestration.runner import RunOptions, execute
from hkproof.pipelines.darboux import DarbouxSearch, search_darboux
from hkproof.pipelines.discover import DiscoveryReport
from hkproof.pipelines.discover import discover as _discover
from hkproof.pipelines.stages import Progress
from hkproof.proof.certificate import Certificate

__all__ = ["check_integral", "degrees", "discover", "kahan_map", "measure", "prove", "system"]

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
    return _discover(system(source), degree, params=params, seed=seed, progress=progress,
                     budget=Budget(seconds, raise_with="a larger `seconds`"))


def measure(source: System, degree: int = 4, *, params: Mapping[str, Rational] | None = None,
            seed: int = 0) -> DarbouxSearch:
    """Darboux polynomials, invariant measures dx/P and integrals P_i/P_j of degree <= `degree` (docs/geometry.md)."""
    f, fixed = _specialized(source, params)
    return search_darboux(f, degree, seed=seed, fixed=fixed)


def degrees(source: System, iterates: int = 8, *, values: Mapping[str, Rational] | None = None, seed: int = 0,
            runs: int = 2) -> DegreeGrowth:
    """deg f^n, n = 1..iterates, on random lines mod large primes (evidence), and its growth."""
    return degree_growth(kahan_map(source), iterates, values, seed=seed, runs=runs)


def check_integral(source: System, expr: str, *, params: Mapping[str, Rational] | None = None) -> IntegralVerdict:
    """Is `expr` an integral of the Kahan map? Exact substitution h(N/Delta) - h = 0, every parameter not in
    `params` symbolic."""
    f, fixed = _specialized(source, params)
    h = system(source).parse(expr)
    return _check_integral(f, h.specialize(fixed, f.ring) if fixed else h)


def prove(*ids: str, groups: Sequence[str] = (), include_slow: bool = True, jobs: int = 1) -> list[Certificate]:
    """Certificates of the paper's theorems (by id or group; all of them when none is given)."""
    run = execute(select(ids=ids, groups=groups, include_slow=include_slow), RunOptions(jobs=jobs))
    return [cert for _, cert in run.finished]
