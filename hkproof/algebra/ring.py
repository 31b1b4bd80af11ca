"""Polynomial rings Z[names] on python-flint, with parsing from strings and specialization."""
from __future__ import annotations

import os
from contextlib import contextmanager
from fractions import Fraction
from functools import lru_cache
from typing import TYPE_CHECKING, Iterable, Iterator, Mapping, Sequence

import flint

from hkproof.algebra.printing import poly_to_sympy
from hkproof.errors import ParseError, UnknownSymbolError

if TYPE_CHECKING:
    import sympy

__all__ = ["flint_threads", "get_ring", "Rational", "Ring", "to_fmpq"]

Rational = int | Fraction | flint.fmpq | str  # a str is read exactly by to_fmpq ('1/3', '0.1')


def to_fmpq(value: Rational | str) -> flint.fmpq:
    """An exact rational from an int, a Fraction, an fmpq or a string such as '3/7' or '0.1' (read exactly)."""
    if isinstance(value, flint.fmpq):
        return value
    if isinstance(value, flint.fmpz):
        return flint.fmpq(value)
    if isinstance(value, str):
        from hkproof.algebra.formula import parse_rational
        return parse_rational(value)
    if isinstance(value, bool) or not isinstance(value, (int, Fraction)):
        raise ParseError(f"{value!r} is not an exact rational number (give an int, a fraction 'a/b' or a Fraction)")
    value = Fraction(value)
    return flint.fmpq(value.numerator, value.denominator)


class Ring:
    """The polynomial ring Z[v1, ..., vk] with named variables (degrevlex order); fractions live over it."""

    def __init__(self, names: Sequence[str]):
        names = tuple(names)
        if len(set(names)) != len(names):
            raise ParseError(f"repeated variable names in {names}")
        if not names:
            raise ParseError("a ring needs at least one variable")
        self.names = names
        self.ctx = flint.fmpz_mpoly_ctx.get(names, "degrevlex")
        self.qctx = flint.fmpq_mpoly_ctx.get(names, "degrevlex")

    def __repr__(self) -> str:
        return f"Ring(Z[{', '.join(self.names)}])"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Ring) and other.names == self.names

    def __hash__(self) -> int:
        return hash(self.names)

    def gen(self, name: str) -> flint.fmpz_mpoly:
        """The variable called `name` as a polynomial."""
        if name not in self.names:
            raise UnknownSymbolError(f"'{name}' is not a variable of {self}")
        return self.ctx.gen(self.names.index(name))

    def gens(self) -> tuple[flint.fmpz_mpoly, ...]:
        return self.ctx.gens()

    def constant(self, c: int) -> flint.fmpz_mpoly:
        return self.ctx.constant(c)

    def index(self, name: str) -> int:
        return self.names.index(name)

    # ---- conversion -------------------------------------------------------------------------
    def variables_of(self, p: flint.fmpz_mpoly) -> set[str]:
        """Names of the variables that occur in p."""
        return {self.names[i] for i, d in enumerate(p.degrees()) if d > 0}

    def to_sympy(self, p: flint.fmpz_mpoly) -> sympy.Expr:
        return poly_to_sympy(p)

    def substitute(self, p: flint.fmpz_mpoly, values: Mapping[str, flint.fmpz_mpoly | int],
                   target: "Ring | None" = None) -> flint.fmpz_mpoly:
        """p with the named variables replaced by polynomials of `target` (default: this ring) and every other
        variable sent to the variable of the same name in `target`: one compose.

        >>> r = get_ring(("x", "y"))
        >>> r.substitute(r.gen("x") ** 2 + r.gen("y"), {"x": r.gen("y") + 1})
        y^2 + 3*y + 1
        """
        target = target or self
        unknown = sorted(set(values) - set(self.names))
        if unknown:
            raise UnknownSymbolError(f"{unknown} are not variables of {self}")
        given = [values[n] if n in values else target.gen(n) for n in self.names]
        args = [a if isinstance(a, flint.fmpz_mpoly) else target.constant(int(a)) for a in given]
        return p.compose(*args, ctx=target.ctx)

    def to_q(self, p: flint.fmpz_mpoly) -> flint.fmpq_mpoly:
        return flint.fmpq_mpoly(p, self.qctx)

    # ---- smaller and larger rings -------------------------------------------------------------
    def drop(self, names: Iterable[str]) -> "Ring":
        names = set(names)
        return get_ring(tuple(n for n in self.names if n not in names))

    def extend(self, names: Iterable[str]) -> "Ring":
        return get_ring(self.names + tuple(n for n in names if n not in self.names))

    def project(self, p: flint.fmpz_mpoly, target: "Ring") -> flint.fmpz_mpoly:
        """p, which must not involve variables missing from `target`, as an element of `target`."""
        return p.project_to_context(target.ctx)

    def specialize_poly(self, p: flint.fmpz_mpoly, values: Mapping[str, Rational],
                        target: "Ring") -> tuple[flint.fmpz_mpoly, flint.fmpz]:
        """(P, d) with p|values = P/d in `target` (the ring without the fixed names), d > 0 an integer."""
        ints: dict[str | int, int] = {k: v for k, v in values.items() if isinstance(v, int) and not isinstance(v, bool)}
        rest: dict[str | int, flint.fmpq] = {k: to_fmpq(v) for k, v in values.items() if k not in ints}
        if ints:
            p = p.subs(ints)
        if not rest:
            return p.project_to_context(target.ctx), flint.fmpz(1)
        q = self.to_q(p).subs(rest).project_to_context(target.qctx)
        den = flint.fmpz(1)
        for c in q.coeffs():
            den = den.lcm(c.q)
        q = q * den
        return target.ctx.from_dict({m: int(c.p) for m, c in q.to_dict().items()}), den

    def point(self, values: Mapping[str, Rational]) -> list[flint.fmpq]:
        """The values of every variable, in the ring's order (exact rationals); ParseError for a missing one."""
        missing = [n for n in self.names if n not in values]
        if missing:
            raise ParseError(f"no value given for {missing}")
        return [to_fmpq(values[n]) for n in self.names]

    def evaluate(self, p: flint.fmpz_mpoly, values: Mapping[str, Rational]) -> flint.fmpq:
        """p at a point that fixes every variable (exact rational)."""
        return self.to_q(p)(*self.point(values))


@lru_cache(maxsize=None)
def get_ring(names: tuple[str, ...]) -> Ring:
    """The Ring with these names, built once and shared."""
    return Ring(names)


_SHARE: list[int | None] = [None]     # the cores a worker of `prove --jobs N` may use (share_cores), None: all


def share_cores(n: int | None) -> None:
    """Let this process use at most n cores (None: every core it may run on): a worker of `prove --jobs N` on C
    cores takes C // N, so that FLINT's threads and forked parts do not oversubscribe the machine (on two cores
    with two workers, two threads each cost `prove --all` a tenth more CPU and wall time)."""
    _SHARE[0] = n


def cores() -> int:
    """The cores this process may use: those it may run on, at most its share (`share_cores`)."""
    available = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return min(available, _SHARE[0]) if _SHARE[0] else available


@contextmanager
def flint_threads(n: int | None = None) -> Iterator[None]:
    """FLINT's own threads for big polynomial products and divisions (n = the cores this process may use)."""
    before = flint.ctx.threads
    flint.ctx.threads = n or cores()
    try:
        yield
    finally:
        flint.ctx.threads = before
