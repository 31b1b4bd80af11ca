"""Elements of the fraction field Q(v1, ..., vk) as num/den over Z[v], kept in lowest terms."""
from __future__ import annotations

from enum import Enum
from fractions import Fraction
from functools import lru_cache
from typing import TYPE_CHECKING, Mapping, Sequence, TypeAlias

import flint

from hkproof.algebra.printing import math
from hkproof.algebra.ring import Rational, Ring, to_fmpq
from hkproof.errors import ParseError, RingMismatchError, SingularPointError

if TYPE_CHECKING:
    import sympy

__all__ = ["Frac", "homogenized_compose", "normalize_sign", "Operand", "Parity", "poly_str"]


Operand: TypeAlias = "Frac | int | flint.fmpz | flint.fmpq | Fraction | flint.fmpz_mpoly"


class Parity(str, Enum):
    """Behaviour of a rational function under v -> -v (paper, Prop. "prop: even")."""
    EVEN = "even"
    ODD = "odd"
    NEITHER = "neither"


def _lowest_terms(num: flint.fmpz_mpoly, den: flint.fmpz_mpoly) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
    if den.is_zero():
        raise ZeroDivisionError("denominator is the zero polynomial")
    if num.is_zero():
        return num, den.context().constant(1)
    g = num.gcd(den)
    if not g.is_one():
        num, den = num / g, den / g
    return normalize_sign(num, den)


def normalize_sign(num: flint.fmpz_mpoly, den: flint.fmpz_mpoly) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
    """Fix the sign of num/den so that the last term of den (its constant term, if any) is positive."""
    if den.coefficient(len(den) - 1) < 0:
        return -num, -den
    return num, den


def _exponent_parity(p: flint.fmpz_mpoly, i: int) -> int | None:
    """0 if every exponent of variable i in p is even, 1 if every one is odd, None if both occur (FLINT's deflation
    index: the gcd of the exponents' differences, 0 for a single exponent, and the smallest exponent)."""
    strides, shifts = p.deflation_index()
    return None if strides[i] % 2 else shifts[i] % 2


class Frac:
    """A rational function num/den over Z[v]: gcd(num, den) = 1 and the last term of den positive.

    Integers, rationals and polynomials of the same ring coerce into the field; elements of other rings do not.

    >>> from hkproof.algebra.ring import get_ring
    >>> r = get_ring(("x", "eps"))
    >>> h = Frac.parse(r, "x/(1 + eps**2)")
    >>> h + 1, h * r.gen("eps"), bool(h - h)
    ((eps**2 + x + 1)/(eps**2 + 1), (x*eps)/(eps**2 + 1), False)
    >>> h.parity("eps"), h.is_even_in("eps")
    (<Parity.EVEN: 'even'>, True)
    """

    __slots__ = ("ring", "num", "den")

    def __init__(self, ring: Ring, num: flint.fmpz_mpoly | int, den: flint.fmpz_mpoly | int = 1,
                 *, reduced: bool = False):
        self.ring = ring
        if not isinstance(num, flint.fmpz_mpoly):
            num = ring.constant(int(num))
        if not isinstance(den, flint.fmpz_mpoly):
            den = ring.constant(int(den))
        if reduced:
            self.num, self.den = num, den
        else:
            self.num, self.den = _lowest_terms(num, den)

    # ---- construction ---------------------------------------------------------------------------
    @classmethod
    def parse(cls, ring: Ring, text: str, known: Mapping[str, "Frac"] | None = None) -> "Frac":
        """Read a rational function exactly (hkproof.algebra.formula: no eval; decimals are exact decimals)."""
        from hkproof.algebra.formula import parse_formula
        if known:
            return parse_formula(ring, text, known)
        return _parse_cached(ring, text)

    @classmethod
    def rational(cls, ring: Ring, value: Rational) -> "Frac":
        v = to_fmpq(value)
        return cls(ring, ring.constant(int(v.p)), ring.constant(int(v.q)))

    # ---- arithmetic ----------------------------------------------------------------------------
    def _coerce(self, other: object) -> "Frac":
        """other as an element of this field: a Frac of the same ring, a polynomial of its ring, or a rational."""
        if isinstance(other, Frac):
            if other.ring != self.ring:
                raise RingMismatchError(f"cannot combine an element of {self.ring} with one of {other.ring}")
            return other
        if isinstance(other, (int, flint.fmpz)) and not isinstance(other, bool):
            return Frac(self.ring, self.ring.constant(int(other)), reduced=True)
        if isinstance(other, (flint.fmpq, Fraction)):
            return Frac(self.ring, int(other.numerator), int(other.denominator))
        if isinstance(other, flint.fmpz_mpoly):
            if other.context() is not self.ring.ctx:
                raise RingMismatchError(f"cannot combine an element of {self.ring} with a polynomial in "
                                        f"{other.context().names()}")
            return Frac(self.ring, other, reduced=True)
        return NotImplemented

    def __add__(self, other: "Operand") -> "Frac":
        o = self._coerce(other)
        if o is NotImplemented:
            return o
        if self.den == o.den:
            return Frac(self.ring, self.num + o.num, self.den)
        g = self.den.gcd(o.den)
        a, b = self.den / g, o.den / g
        return Frac(self.ring, self.num * b + o.num * a, self.den * b)

    __radd__ = __add__

    def __neg__(self) -> "Frac":
        return Frac(self.ring, -self.num, self.den, reduced=True)

    def __sub__(self, other: "Operand") -> "Frac":
        o = self._coerce(other)
        if o is NotImplemented:
            return o
        return self + (-o)

    def __rsub__(self, other: "Operand") -> "Frac":
        return (-self) + other

    def __mul__(self, other: "Operand") -> "Frac":
        o = self._coerce(other)
        if o is NotImplemented:
            return o
        if self.num.is_zero() or o.num.is_zero():
            return Frac(self.ring, 0)
        g1, g2 = self.num.gcd(o.den), o.num.gcd(self.den)
        num, den = (self.num / g1) * (o.num / g2), (self.den / g2) * (o.den / g1)
        return Frac(self.ring, *normalize_sign(num, den), reduced=True)

    __rmul__ = __mul__

    def inverse(self) -> "Frac":
        if self.num.is_zero():
            raise ZeroDivisionError("inverse of the zero rational function")
        return Frac(self.ring, *normalize_sign(self.den, self.num), reduced=True)   # still in lowest terms

    def __truediv__(self, other: "Operand") -> "Frac":
        o = self._coerce(other)
        if o is NotImplemented:
            return o
        return self * o.inverse()

    def __rtruediv__(self, other: "Operand") -> "Frac":
        return self.inverse() * other

    def __pow__(self, k: int) -> "Frac":
        if k < 0:
            return self.inverse() ** (-k)
        return Frac(self.ring, self.num**k, self.den**k, reduced=True)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Frac) and other.ring != self.ring:
            return False
        o = self._coerce(other)
        if o is NotImplemented:
            return NotImplemented
        return self.num == o.num and self.den == o.den

    def __bool__(self) -> bool:
        return not self.num.is_zero()

    def __hash__(self) -> int:
        return hash((self.ring, str(self.num), str(self.den)))

    def is_zero(self) -> bool:
        return self.num.is_zero()

    def is_polynomial(self) -> bool:
        return self.den.is_constant()

    def is_constant(self) -> bool:
        return self.num.is_constant() and self.den.is_constant()

    def constant_value(self) -> flint.fmpq:
        """The rational number of a constant function (ParseError if it depends on a variable)."""
        if not self.is_constant():
            raise ParseError(f"{self} is not a constant (it involves {sorted(self.variables())})")
        return flint.fmpq(self.num.coefficient(0) if len(self.num) else 0, self.den.coefficient(0))

    # ---- structure ----------------------------------------------------------------------------
    def variables(self) -> set[str]:
        """Names of the variables that occur in num or den."""
        return self.ring.variables_of(self.num) | self.ring.variables_of(self.den)

    def den_variables_in(self, names: Sequence[str]) -> set[str]:
        """Those of `names` on which the denominator depends."""
        degs = self.den.degrees()
        return {n for n in names if degs[self.ring.index(n)] > 0}

    def degrees_in(self, names: Sequence[str]) -> tuple[int, int]:
        """(total degree of num, total degree of den) in the given variables only."""
        idx = [self.ring.index(n) for n in names]
        num, den = (max((sum(m[i] for i in idx) for m in p.monoms()), default=0) for p in (self.num, self.den))
        return num, den

    def substitute(self, values: Mapping[str, flint.fmpz_mpoly | int], target: Ring | None = None) -> "Frac":
        """The function with the named variables replaced by polynomials of `target` (Ring.substitute), reduced.

        >>> from hkproof.algebra.ring import get_ring
        >>> r = get_ring(("x", "y"))
        >>> h = Frac.parse(r, "x/(x + y)")
        >>> h.substitute({"y": r.gen("x")})
        (1)/(2)
        """
        target = target or self.ring
        return Frac(target, self.ring.substitute(self.num, values, target),
                    self.ring.substitute(self.den, values, target))

    def parity(self, name: str) -> Parity:
        """Exact parity in one variable: even, odd or neither, read from the exponents of num and den.

        If the exponents of v in num have one parity and those in den one parity, h is even when the two agree and
        odd when they differ, whatever the form. Conversely, in lowest terms h(-v) = +-h(v) forces num(-v) = c num(v)
        and den(-v) = +-c den(v) with c = +-1 (v -> -v keeps num and den coprime, so each divides the other's image),
        so "neither" is exact too. FLINT's deflation index reads the parities without a loop over the terms (the
        substitution eps -> -eps and a comparison cost seconds on the 300 000-term components of the Clebsch flows).

        >>> from hkproof.algebra.ring import get_ring
        >>> r = get_ring(("x", "eps"))
        >>> [Frac.parse(r, t).parity("eps").value for t in ("x*eps/(1 + eps**2)", "eps/(eps**3 + x*eps)", "1 + eps")]
        ['odd', 'even', 'neither']
        """
        i = self.ring.index(name)
        top, bottom = (_exponent_parity(p, i) for p in (self.num, self.den))
        if top is None or bottom is None:
            return Parity.NEITHER
        return Parity.EVEN if top == bottom else Parity.ODD

    def is_even_in(self, name: str) -> bool:
        """True iff f(..., -v, ...) = f(..., v, ...) exactly (Prop. "prop: even")."""
        return self.parity(name) is Parity.EVEN

    def derivative(self, name: str) -> "Frac":
        i = self.ring.index(name)
        return Frac(self.ring, self.num.derivative(i) * self.den - self.num * self.den.derivative(i),
                    self.den * self.den)

    def pullback(self, images: Sequence[flint.fmpz_mpoly], den: flint.fmpz_mpoly,
                 moved: Sequence[str]) -> "Frac":
        """self with moved[k] replaced by images[k]/den (a map with common denominator), in lowest terms."""
        return Frac(self.ring, *self.pullback_terms(images, den, moved))

    def pullback_terms(self, images: Sequence[flint.fmpz_mpoly], den: flint.fmpz_mpoly, moved: Sequence[str],
                       den_image: tuple[flint.fmpz_mpoly, int] | None = None
                       ) -> tuple[flint.fmpz_mpoly, flint.fmpz_mpoly]:
        """(P, Q) with P/Q = self(images/den), not reduced: two homogenized composes and no gcd (one, when the
        caller passes `den_image`, the compose of self.den it already has)."""
        pn, dn = homogenized_compose(self.ring, self.num, moved, images, den)
        pd, dd = den_image if den_image is not None else homogenized_compose(self.ring, self.den, moved, images, den)
        if dn > dd:
            pd = pd * den ** (dn - dd)
        elif dd > dn:
            pn = pn * den ** (dd - dn)
        return pn, pd

    def is_ratio(self, num: flint.fmpz_mpoly, den: flint.fmpz_mpoly) -> bool:
        """num/den == self, with no gcd: self being in lowest terms, num = k self.num and den = k self.den for one
        polynomial k (one exact division and one product)."""
        if den.is_zero():
            raise ZeroDivisionError("denominator is the zero polynomial")
        if self.num.is_zero():
            return num.is_zero()
        k, rem = divmod(num, self.num)
        return rem.is_zero() and k * self.den == den

    # ---- evaluation ---------------------------------------------------------------------------
    def evaluate(self, values: Mapping[str, Rational]) -> flint.fmpq:
        """The exact value at a point fixing every variable; SingularPointError where den vanishes."""
        d = self.ring.evaluate(self.den, values)
        if d == 0:
            raise SingularPointError(f"the denominator {self.den} vanishes at {dict(values)}")
        return self.ring.evaluate(self.num, values) / d

    def mod_p(self, p: int) -> ModularFrac:
        """This function reduced mod the prime p, for many cheap evaluations (and gradients) at residues."""
        return ModularFrac(self, p)

    def residue_at(self, point: Sequence[int], p: int) -> int | None:
        """The value mod p at a point of residues (one per ring variable, in order); None where the denominator
        vanishes mod p."""
        return self.mod_p(p)(point)

    def specialize(self, values: Mapping[str, Rational], target: Ring) -> "Frac":
        """The function with some variables fixed, as an element over the smaller ring `target`."""
        p, a = self.ring.specialize_poly(self.num, values, target)
        q, b = self.ring.specialize_poly(self.den, values, target)
        if q.is_zero():
            raise SingularPointError(f"the denominator {self.den} vanishes identically at {dict(values)}")
        return Frac(target, p * int(b), q * int(a))

    def to_ring(self, target: Ring) -> "Frac":
        """The same function over a ring with more (or re-ordered) variables."""
        return Frac(target, self.num.project_to_context(target.ctx),
                    self.den.project_to_context(target.ctx), reduced=True)

    # ---- output -------------------------------------------------------------------------------
    def __str__(self) -> str:
        """A string that sympy.sympify parses with the ring's own names."""
        num = poly_str(self.num)
        if self.den.is_one():
            return num
        return f"({num})/({poly_str(self.den)})"

    __repr__ = __str__

    def to_sympy(self) -> sympy.Expr:
        """num/den as a sympy expression in the ring's own names."""
        return self.ring.to_sympy(self.num) / self.ring.to_sympy(self.den)

    def _repr_latex_(self) -> str:
        return math(self.to_sympy())


class ModularFrac:
    """num/den reduced mod a prime p (nmod_mpoly): values and gradients at residues, None where den vanishes.

    >>> from hkproof.algebra.ring import get_ring
    >>> h = Frac.parse(get_ring(("x", "y")), "x**2/(1 + y)").mod_p(7)
    >>> h([3, 1]), h.gradient([3, 1])
    (1, [3, 3])
    """

    def __init__(self, h: Frac, p: int):
        ctx = flint.nmod_mpoly_ctx.get(h.ring.names, p, "degrevlex")  # type: ignore[call-arg, arg-type]  # flint's stubs lag the API
        self.p = p
        self.num, self.den = (ctx.from_dict({m: int(c) % p for m, c in poly.to_dict().items() if int(c) % p})
                              for poly in (h.num, h.den))
        self._derivatives: list[tuple[flint.nmod_mpoly, flint.nmod_mpoly]] | None = None
        self._polynomial = self.den.is_one()    # a polynomial (a monomial of a basis, mostly): no division

    def __call__(self, point: Sequence[int]) -> int | None:
        if self._polynomial:
            return int(self.num(*point))
        d = int(self.den(*point))
        return None if d == 0 else int(self.num(*point)) * pow(d, -1, self.p) % self.p

    def gradient(self, point: Sequence[int], variables: Sequence[int] | None = None) -> list[int] | None:
        """d/dx_i of num/den mod p at the point, for the ring variables of the given indices (all by default)."""
        n = len(point)
        if self._derivatives is None:
            self._derivatives = [(self.num.derivative(i), self.den.derivative(i)) for i in range(n)]
        d = int(self.den(*point))
        if d == 0:
            return None
        num, inv = int(self.num(*point)), pow(d, -2, self.p)
        return [(int(dn(*point)) * d - num * int(dd(*point))) * inv % self.p
                for dn, dd in (self._derivatives[i] for i in (variables if variables is not None else range(n)))]


def poly_str(p: flint.fmpz_mpoly) -> str:
    """A polynomial as a sympy-parsable string (python power syntax)."""
    return str(p).replace("^", "**")


@lru_cache(maxsize=4096)
def _parse_cached(ring: Ring, text: str) -> Frac:
    """A formula read once per ring (a Frac is never changed in place)."""
    from hkproof.algebra.formula import parse_formula
    return parse_formula(ring, text)


def homogenized_compose(ring: Ring, p: flint.fmpz_mpoly, moved: Sequence[str],
                        images: Sequence[flint.fmpz_mpoly], den: flint.fmpz_mpoly) -> tuple[flint.fmpz_mpoly, int]:
    """(p(images/den) * den^d, d) with d the total degree of p in `moved`: one compose of homogenized p."""
    idx = [ring.index(n) for n in moved]
    if p.is_zero():
        return p, 0
    d = max(sum(m[i] for i in idx) for m in p.monoms())
    hring = ring.extend(["_hom"])
    data = {}
    for m, c in p.to_dict().items():
        data[m + (d - sum(m[i] for i in idx),)] = c
    ph = hring.ctx.from_dict(data)
    args = list(ring.gens())
    for i, img in zip(idx, images, strict=True):
        args[i] = img
    args.append(den)
    return ph.compose(*args), d
