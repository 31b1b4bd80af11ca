"""Quadratic vector fields x' = Q(x) + Bx + c (paper, eq. "diff eq gen"), with symbolic parameters."""
from __future__ import annotations

import os
import stat
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.formula import check_name
from hkproof.algebra.ring import Rational, Ring, get_ring, to_fmpq
from hkproof.errors import (FormulaTooLargeError, NotQuadraticError, ParseError, ResourceLimitError,
                            UnknownSystemError)

__all__ = ["EPS", "QuadraticField", "STEP_CONVENTION", "STEPS", "TILDE"]

EPS = "eps"
TILDE = "_t"


STEPS = ("eps", "h")
STEP_CONVENTION = ("hkproof's eps is HALF the time step: x~ - x = 2 eps * (polarized field), i.e. h = 2 eps in the "
                   "convention of Celledoni-McLachlan-Owren-Quispel")
MAX_VARIABLES = 64          # phase variables of a system: exact orbits cost n^3 per step, det M can have 2^n terms
MAX_PARAMETERS = 64         # parameters of a system
MAX_FILE_BYTES = 10_000_000  # size of a TOML file of a system


@dataclass(frozen=True)
class QuadraticField:
    """A vector field with components of degree <= 2 in the phase variables; coefficients in Q(parameters).

    hkproof's `eps` is half the time step (x~ - x = 2 eps * polarized field). `step = "h"` lets formulas read for
    this system use `h` for the full step h = 2 eps.
    """

    name: str
    variables: tuple[str, ...]
    parameters: tuple[str, ...]
    rhs_text: tuple[str, ...]
    description: str = ""
    step: str = "eps"
    rhs: tuple[Frac, ...] = field(init=False, repr=False, compare=False)

    def __reduce__(self) -> tuple:
        """Pickled as its data (the right-hand sides as text, read again exactly): for worker processes."""
        return (QuadraticField, (self.name, self.variables, self.parameters, self.rhs_text, self.description,
                                 self.step))

    def __post_init__(self) -> None:
        variables, parameters = tuple(self.variables), tuple(self.parameters)
        object.__setattr__(self, "variables", variables)
        object.__setattr__(self, "parameters", parameters)
        object.__setattr__(self, "rhs_text", tuple(str(t) for t in self.rhs_text))
        _check_names(variables, parameters, self.step)
        if len(self.rhs_text) != len(variables):
            raise ParseError(f"{len(variables)} variables but {len(self.rhs_text)} right-hand sides")
        rhs = []
        for v, text in zip(variables, self.rhs_text, strict=True):
            try:
                f = Frac.parse(self.ring, text)
            except ParseError as exc:
                raise type(exc)(f"the right-hand side of {v}': {exc}") from None
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
            rhs.append(f)
        object.__setattr__(self, "rhs", tuple(rhs))

    @property
    def ring(self) -> Ring:
        """Z[x, eps, parameters]: where the Kahan map and its integrals live."""
        return get_ring(self.variables + (EPS,) + self.parameters)

    @property
    def control_names(self) -> tuple[str, ...]:
        """eps and the parameters: the names a scene or a modular map fixes."""
        return (EPS,) + self.parameters

    @property
    def tilde_variables(self) -> tuple[str, ...]:
        return tuple(v + TILDE for v in self.variables)

    @property
    def tilde_ring(self) -> Ring:
        """Z[x, x~, eps, parameters]: where the Kahan equations E(x, x~, eps) live."""
        return get_ring(self.variables + self.tilde_variables + (EPS,) + self.parameters)

    def parse(self, text: str) -> Frac:
        """A formula over this system's names (and `h` = 2 eps when the system declares step = "h"), exactly."""
        if self.step == "h":
            return Frac.parse(self.ring, text, {"h": 2 * Frac(self.ring, self.ring.gen(EPS))})
        return Frac.parse(self.ring, text)

    def check_values(self, values: Mapping[str, Rational | str]) -> dict[str, flint.fmpq]:
        """Values of eps and parameters read exactly and checked: known names, eps != 0 (the map would be the
        identity), and off the poles of the field's coefficients (such as w_i = w_j where it divides by w_i - w_j)."""
        names = (EPS,) + self.parameters
        unknown = sorted(set(values) - set(names))
        if unknown:
            raise ParseError(f"{unknown} are not eps or parameters of {self.name} (they are {list(names)})")
        exact = {k: to_fmpq(v) for k, v in values.items()}
        if exact.get(EPS) == 0:
            raise ParseError("eps = 0 makes the Kahan map the identity: give a non-zero step (hkproof's eps is half "
                             "the time step)")
        params = {k: v for k, v in exact.items() if k != EPS}
        if params:
            target = self.ring.drop(params)
            for v, f in zip(self.variables, self.rhs, strict=True):
                if self.ring.specialize_poly(f.den, params, target)[0].is_zero():
                    at = ", ".join(f"{k}={x}" for k, x in params.items())
                    raise ParseError(f"the right-hand side of {v}' = {f} is undefined at {at}: its denominator "
                                     f"{f.den} vanishes there (a pole of the coefficients)")
        return exact

    def specialize(self, values: Mapping[str, Rational | str]) -> "QuadraticField":
        """The same field with some parameters fixed to exact numbers (a smaller ring for a smaller question)."""
        unknown = set(values) - set(self.parameters)
        if unknown:
            raise ParseError(f"{sorted(unknown)} are not parameters of {self.name} ({list(self.parameters)})")
        exact = self.check_values(values)
        target = self.ring.drop(exact)
        rhs = [str(f.specialize(exact, target)) for f in self.rhs]
        fixed = ", ".join(f"{k}={x}" for k, x in exact.items())
        return QuadraticField(f"{self.name}[{fixed}]", self.variables,
                              tuple(p for p in self.parameters if p not in values), tuple(rhs),
                              self.description, self.step)

    @classmethod
    def from_toml(cls, path: str | Path) -> "QuadraticField":
        """Read a field from a TOML file: `variables`, optional `parameters`, `name`, `description`, `step` and a
        table `[rhs]` of formulas (strings, or integers); the file is data, never code."""
        path = Path(path)
        try:
            data = tomllib.loads(read_system_file(path))
        except tomllib.TOMLDecodeError as exc:
            raise ParseError(f"{path} is not valid TOML: {exc}") from None
        except RecursionError:
            raise ParseError(f"{path} nests arrays or tables too deeply to be a system (variables, parameters and "
                             "[rhs] need no nesting)") from None
        if "variables" not in data or "rhs" not in data:
            raise ParseError(f"{path} needs a list `variables` and a table `[rhs]`")
        variables = _strings(data["variables"], f"{path}: `variables`")
        parameters = _strings(data.get("parameters", []), f"{path}: `parameters`")
        rhs_table = data["rhs"]
        if not isinstance(rhs_table, dict):
            raise ParseError(f"{path}: `rhs` must be a table [rhs] with one formula per variable")
        missing = [v for v in variables if v not in rhs_table]
        extra = [k for k in rhs_table if k not in variables]
        if missing or extra:
            raise ParseError(f"{path}: [rhs] must give one right-hand side per variable "
                             f"(missing {missing}, not variables {extra})")
        rhs = []
        for v in variables:
            value = rhs_table[v]
            if isinstance(value, bool) or not isinstance(value, (str, int)):
                raise ParseError(f"{path}: rhs.{v} must be a formula in quotes (a TOML {type(value).__name__} "
                                 f"such as {value!r} is not read exactly)")
            rhs.append(str(value))
        for key in ("name", "description", "step"):
            if key in data and not isinstance(data[key], str):
                raise ParseError(f"{path}: `{key}` must be a string")
        return cls(str(data.get("name", path.stem)), tuple(variables), tuple(parameters), tuple(rhs),
                   str(data.get("description", "")), str(data.get("step", "eps")))


def read_system_file(path: Path, cap: int = MAX_FILE_BYTES) -> str:
    """The UTF-8 text of a regular file of at most `cap` bytes. Anything else is refused before it is read: a FIFO
    would block, /dev/zero and /dev/urandom never end, a directory has no text."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise UnknownSystemError(_not_regular(path))
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except FileNotFoundError:
        raise UnknownSystemError(f"no such file: {path}") from None
    except OSError as exc:
        raise UnknownSystemError(f"cannot read {path}: {exc.strerror or exc}") from None
    with os.fdopen(fd, "rb") as fh:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):       # replaced between the two looks
            raise UnknownSystemError(_not_regular(path))
        data = fh.read(cap + 1) if info.st_size <= cap else b""
    if info.st_size > cap or len(data) > cap:
        raise FormulaTooLargeError(f"{path} has more than {cap} bytes, the limit for the file of a system")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise UnknownSystemError(f"cannot read {path}: it is not UTF-8 text ({exc.reason} at byte "
                                 f"{exc.start})") from None


def _not_regular(path: Path) -> str:
    kind = "a directory" if path.is_dir() else "not a regular file (a FIFO, a device or a socket)"
    return f"{path} is {kind}: a system is read from a regular TOML file only"


def _strings(value: object, what: str) -> list[str]:
    """A TOML list of strings, or a ParseError naming the key."""
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ParseError(f"{what} must be a list of names in quotes, e.g. [\"x\", \"y\"]")
    return value


def _check_names(variables: tuple[str, ...], parameters: tuple[str, ...], step: str) -> None:
    """Variables and parameters: identifiers, distinct, at least one variable, none reserved by hkproof."""
    if step not in STEPS:
        raise ParseError(f"step must be \"eps\" (half the time step, hkproof's convention) or \"h\" (the full "
                         f"step h = 2 eps), not {step!r}")
    if not variables:
        raise ParseError("a system needs at least one phase variable")
    for what, names, most in (("phase variables", variables, MAX_VARIABLES),
                              ("parameters", parameters, MAX_PARAMETERS)):
        if len(names) > most:
            raise ResourceLimitError(f"the system has {len(names)} {what}; hkproof handles at most {most} (no "
                                     "option raises this limit)",
                                     limit=f"{most} {what}", raise_with="no option raises it")
    for what, names in (("variable", variables), ("parameter", parameters)):
        for n in names:
            check_name(n, what)
            if n == EPS or (step == "h" and n == "h"):
                raise ParseError(f"{what} name {n!r} is reserved for the step size")
            if n.endswith(TILDE):
                raise ParseError(f"{what} name {n!r}: names ending in '{TILDE}' are reserved for x-tilde")
    names = variables + parameters
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ParseError(f"variable and parameter names must be distinct: {repeated} repeated")
