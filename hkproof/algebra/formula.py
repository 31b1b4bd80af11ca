"""The one reader of formulas: text -> exact element of Q(ring), by a tokenizer and a recursive-descent parser.

Nothing is evaluated as Python. The grammar (docs/usage.md, "Formulas"):

    expr   := term (("+" | "-") term)*
    term   := unary (("*" | "/") unary)*
    unary  := ("+" | "-") unary | power
    power  := atom (("**" | "^") unary)?        (right-associative; the exponent is an integer constant)
    atom   := NUMBER | NAME | "(" expr ")"

NUMBER is an integer or a decimal literal with an optional exponent (`12`, `0.1`, `1.5e-3`), read as the exact
rational it writes; NAME is a variable of the ring or a name bound in `known`. Sizes are bounded by `LIMITS`, so
that a formula is refused with a clear message instead of exhausting memory.
"""
from __future__ import annotations

import keyword
import math
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Iterable, Iterator, Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring, get_ring
from hkproof.errors import FormulaTooLargeError, ParseError, UnknownSymbolError

__all__ = ["check_name", "cycled", "indexed", "LIMITS", "Limits", "parse_formula", "parse_matrix", "parse_rational",
           "read_number", "rename", "split_list", "STRUCTURE", "Token", "tokens"]


@dataclass(frozen=True)
class Limits:
    """Documented bounds on what one formula may ask for (docs/usage.md, "Limits")."""

    length: int = 1_000_000          # characters of a formula
    literal_digits: int = 10_000     # digits of one number literal
    literal_exponent: int = 10_000   # |e| in a literal 1.5e<e>
    depth: int = 100                 # nesting of parentheses, signs and powers
    exponent: int = 1_000_000        # |k| in a ** k
    terms: int = 10_000_000          # terms a product or a power may create
    bits: int = 10_000_000           # bits of a coefficient a power may create
    megabytes: int = 1_000           # estimated size of the result of one product or power


LIMITS = Limits()

_TOKEN = re.compile(r"""
    (?P<space>[ \t\r\n]+)
  | (?P<number>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)
  | (?P<name>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<op>\*\*|[-+*/^()])
""", re.VERBOSE)
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
_WORDS = {"pi": "the constant pi is not rational", "I": "complex numbers are not allowed",
          "E": "Euler's number is not rational", "oo": "infinity is not a number", "inf": "infinity is not a number",
          "nan": "nan is not a number"}


@dataclass(frozen=True)
class Token:
    kind: str      # "number", "name", "op" or "end"
    text: str
    pos: int       # 1-based column


def check_name(name: str, what: str = "name") -> str:
    """A variable or parameter name: an ASCII identifier, not a Python keyword, not starting with '_'."""
    if not isinstance(name, str) or not _NAME.match(name):
        raise ParseError(f"{what} {name!r} is not an ASCII identifier (a letter, then letters, digits or '_')")
    if keyword.iskeyword(name):
        raise ParseError(f"{what} {name!r} is a Python keyword; output formulas must stay readable by sympy: "
                         "choose another name")
    return name


def check_new_names(names: Sequence[str], taken: Iterable[str], what: str = "name") -> list[str]:
    """Names for new quantities (kernel coordinates, functions): identifiers, pairwise distinct, and none of the names
    already `taken` (a system's variables, eps, parameters), which they would shadow.

    >>> check_new_names(["c1", "a1"], ["x1", "eps", "a1"], "coordinate name")
    Traceback (most recent call last):
    hkproof.errors.ParseError: coordinate name 'a1' is already a name of the system (x1, eps, a1): choose another
    """
    out = [check_name(n, what) for n in names]
    repeated = sorted({n for n in out if out.count(n) > 1})
    if repeated:
        raise ParseError(f"{what}s must be distinct: {', '.join(repeated)} given more than once")
    taken = list(taken)
    for n in out:
        if n in taken:
            raise ParseError(f"{what} {n!r} is already a name of the system ({', '.join(taken)}): choose another")
    return out


def _excerpt(text: str, pos: int) -> str:
    """The formula (or the part of it around column `pos` when it is long), for error messages."""
    if len(text) <= 80:
        return repr(text)
    lo = max(pos - 30, 0)
    return f"'...{text[lo:lo + 60]}...'"


def tokens(text: str) -> Iterator[Token]:
    """The tokens of a formula; anything else (a quote, a dot, a comma, a non-ASCII letter) is a ParseError."""
    i = 0
    while i < len(text):
        m = _TOKEN.match(text, i)
        if m is None:
            raise ParseError(f"cannot read {_excerpt(text, i + 1)}: unexpected character {text[i]!r} at column "
                             f"{i + 1} (formulas use numbers, names, + - * / ** ^ and parentheses)")
        if m.lastgroup != "space":
            yield Token(m.lastgroup or "", m.group(), i + 1)
        i = m.end()
    yield Token("end", "", len(text) + 1)


def read_number(literal: str, limits: Limits = LIMITS) -> flint.fmpq:
    """The exact rational written by an integer or decimal literal ('0.1' is 1/10, never a binary float), in ASCII
    digits (a Bengali four is no number), up to `limits.literal_digits` digits (beyond Python's int/str limit)."""
    m = re.fullmatch(r"([0-9]*)(?:\.([0-9]*))?(?:[eE]([+-]?[0-9]+))?", literal)
    if m is None or not (m.group(1) or m.group(2)):
        raise ParseError(f"{literal!r} is not a number literal")
    whole, frac, exp = m.group(1), m.group(2) or "", m.group(3)
    if len(whole) + len(frac) > limits.literal_digits:
        raise FormulaTooLargeError(f"a number literal has {len(whole) + len(frac)} digits; the limit is "
                                   f"{limits.literal_digits}")
    e = int(exp) if exp else 0
    if abs(e) > limits.literal_exponent:
        raise FormulaTooLargeError(f"the exponent of {literal!r} exceeds the limit {limits.literal_exponent}")
    e -= len(frac)
    mantissa = flint.fmpz((whole + frac).lstrip("0") or "0")   # FLINT reads decimal text without Python's limit
    return flint.fmpq(mantissa * flint.fmpz(10)**e) if e >= 0 else flint.fmpq(mantissa, flint.fmpz(10)**-e)


_INTEGER = re.compile(r"[+-]?[0-9]+")


def read_integer(text: str, limits: Limits = LIMITS) -> int:
    """An integer written in ASCII digits with an optional sign ('12', '-3'); anything else ('1.0', a Bengali four,
    '1e3') is refused.

    >>> read_integer("-12"), read_integer("\u09ea")
    Traceback (most recent call last):
    hkproof.errors.ParseError: '৪' is not an integer (ASCII digits 0-9, an optional sign)
    """
    if not isinstance(text, str) or not _INTEGER.fullmatch(text.strip()):
        raise ParseError(f"{text!r} is not an integer (ASCII digits 0-9, an optional sign)")
    if len(text.strip()) > limits.literal_digits + 1:
        raise FormulaTooLargeError(f"an integer of {len(text.strip())} characters; the limit is "
                                   f"{limits.literal_digits} digits")
    return int(flint.fmpz(text.strip().lstrip("+")))


class _Parser:
    """Recursive descent over the token list; values are Frac elements of `ring`, built as they are read."""

    def __init__(self, text: str, ring: Ring, known: Mapping[str, Frac], limits: Limits):
        if len(text) > limits.length:
            raise FormulaTooLargeError(f"the formula has {len(text)} characters; the limit is {limits.length}")
        self.text, self.ring, self.known, self.limits = text, ring, known, limits
        self.toks = list(tokens(text))
        self.i = 0
        self.depth = 0

    # ---- token helpers --------------------------------------------------------------------------
    @property
    def tok(self) -> Token:
        return self.toks[self.i]

    def error(self, message: str, tok: Token | None = None) -> ParseError:
        tok = tok or self.tok
        where = "at the end" if tok.kind == "end" else f"at column {tok.pos}"
        return ParseError(f"cannot read {_excerpt(self.text, tok.pos)}: {message} {where}")

    def take(self, *ops: str) -> Token | None:
        if self.tok.kind == "op" and self.tok.text in ops:
            self.i += 1
            return self.toks[self.i - 1]
        return None

    def enter(self) -> None:
        self.depth += 1
        if self.depth > self.limits.depth:
            raise FormulaTooLargeError(f"the formula nests deeper than {self.limits.depth} levels "
                                       f"(column {self.tok.pos})")

    # ---- grammar --------------------------------------------------------------------------------
    def parse(self) -> Frac:
        if self.tok.kind == "end":
            raise self.error("the formula is empty")
        value = self.expr()
        if self.tok.kind != "end":
            hint = "; write * for a product" if self.tok.kind in ("name", "number") or self.tok.text == "(" else ""
            raise self.error(f"unexpected {self.tok.text!r}{hint}")
        return value

    def expr(self) -> Frac:
        value = self.term()
        while (op := self.take("+", "-")) is not None:
            rhs = self.term()
            value = value + rhs if op.text == "+" else value - rhs
        return value

    def term(self) -> Frac:
        value = self.unary()
        while (op := self.take("*", "/")) is not None:
            rhs = self.unary()
            if op.text == "*":
                self.check_product(value, rhs, op)
                value = value * rhs
            elif rhs.is_zero():
                raise self.error("division by zero", op)
            else:
                value = value / rhs
        return value

    def unary(self) -> Frac:
        if (op := self.take("+", "-")) is not None:
            self.enter()
            value = self.unary()
            self.depth -= 1
            return -value if op.text == "-" else value
        return self.power()

    def power(self) -> Frac:
        base = self.atom()
        if (op := self.take("**", "^")) is None:
            return base
        self.enter()
        start = self.tok
        exponent = self.unary()
        self.depth -= 1
        if not exponent.is_constant():
            raise self.error("an exponent must be an integer constant, not a function of the variables", start)
        value = exponent.constant_value()
        if value.q != 1:
            raise self.error(f"an exponent must be an integer, not {value}", start)
        k = int(value.p)
        if base.is_zero() and k < 0:
            raise self.error("division by zero (0 to a negative power)", op)
        self.check_power(base, k, op)
        return base ** k

    def atom(self) -> Frac:
        tok = self.tok
        if tok.kind == "number":
            self.i += 1
            v = read_number(tok.text, self.limits)
            return Frac(self.ring, int(v.p), int(v.q))
        if tok.kind == "name":
            self.i += 1
            if self.tok.text == "(":
                raise self.error(f"function calls such as {tok.text}(...) are not allowed (only + - * / ** ^ of "
                                 "numbers and names)", tok)
            return self.name(tok)
        if self.take("("):
            self.enter()
            value = self.expr()
            self.depth -= 1
            if not self.take(")"):
                raise self.error(f"expected ')' to close the '(' at column {tok.pos}, found "
                                 f"{self.tok.text or 'the end'!r}")
            return value
        what = "the end of the formula" if tok.kind == "end" else repr(tok.text)
        raise self.error(f"expected a number, a name or '(', found {what}", tok)

    def name(self, tok: Token) -> Frac:
        if tok.text in self.known:
            return self.known[tok.text]
        if tok.text in self.ring.names and not tok.text.startswith("_"):
            return _generator(self.ring, tok.text)
        why = _WORDS.get(tok.text, "")
        names = [n for n in (*self.ring.names, *self.known) if not n.startswith("_")]
        raise UnknownSymbolError(
            f"cannot read {_excerpt(self.text, tok.pos)}: unknown name {tok.text!r} at column {tok.pos}"
            + (f" ({why})" if why else "") + f"; the names here are {names}")

    # ---- size guards ----------------------------------------------------------------------------
    def check_product(self, a: Frac, b: Frac, op: Token) -> None:
        for p, q in ((a.num, b.num), (a.den, b.den)):
            terms = len(p) * len(q)
            if terms > self.limits.terms:
                raise FormulaTooLargeError(f"the product at column {op.pos} could have {terms} terms; the limit is "
                                           f"{self.limits.terms}")
            bits = _norm_bits(p) + _norm_bits(q)
            self.check_size(terms, bits, f"the product at column {op.pos}")

    def check_power(self, base: Frac, k: int, op: Token) -> None:
        lim = self.limits
        if abs(k) > lim.exponent:
            raise FormulaTooLargeError(f"the exponent {k} at column {op.pos} exceeds the limit {lim.exponent}")
        for p in (base.num, base.den):
            bits = _norm_bits(p) * abs(k)
            if bits > lim.bits:
                raise FormulaTooLargeError(f"the power at column {op.pos} could have coefficients of about "
                                           f"{bits:.0f} bits; the limit is {lim.bits}")
            terms = _power_terms(p, abs(k)) if len(p) > 1 else 1
            if terms > lim.terms:
                raise FormulaTooLargeError(f"expanding the power at column {op.pos} could create more than "
                                           f"{lim.terms} terms; the limit is {lim.terms}")
            self.check_size(terms, bits, f"expanding the power at column {op.pos}")

    def check_size(self, terms: int, bits: float, what: str) -> None:
        """Refuse a result whose size, bounded before it is computed (terms times coefficient bits, and a word of
        exponents per term), exceeds `limits.megabytes`."""
        megabytes = terms * (bits + 64) / 8 / 2**20
        if megabytes > self.limits.megabytes:
            raise FormulaTooLargeError(f"{what} could take about {megabytes:,.0f} MB ({terms} terms of up to "
                                       f"{bits:.0f} bits); the limit is {self.limits.megabytes} MB")


def _norm_bits(p: flint.fmpz_mpoly) -> float:
    """log2 of the sum of |coefficients| of p: a coefficient of p**k has at most k times as many bits, one of p*q
    at most _norm_bits(p) + _norm_bits(q)."""
    norm = sum(abs(int(c)) for c in p.coeffs())
    return math.log2(norm) if norm > 1 else 0.0


def _power_terms(p: flint.fmpz_mpoly, k: int) -> int:
    """An upper bound on the terms of p**k: monomials of degree <= k deg p in its variables, and C(t+k-1, k)."""
    used = sum(1 for d in p.degrees() if d > 0)
    by_degree = math.comb(used + k * p.total_degree(), used)
    t = len(p)
    by_terms = math.comb(t + k - 1, k) if k < 10_000 or t == 1 else by_degree
    return min(by_degree, by_terms)


@lru_cache(maxsize=None)
def _generator(ring: Ring, name: str) -> Frac:
    return Frac(ring, ring.gen(name), reduced=True)


def parse_formula(ring: Ring, text: str, known: Mapping[str, Frac] | None = None,
                  limits: Limits = LIMITS) -> Frac:
    """The exact rational function written by `text` over `ring`; names in `known` stand for those functions.

    >>> r = get_ring(("x", "y"))
    >>> parse_formula(r, "(x**2 - y^2)/(x - y) + 0.5")
    (2*x + 2*y + 1)/(2)
    >>> parse_formula(r, "sin(x)")
    Traceback (most recent call last):
    hkproof.errors.ParseError: cannot read 'sin(x)': function calls such as sin(...) are not allowed (only + - * / ** ^ of numbers and names) at column 1
    """
    if not isinstance(text, str):
        raise ParseError(f"a formula must be text, not {type(text).__name__}")
    for name, value in (known or {}).items():
        if value.ring != ring:
            raise ParseError(f"the value of {name!r} lives in {value.ring}, not in {ring}")
    return _Parser(text, ring, known or {}, limits).parse()


_CONSTANTS = get_ring(("_",))


def parse_rational(text: str, limits: Limits = LIMITS) -> flint.fmpq:
    """An exact rational constant: '3', '-2/7', '0.1' (= 1/10), '1.5e-3', '(1 + 2)/3'; anything else is refused.

    >>> parse_rational("1.00000000000000001")
    100000000000000001/100000000000000000
    >>> parse_rational("2**-3")
    1/8
    """
    value = parse_formula(_CONSTANTS, text, None, limits)
    return value.constant_value()


def split_list(text: str, what: str = "list") -> list[str]:
    """The comma-separated items of `text` at bracket depth 0 ('a, (b, c)' has two items); empty items refused."""
    items, depth, start = [], 0, 0
    for i, ch in enumerate(text):
        if ch in "([":
            depth += 1
        elif ch in ")]":
            depth -= 1
            if depth < 0:
                raise ParseError(f"cannot read the {what} {_excerpt(text, i + 1)}: unmatched {ch!r} at column {i + 1}")
        elif ch == "," and depth == 0:
            items.append(text[start:i])
            start = i + 1
    if depth:
        raise ParseError(f"cannot read the {what} {_excerpt(text, len(text))}: a bracket is not closed")
    items.append(text[start:])
    items = [t.strip() for t in items]
    if any(not t for t in items):
        raise ParseError(f"cannot read the {what} {_excerpt(text, 1)}: an item is empty (two commas in a row, or a "
                         "comma at an end)")
    return items


def _unbracket(text: str, what: str) -> str:
    t = text.strip()
    if not (t.startswith("[") and t.endswith("]")):
        raise ParseError(f"the {what} {_excerpt(text, 1)} must be written in square brackets [...]")
    return t[1:-1]


def parse_matrix(ring: Ring, text: str, known: Mapping[str, Frac] | None = None) -> list[list[Frac]]:
    """A matrix written as rows '[[a, b], [c, d]]': every row of the same length, every entry a formula."""
    rows = [split_list(_unbracket(r, "row"), "row") for r in split_list(_unbracket(text, "matrix"), "matrix")]
    widths = {len(r) for r in rows}
    if len(widths) != 1:
        raise ParseError(f"the matrix {_excerpt(text, 1)} has rows of different lengths {[len(r) for r in rows]}")
    return [[Frac.parse(ring, e, known) for e in r] for r in rows]


STRUCTURE = "[],;="     # the separators of printed lists, matrices and relations 'lhs = rhs'


def rename(text: str, names: Mapping[str, str]) -> str:
    """The formula (or list, matrix, relation of formulas) with whole names replaced (by tokens, never inside a
    longer name): a cyclic shift of indices, or a name replaced by a parenthesized formula.

    >>> rename("x1*x12 + a1", {"x1": "x2", "a1": "(b + 1)"})
    'x2*x12 + (b + 1)'
    >>> rename("[[c1, c12], [c2 = 0]]", {"c1": "y"})
    '[[y, c12], [c2 = 0]]'
    """
    out: list[str] = []
    piece: list[str] = []
    for ch in text + STRUCTURE[0]:
        if ch in STRUCTURE:
            out.append(_rename_formula("".join(piece), names))
            out.append(ch)
            piece = []
        else:
            piece.append(ch)
    return "".join(out)[:-1]


def _rename_formula(text: str, names: Mapping[str, str]) -> str:
    out, last = [], 0
    for tok in tokens(text):
        if tok.kind == "name" and tok.text in names:
            out += [text[last:tok.pos - 1], names[tok.text]]
            last = tok.pos - 1 + len(tok.text)
    return "".join(out) + text[last:]


def cycled(text: str, names: Mapping[str, str], times: int = 1) -> str:
    """The formula with the renaming `names` (a cyclic shift of indices such as x1 -> x2 -> x3 -> x1, the paper's
    cyclic symmetry) applied `times` times.

    >>> cycled("a1*x2", {"a1": "a2", "a2": "a3", "a3": "a1", "x1": "x2", "x2": "x3", "x3": "x1"}, 2)
    'a3*x1'
    """
    for _ in range(times):
        text = rename(text, names)
    return text


def indexed(text: str, **indices: int) -> str:
    """A formula template with its index placeholders filled: with i=1, j=2 the names a_i, x_j, E_i become a1, x2, E1.

    >>> indexed("a_j*x_i**2 - a_i*x_j**2", i=1, j=3)
    'a3*x1**2 - a1*x3**2'
    """
    found = {t.text for t in tokens(text) if t.kind == "name"}
    mapping = {}
    for name in found:
        base, sep, index = name.rpartition("_")
        if sep and base and index in indices:
            mapping[name] = f"{base}{indices[index]}"
    return rename(text, mapping)
