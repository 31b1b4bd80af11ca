"""Quadratic vector fields x' = Q(x) + Bx + c (paper, eq. "diff eq gen"), with symbolic parameters."""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import sympy

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring, get_ring
from hkproof.errors import NotQuadraticError, ParseError, UnknownSystemError

EPS = "eps"
TILDE = "_t"


@dataclass(frozen=True)
class QuadraticField:
    """A vector field with components of degree <= 2 in the phase variables; coefficients in Q(parameters)."""

    name: str
    variables: tuple[str, ...]
    parameters: tuple[str, ...]
    rhs_text: tuple[str, ...]
    description: str = ""
    rhs: tuple[Frac, ...] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        variables, parameters = tuple(self.variables), tuple(self.parameters)
        object.__setattr__(self, "variables", variables)
        object.__setattr__(self, "parameters", parameters)
        object.__setattr__(self, "rhs_text", tuple(str(t) for t in self.rhs_text))
        names = variables + (EPS,) + parameters
        if len(set(names)) != len(names):
            raise ParseError(f"variable and parameter names must be distinct and not '{EPS}': {names}")
        clash = [v for v in variables if v + TILDE in names]
        if clash:
            raise ParseError(f"names ending in '{TILDE}' are reserved for x-tilde: rename {clash}")
        if len(self.rhs_text) != len(variables):
            raise ParseError(f"{len(variables)} variables but {len(self.rhs_text)} right-hand sides")
        rhs = tuple(Frac.parse(self.ring, t) for t in self.rhs_text)
        for v, f in zip(variables, rhs):
            if EPS in f.variables():
                raise ParseError(f"the right-hand side of {v}' uses '{EPS}', which is reserved for the step size")
            bad = f.den_variables_in(variables)
            if bad:
                raise NotQuadraticError(
                    f"the right-hand side of {v}' = {f} is not polynomial in the phase variables "
                    f"(its denominator involves {sorted(bad)}); Kahan's scheme needs degree <= 2 polynomials")
            deg = f.degrees_in(variables)[0]
            if deg > 2:
                raise NotQuadraticError(
                    f"the right-hand side of {v}' = {f} has degree {deg} in the phase variables; "
                    "Kahan's discretization (eq. \"Kahan gen\") applies to fields of degree <= 2 only")
        object.__setattr__(self, "rhs", rhs)

    @property
    def ring(self) -> Ring:
        """Z[x, eps, parameters]: where the Kahan map and its integrals live."""
        return get_ring(self.variables + (EPS,) + self.parameters)

    @property
    def tilde_variables(self) -> tuple[str, ...]:
        return tuple(v + TILDE for v in self.variables)

    @property
    def tilde_ring(self) -> Ring:
        """Z[x, x~, eps, parameters]: where the Kahan equations E(x, x~, eps) live."""
        return get_ring(self.variables + self.tilde_variables + (EPS,) + self.parameters)

    def specialize(self, values: Mapping[str, object]) -> "QuadraticField":
        """The same field with some parameters fixed to numbers (a smaller ring for a smaller question)."""
        unknown = set(values) - set(self.parameters)
        if unknown:
            raise ParseError(f"{sorted(unknown)} are not parameters of {self.name} ({list(self.parameters)})")
        subs = {sympy.Symbol(k): sympy.nsimplify(v) for k, v in values.items()}
        rhs = [str(sympy.sympify(t, locals={n: sympy.Symbol(n) for n in self.ring.names}).subs(subs))
               for t in self.rhs_text]
        fixed = ", ".join(f"{k}={v}" for k, v in values.items())
        return QuadraticField(f"{self.name}[{fixed}]", self.variables,
                              tuple(p for p in self.parameters if p not in values), tuple(rhs),
                              self.description)

    @classmethod
    def from_toml(cls, path: str | Path) -> "QuadraticField":
        """Read a field from a TOML file with `variables`, optional `parameters`, and a table `[rhs]`."""
        path = Path(path)
        try:
            data = tomllib.loads(path.read_text())
        except FileNotFoundError:
            raise UnknownSystemError(f"no such file: {path}") from None
        except tomllib.TOMLDecodeError as exc:
            raise ParseError(f"{path} is not valid TOML: {exc}") from None
        try:
            variables = list(data["variables"])
            rhs_table = data["rhs"]
        except KeyError as exc:
            raise ParseError(f"{path} needs a list `variables` and a table `[rhs]` (missing {exc})") from None
        missing = [v for v in variables if v not in rhs_table]
        extra = [k for k in rhs_table if k not in variables]
        if missing or extra:
            raise ParseError(f"{path}: [rhs] must give one right-hand side per variable "
                             f"(missing {missing}, not variables {extra})")
        return cls(str(data.get("name", path.stem)), tuple(variables), tuple(data.get("parameters", [])),
                   tuple(str(rhs_table[v]) for v in variables), str(data.get("description", "")))

