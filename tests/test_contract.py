"""One contract over every catalogue system and every implementation of its Kahan map (issue 39, item 4).

The implementations: the exact map (`KahanMap`: its equations, its explicit N/Delta, `step_exact`), the map mod p
(`KahanMap.mod`, `dynamics/modular_map.py`: step, orbit, tangent map, explicit map mod p), the batch map
(`dynamics/batch_map.py`: numpy int64 residues below 2^50, projective, division-free) and the orbits of the four
arithmetics of algorithm (N) (`experiments/`: exact Q, mod p, float64, mpmath). At a seeded random rational point x,
eps (any sign) and parameters of each system:

(a) the exact step x~ solves the Kahan equations x~ - x = 2 eps F^(x, x~), built here with sympy from the field's
    printed right-hand sides (the polarization F^(x, y) = 2 F((x + y)/2) - (F(x) + F(y))/2), and the equations
    `KahanMap.equations` expose vanish at (x, x~); N(x)/Delta(x) = x~;
(b) the map mod p (a random 62-bit prime dividing no denominator) at the residues of x agrees with the residues of
    the exact step, of a two-step exact orbit, of the explicit map, and its tangent map with the Jacobian of N/Delta;
(c) the batch map mod a 50-bit prime agrees with the exact map on a batch of points with different eps and
    parameters (two steps, projectively), and reports D = 0 exactly where the map mod p is singular; the orbits of
    the four arithmetics of algorithm (N) agree with the exact orbit (exactly over Q and mod p; float64 and mpmath
    to a relative tolerance set by their own error estimate);
(d) f(f(x, eps), -eps) = x exactly (step, explicit inverse N(-eps)/Delta(-eps), and mod p);
(e) the four arithmetics give one rank profile for one small candidate basis per system (all monomials of degree
    <= 2 for at most three variables, the squares and 1 above), float64 and mpmath allowed to say "ambiguous" but
    never another rank, and each of them decided at some seeded draw.

`test_the_contract_catches_a_fault` shows that each check fails on a perturbed implementation (a wrong sign of eps,
a changed coefficient, explicit Euler instead of Kahan, a float64 product in the batch map, single precision, a
transposed tangent map, ...).
"""
from __future__ import annotations

import random
from contextlib import nullcontext
from dataclasses import dataclass, field as dataclass_field, replace
from functools import cached_property
from itertools import combinations_with_replacement
from typing import Callable, Mapping, Sequence

import flint
import mpmath
import numpy as np
import pytest
import sympy

from hkproof.algebra.modular import random_prime, residue, residue_or_none
from hkproof.algebra.sampling import random_rational, random_rationals
from hkproof.dynamics import batch_map
from hkproof.dynamics.batch_map import BatchKahanMap
from hkproof.dynamics.catalogue import SYSTEMS, kahan_map
from hkproof.dynamics.field import EPS, QuadraticField
from hkproof.dynamics.kahan import KahanMap
from hkproof.dynamics.modular_map import ModularKahanMap
from hkproof.errors import ParseError, SingularPointError, UnluckyPrimeError
from hkproof.experiments.approximate import Approximate, Float64, MPMath
from hkproof.experiments.arithmetics import Arithmetic, ExactQ, FieldArithmetic
from hkproof.experiments.choice import get_arithmetic
from hkproof.experiments.profiles_mod_p import ModP
from hkproof.experiments.profiles import AMBIGUOUS, HK_BASIS, NO_BASIS, SINGULAR, KernelProfile, ProfileProblem, \
    parse_basis
from hkproof.experiments.scene import Scene, make_scene

from tests.sympy_bridge import value_at

NAMES = list(SYSTEMS)
BIG_EXPLICIT = 20_000        # terms of N and Delta above which the explicit map mod p is reduced only under -m slow
ARITHMETIC_DRAWS = 12        # seeded draws in which float64 and mpmath must each decide the ranks once


# ---- the independent oracle: Kahan's equations from the printed field, with sympy ----------------------------
class Oracle:
    """The field's right-hand sides read by sympy (not by hkproof's parser), and Kahan's scheme built from them."""

    def __init__(self, field: QuadraticField):
        self.field = field
        self.symbols = {n: sympy.Symbol(n) for n in field.variables + field.parameters}
        self.rhs = [sympy.sympify(t, locals=self.symbols) for t in field.rhs_text]

    def at(self, x: Sequence[sympy.Rational], params: Mapping[str, sympy.Rational]) -> list[sympy.Expr]:
        """F(x) at rational values."""
        subs = {self.symbols[v]: q for v, q in zip(self.field.variables, x, strict=True)}
        subs.update({self.symbols[k]: v for k, v in params.items()})
        return [F.subs(subs, simultaneous=True) for F in self.rhs]

    def residuals(self, x: Sequence[flint.fmpq], xt: Sequence[flint.fmpq],
                  values: Mapping[str, flint.fmpq]) -> list[sympy.Expr]:
        """x~ - x - 2 eps F^(x, x~) with F^(x, y) = 2 F((x + y)/2) - (F(x) + F(y))/2 (zero for Kahan's step)."""
        params = {k: _sym(v) for k, v in values.items() if k != EPS}
        eps = _sym(values[EPS])
        a, b = [_sym(v) for v in x], [_sym(v) for v in xt]
        mid = self.at([(u + w) / 2 for u, w in zip(a, b, strict=True)], params)
        fa, fb = self.at(a, params), self.at(b, params)
        return [w - u - 2 * eps * (2 * m - (p + q) / 2) for u, w, m, p, q in zip(a, b, mid, fa, fb, strict=True)]


def _sym(q: flint.fmpq) -> sympy.Rational:
    return sympy.Rational(int(q.p), int(q.q))


# ---- seeded draws ---------------------------------------------------------------------------------------------
@dataclass
class Draw:
    """eps and the parameters, a point x, and the reference exact orbit x, x~ = f(x), f(x~) of the catalogue map."""

    values: dict[str, flint.fmpq]
    x: list[flint.fmpq]
    xt: list[flint.fmpq]
    x2: list[flint.fmpq]

    variables: tuple[str, ...] = dataclass_field(default=(), repr=False)

    def point(self, x: Sequence[flint.fmpq] | None = None) -> dict[str, flint.fmpq]:
        """Every ring name's value: eps, the parameters and the phase variables (x by default)."""
        return {**self.values, **dict(zip(self.variables, self.x if x is None else x, strict=True))}

    def flipped(self) -> dict[str, flint.fmpq]:
        """The values with eps negated."""
        return {**self.values, EPS: -self.values[EPS]}


def _value(kmap: KahanMap, p: flint.fmpz_mpoly, point: Mapping[str, flint.fmpq]) -> flint.fmpq:
    return kmap.ring.to_q(p)(*[point[n] for n in kmap.ring.names])


def draw(kmap: KahanMap, rng: random.Random, *, size: int = 9) -> Draw:
    """Random rational eps (either sign) and parameters off the poles of the coefficients, and a random x with
    Delta(x) != 0 whose orbit f(x), f(f(x)) and f(x, -eps) back step are defined: drawn again until so."""
    field = kmap.field
    _, delta = kmap.explicit
    for _ in range(200):
        values = {EPS: random_rational(rng, size)} | {p: random_rational(rng, size) for p in field.parameters}
        try:
            field.check_values(values)
        except ParseError:
            continue
        x = random_rationals(rng, len(field.variables), size)
        d = Draw(values, x, [], [], field.variables)
        if _value(kmap, delta, d.point()) == 0:
            continue
        try:
            step = kmap.step_exact(d.point())
            xt = [step[v] for v in field.variables]
            step2 = kmap.step_exact(d.point(xt))
            kmap.step_exact({**d.point(xt), EPS: -values[EPS]})
        except SingularPointError:
            continue
        return Draw(values, x, xt, [step2[v] for v in field.variables], field.variables)
    raise AssertionError(f"no regular random point of {field.name} in 200 draws")


def det_m(kmap: KahanMap, point: Mapping[str, flint.fmpq]) -> flint.fmpq:
    m, _ = kmap.matrix
    return flint.fmpq_mat([[_value(kmap, e, point) for e in row] for row in m]).det()


def good_prime(kmap: KahanMap, draws: Sequence[Draw], rng: random.Random, bits: int) -> int:
    """A random prime of `bits` bits dividing no denominator of the draws' values and orbits, and no det M on them."""
    numbers = [v for d in draws for v in (*d.values.values(), *d.x, *d.xt, *d.x2)]
    dets = [det_m(kmap, pt) for d in draws for pt in (d.point(), d.point(d.xt), {**d.point(d.xt), EPS: -d.values[EPS]})]
    while True:
        p = random_prime(rng, bits)
        if all(residue_or_none(q, p) is not None for q in numbers + dets) and all(int(q.p) % p for q in dets):
            return p


def residues(values: Sequence[flint.fmpq], p: int) -> list[int]:
    return [residue(v, p) for v in values]


@dataclass
class Case:
    """One system's reference map, its oracle, its seeded draws and primes."""

    name: str
    kmap: KahanMap
    oracle: Oracle
    draws: list[Draw]
    p: int                  # a 62-bit prime for the map mod p
    q: int                  # a 50-bit prime for the batch map

    @property
    def draw(self) -> Draw:
        return self.draws[0]


_CASES: dict[str, Case] = {}


def case(name: str) -> Case:
    """The seeded draws of a system, made once per test run (the seed is the system's name)."""
    if name not in _CASES:
        kmap = kahan_map(name)
        rng = random.Random(f"contract:{name}")
        draws = [draw(kmap, rng) for _ in range(3)]
        _CASES[name] = Case(name, kmap, Oracle(kmap.field), draws, good_prime(kmap, draws, rng, 62),
                            good_prime(kmap, draws, rng, 50))
    return _CASES[name]


# ---- (a) the exact step solves the Kahan equations ------------------------------------------------------------
def check_exact_step(oracle: Oracle, kmap: KahanMap, d: Draw) -> None:
    """kmap's step at d's point solves the oracle's Kahan equations and kmap's own; N/Delta gives the same step."""
    step = kmap.step_exact(d.point())
    xt = [step[v] for v in kmap.variables]
    bad = [r for r in oracle.residuals(d.x, xt, d.values) if r != 0]
    assert not bad, f"{kmap}: the exact step misses the Kahan equations built from the field by {bad}"
    at = {**d.point(), **{w: v for w, v in zip(kmap.field.tilde_variables, xt, strict=True)}}
    names = kmap.field.tilde_ring.names
    exposed = [value_at(e, names, at) for e in kmap.equations]
    assert all(v == 0 for v in exposed), f"{kmap}: KahanMap.equations do not vanish at (x, x~): {exposed}"
    nums, delta = kmap.explicit
    den = _value(kmap, delta, d.point())
    assert den != 0, f"{kmap}: Delta(x) = 0 at a point where the step is defined"
    explicit = [_value(kmap, n, d.point()) / den for n in nums]
    assert explicit == xt, f"{kmap}: N(x)/Delta(x) = {explicit} but the step gives {xt}"


# ---- (b) the map mod p ----------------------------------------------------------------------------------------
ModularFactory = Callable[[KahanMap, int, Mapping[str, flint.fmpq]], ModularKahanMap]


def _mod(kmap: KahanMap, p: int, values: Mapping[str, flint.fmpq]) -> ModularKahanMap:
    return kmap.mod(p, values)


def exact_jacobian(kmap: KahanMap, point: Mapping[str, flint.fmpq]) -> list[list[flint.fmpq]]:
    """D(N/Delta) at a rational point, from the derivatives of the explicit map."""
    nums, delta = kmap.explicit
    r = kmap.ring
    den = _value(kmap, delta, point)
    out = []
    for n in nums:
        value = _value(kmap, n, point)
        out.append([(_value(kmap, n.derivative(r.index(v)), point) * den
                     - value * _value(kmap, delta.derivative(r.index(v)), point)) / den ** 2 for v in kmap.variables])
    return out


def check_modular(kmap: KahanMap, d: Draw, p: int, *, modular: ModularFactory = _mod, explicit: bool = True) -> None:
    """The map mod p at the residues of x: one step, a two-step orbit and the tangent map agree with the exact map
    reduced mod p; with `explicit`, N/Delta mod p and its homogenization too."""
    m = modular(kmap, p, d.values)
    x, xt, x2 = residues(d.x, p), residues(d.xt, p), residues(d.x2, p)
    assert m.step(x) == xt, f"{m}: step {m.step(x)} != exact step mod p {xt}"
    assert m.orbit(x, 2) == [x, xt, x2], f"{m}: the orbit mod p differs from the exact orbit mod p"
    points, jacobians = m.tangent_orbit(x, 1)
    assert points == [x, xt], f"{m}: tangent_orbit's points differ from the exact orbit mod p"
    jac = [residues(row, p) for row in exact_jacobian(kmap, d.point())]
    got = [[int(jacobians[1][i, j]) for j in range(m.n)] for i in range(m.n)]
    assert got == jac, f"{m}: the tangent map mod p is not the Jacobian of N/Delta mod p"
    if explicit:
        assert m.evaluate(x) == xt, f"{m}: N/Delta mod p gives {m.evaluate(x)}, the exact step {xt}"
        polys, degree = m.homogenized()
        for w in (1, 5):
            at = [v * w % p for v in x] + [w]
            vals = [int(h(*at)) for h in polys]
            assert vals[-1] != 0 and [v * pow(vals[-1], -1, p) % p for v in vals[:-1]] == xt, \
                f"{m}: the homogenized map (degree {degree}) at (w x, w) differs from the exact step"


# ---- (c) the batch map and the orbits of the arithmetics -------------------------------------------------------
BatchFactory = Callable[[KahanMap, int], BatchKahanMap]


def singular_residues(kmap: KahanMap, values: Mapping[str, flint.fmpq], p: int, rng: random.Random) -> list[int]:
    """Residues x with det M(x, eps) = 0 mod p: a root of det M along a random line (det M from kmap.matrix
    reduced here, not from the modular map), found by Lagrange interpolation and nmod_poly.roots."""
    m, _ = kmap.matrix
    names = kmap.ring.names
    n = len(kmap.variables)
    fixed = {k: residue(v, p) for k, v in values.items()}

    def det_at(x: Sequence[int]) -> int:
        args = [fixed.get(name, 0) for name in names]
        for v, r in zip(kmap.variables, x, strict=True):
            args[names.index(v)] = r
        return int(flint.nmod_mat([[int(e(*args)) % p for e in row] for row in m], p).det())

    for _ in range(50):
        x0 = [rng.randrange(p) for _ in range(n)]
        direction = [rng.randrange(p) for _ in range(n)]
        ts = list(range(n + 1))                 # det M has degree <= n in x: n + 1 values fix it on the line
        ys = [det_at([(a + t * b) % p for a, b in zip(x0, direction, strict=True)]) for t in ts]
        poly = flint.nmod_poly([0], p)
        for i, (ti, yi) in enumerate(zip(ts, ys, strict=True)):
            basis = flint.nmod_poly([yi], p)
            for j, tj in enumerate(ts):
                if j != i:
                    basis *= flint.nmod_poly([-tj, 1], p) * pow(ti - tj, -1, p)
            poly += basis
        if poly.degree() < 1:
            continue
        roots = poly.roots()
        if roots:
            t = int(roots[0][0])
            return [(a + t * b) % p for a, b in zip(x0, direction, strict=True)]
    raise AssertionError(f"det M of {kmap} has no root mod {p} on 50 random lines")


def check_batch(kmap: KahanMap, draws: Sequence[Draw], q: int, singular: Sequence[int], *,
                batch: BatchFactory = BatchKahanMap) -> None:
    """The batch map mod q on the draws (each its own eps and parameters) and on a point where det M = 0 mod q
    with the first draw's values: two steps agree with the exact orbit mod q, D = 0 exactly at the singular point,
    where the map mod q refuses to step too."""
    bm = batch(kmap, q)
    rows = [{**{k: residue(v, q) for k, v in d.values.items()}, **dict(zip(kmap.variables, residues(d.x, q)))}
            for d in draws]
    rows.append({**rows[0], **dict(zip(kmap.variables, singular))})
    values = {name: np.array([r[name] for r in rows], dtype=np.int64) for name in kmap.ring.names}
    orbit = bm.orbit(values, 2)
    for k, (xs, w) in enumerate(orbit):
        for i, d in enumerate(draws):
            assert int(w[i]) != 0, f"batch map of {kmap}: W = 0 at step {k} of a regular point"
            got = [int(x[i]) * pow(int(w[i]), -1, q) % q for x in xs]
            want = residues((d.x, d.xt, d.x2)[k], q)
            assert got == want, f"batch map of {kmap} mod {q}: step {k} of point {i} gives {got}, exact {want}"
    assert int(orbit[1][1][-1]) == 0, f"batch map of {kmap}: D != 0 where det M(x) = 0 mod {q}"
    with pytest.raises(UnluckyPrimeError):
        kmap.mod(q, draws[0].values).step(list(singular))


def orbit_tolerance(arithmetic: Approximate, prep, orbit) -> list[float]:
    """Relative tolerances of an approximate orbit: 16 times the arithmetic's own first-order error estimate."""
    errors, _ = arithmetic.orbit_errors(prep, orbit)
    return [16 * float(e) + 4 * float(arithmetic.u) for e in errors]


def check_arithmetic_orbit(kmap: KahanMap, d: Draw, arithmetic: FieldArithmetic) -> None:
    """The arithmetic's own two-step orbit (the loop of algorithm (N)) against the exact orbit: equal over Q,
    equal mod p for ModP, within the arithmetic's own error estimate for float64 and mpmath."""
    with mpmath.workdps(arithmetic.dps) if isinstance(arithmetic, MPMath) else nullcontext():
        _check_arithmetic_orbit(kmap, d, arithmetic)


def _check_arithmetic_orbit(kmap: KahanMap, d: Draw, arithmetic: FieldArithmetic) -> None:
    scene = make_scene(kmap, d.values)
    prep = arithmetic.prepare(scene, [])
    orbit = arithmetic.orbit(prep, d.x, 2)
    exact = [d.x, d.xt, d.x2]
    if isinstance(arithmetic, ExactQ):
        assert orbit == exact, f"{arithmetic.name} orbit of {kmap} differs from the exact orbit"
    elif isinstance(arithmetic, ModP):
        assert orbit == [residues(x, arithmetic.p) for x in exact], f"{arithmetic.name} orbit of {kmap} differs"
    else:
        assert isinstance(arithmetic, Approximate)
        tolerance = orbit_tolerance(arithmetic, prep, orbit)
        for k, (got, want, tol) in enumerate(zip(orbit, exact, tolerance, strict=True)):
            err = arithmetic.norm([g - arithmetic.number(w) for g, w in zip(got, want, strict=True)])
            size = arithmetic.norm([arithmetic.number(w) for w in want])
            assert err <= tol * size, (f"{arithmetic.name} orbit of {kmap}: step {k} off by {float(err / size):.3g} "
                                       f"(relative), tolerance {tol:.3g}")


# ---- (d) reversibility ----------------------------------------------------------------------------------------
def check_reversible(kmap: KahanMap, d: Draw, p: int, *, modular: ModularFactory = _mod) -> None:
    """f(f(x, eps), -eps) = x exactly: by two steps, by N(-eps)/Delta(-eps) at x~, and mod p; the equations'
    symmetry E(x~, x, -eps) = -E(x, x~, eps)."""
    forward = kmap.step_exact(d.point())
    xt = [forward[v] for v in kmap.variables]
    back = kmap.step_exact({**d.point(xt), EPS: -d.values[EPS]})
    assert [back[v] for v in kmap.variables] == d.x, f"{kmap}: f(f(x, eps), -eps) = {back} != x = {d.x}"
    nums, delta = kmap.inverse_explicit
    at = d.point(xt)
    den = _value(kmap, delta, at)
    assert den != 0 and [_value(kmap, n, at) / den for n in nums] == d.x, \
        f"{kmap}: N(x~, -eps)/Delta(x~, -eps) != x"
    m_fwd, m_back = modular(kmap, p, d.values), modular(kmap, p, d.flipped())
    x = residues(d.x, p)
    assert m_back.step(m_fwd.step(x)) == x, f"{kmap}: f(f(x, eps), -eps) != x mod {p}"
    assert kmap.equations_reversible(), f"{kmap}: E(x~, x, -eps) != -E(x, x~, eps)"


# ---- (e) the four arithmetics give one rank -------------------------------------------------------------------
def candidate_basis(kmap: KahanMap) -> list[str]:
    """All monomials of degree <= 2 for at most three variables; the squares of the variables and 1 above (the
    exact orbit of a 28-function basis of a six-variable map takes minutes)."""
    v = kmap.variables
    if len(v) <= 3:
        return [f"{a}*{b}" for a, b in combinations_with_replacement(v, 2)] + list(v) + ["1"]
    return [f"{a}**2" for a in v] + ["1"]


def four_arithmetics(p: int) -> dict[str, Arithmetic]:
    """The arithmetics of `hkproof scan --arithmetic` by name, the modular one seeded."""
    return {name: get_arithmetic(name, digits=50, seed=p % 1000) for name in ("exact", "modular", "float", "mpmath")}


def check_ranks(kmap: KahanMap, basis: Sequence[str], draws: Sequence[Draw],
                arithmetics: Mapping[str, Arithmetic]) -> KernelProfile:
    """Rank profiles of the basis at each draw (its own eps and parameters) in every arithmetic: exact and modular
    always decided and equal; float64 and mpmath equal to them wherever they decide; every arithmetic decided
    everywhere at one draw at least. Returns the exact profile of that draw."""
    for d in draws:
        problem = ProfileProblem(make_scene(kmap, d.values), parse_basis(kmap.ring, list(basis)))
        profiles = {name: problem.profile(d.x, ar, with_kernel=False) for name, ar in arithmetics.items()}
        exact = profiles["exact"]
        if exact.verdict == SINGULAR:
            continue
        for name, prof in profiles.items():
            assert prof.verdict != SINGULAR, f"{name} says the orbit of {kmap} is singular, exact does not"
            decided = [(a, b) for a, b in zip(prof.dims, exact.dims, strict=True) if a is not None]
            assert all(a == b for a, b in decided), f"{name} dims {prof.dims} != exact dims {exact.dims} ({kmap})"
            if name in ("exact", "modular"):
                assert None not in prof.dims, f"{name} left a rank undecided: {prof.dims}"
        if all(prof.verdict != AMBIGUOUS for prof in profiles.values()):
            return exact
    raise AssertionError(f"{kmap}: in {len(draws)} draws float64 and mpmath never both decided the ranks of {basis}")


# ---- the contract, one test id per system ----------------------------------------------------------------------
@pytest.mark.parametrize("name", NAMES)
def test_exact_step_solves_the_kahan_equations(name):
    c = case(name)
    for d in c.draws:
        check_exact_step(c.oracle, c.kmap, d)


@pytest.mark.parametrize("name", NAMES)
def test_modular_map_agrees_with_the_exact_map(name):
    c = case(name)
    nums, delta = c.kmap.explicit
    check_modular(c.kmap, c.draw, c.p, explicit=sum(len(n) for n in nums) + len(delta) <= BIG_EXPLICIT)


@pytest.mark.slow
@pytest.mark.parametrize("name", [n for n in NAMES if sum(len(q) for q in kahan_map(n).numerators)
                                  + len(kahan_map(n).denominator) > BIG_EXPLICIT])
def test_big_explicit_maps_mod_p(name):
    """The explicit map mod p of the systems whose N and Delta have many terms (seconds of reduction each)."""
    c = case(name)
    check_modular(c.kmap, c.draw, c.p, explicit=True)


@pytest.mark.parametrize("name", NAMES)
def test_batch_map_agrees_with_the_exact_map(name):
    c = case(name)
    singular = singular_residues(c.kmap, c.draw.values, c.q, random.Random(f"singular:{name}"))
    check_batch(c.kmap, c.draws, c.q, singular)


@pytest.mark.parametrize("name", NAMES)
def test_arithmetic_orbits_agree_with_the_exact_map(name):
    c = case(name)
    for arithmetic in (ExactQ(), ModP(c.p), Float64(), MPMath(50)):
        check_arithmetic_orbit(c.kmap, c.draw, arithmetic)


@pytest.mark.parametrize("name", NAMES)
def test_reversibility(name):
    c = case(name)
    check_reversible(c.kmap, c.draw, c.p)


@pytest.mark.parametrize("name", NAMES)
def test_four_arithmetics_give_one_rank(name):
    c = case(name)
    rng = random.Random(f"ranks:{name}")
    draws = [draw(c.kmap, rng, size=5) for _ in range(ARITHMETIC_DRAWS)]
    exact = check_ranks(c.kmap, candidate_basis(c.kmap), draws, four_arithmetics(c.p))
    assert exact.verdict in (HK_BASIS, NO_BASIS), f"a generic point of {name} gives irregular ranks {exact.dims}"


def test_every_system_and_implementation_is_covered():
    """The contract runs over the whole catalogue, and the implementations it names are the package's."""
    assert NAMES == list(SYSTEMS) and len(NAMES) >= 18
    assert type(kahan_map(NAMES[0]).mod(101, {EPS: 1})) is ModularKahanMap
    assert {type(a).__name__ for a in four_arithmetics(101).values()} == {"ExactQ", "Modular", "Float64", "MPMath"}


# ---- faults the contract catches --------------------------------------------------------------------------------
def changed_coefficient(field: QuadraticField) -> QuadraticField:
    """The field with its first component changed by x1/7: another (non-integrable) field, same names."""
    rhs = (f"{field.rhs_text[0]} + {field.variables[0]}/7",) + field.rhs_text[1:]
    return QuadraticField(field.name + "-changed", field.variables, field.parameters, rhs)


class WrongEpsSign(KahanMap):
    """step_exact with eps negated: the inverse map."""

    def step_exact(self, point):
        return super().step_exact({**point, EPS: -flint.fmpq(point[EPS])})


class ExplicitEuler(KahanMap):
    """x~ = x + 2 eps F(x): a consistent scheme, but neither Kahan's nor reversible."""

    def step_exact(self, point):
        values = {n: flint.fmpq(point[n]) for n in self.ring.names}
        return {v: values[v] + 2 * values[EPS] * f.evaluate(values) for v, f in zip(self.variables, self.field.rhs)}


class PerturbedExplicit(KahanMap):
    """N_1 replaced by N_1 + Delta in the explicit map (the matrix form, hence step_exact, untouched)."""

    @cached_property
    def explicit(self):
        nums, delta = KahanMap.explicit.func(self)
        return (nums[0] + delta,) + nums[1:], delta


class InverseSameEps(KahanMap):
    """The explicit inverse without the sign change of eps."""

    @property
    def inverse_explicit(self):
        return self.explicit


def perturbed_equations(field: QuadraticField) -> KahanMap:
    """A map whose exposed equations E_1 gain eps x1 after its matrix form (hence its step) was built."""
    kmap = KahanMap(field)
    first, t = kmap.equations[0], field.tilde_ring
    assert kmap.matrix
    kmap.__dict__["equations"] = (first + t.gen(EPS) * t.gen(field.variables[0]),) + kmap.equations[1:]
    return kmap


class GuessingBatch(BatchKahanMap):
    """A batch map that hides D = 0 (a singular point) behind D = 1."""

    def step(self, point, coefficients):
        xs, den = super().step(point, coefficients)
        return xs, np.where(den == 0, 1, den)


class MPMathFromFloats(MPMath):
    """mpmath at 50 digits fed with float64 constants and points."""

    def number(self, q):
        return mpmath.mpf(float(q))


class WrongTangent(ModularKahanMap):
    def tangent_orbit(self, x, steps):
        points, jacobians = super().tangent_orbit(x, steps)
        return points, [j.transpose() for j in jacobians]


class WrongExplicit(ModularKahanMap):
    def evaluate(self, x):
        out = super().evaluate(x)
        return None if out is None else [(out[0] + 1) % self.p] + out[1:]


def float_mulmod_sum(products, p):
    """sum a_i * b_i mod p in float64 alone: exact only while products stay below 2^53."""
    total = sum(np.asarray(a, dtype=float) * np.asarray(b, dtype=float) for a, b in products)
    return np.fmod(total, float(p)).astype(np.int64)


class SinglePrecision(Float64):
    """float64's algorithm (N) with its constants and points rounded to float32."""

    def number(self, q):
        return float(np.float32(float(q)))


class ChangedScene(Float64):
    """float64's algorithm (N) on a scene whose first right-hand side b_1(x) has a changed linear coefficient."""

    def prepare(self, scene: Scene, basis):
        const, lin = scene.rhs[0]
        lin = tuple((k, c * flint.fmpq(8, 7) if k == 0 else c) for k, c in lin)
        return super().prepare(replace(scene, rhs=((const, lin),) + scene.rhs[1:]), basis)


FAULTS = {
    "exact-step-eps-sign": "a",
    "exact-map-changed-coefficient": "a",
    "exact-equations-changed": "a",
    "exact-explicit-changed": "a",
    "modular-eps-sign": "b",
    "modular-tangent-transposed": "b",
    "modular-explicit-off-by-one": "b",
    "batch-mulmod-in-float64": "c",
    "batch-hides-singular-point": "c",
    "float-arithmetic-in-float32": "c",
    "mpmath-from-float64": "c",
    "not-reversible-euler": "d",
    "explicit-inverse-same-eps": "d",
    "modular-inverse-same-eps": "d",
    "float-arithmetic-changed-coefficient": "e",
}


@pytest.mark.parametrize("fault", FAULTS)
def test_the_contract_catches_a_fault(fault, monkeypatch):
    """Each check passes on the package's implementation and fails on a perturbed one (euler-top: three
    parameters, a two-dimensional kernel of its degree-2 basis)."""
    c = case("euler-top")
    kmap, d, p = c.kmap, c.draw, c.p

    def flip(k, q, values):
        return k.mod(q, {**values, EPS: -flint.fmpq(values[EPS])})

    def batch(fake: BatchFactory = BatchKahanMap) -> None:
        check_batch(kmap, c.draws, c.q, singular_residues(kmap, d.values, c.q, random.Random(1)), batch=fake)

    checks: dict[str, tuple[Callable[[], None], Callable[[], None]]] = {
        "exact-step-eps-sign": (lambda: check_exact_step(c.oracle, kmap, d),
                                lambda: check_exact_step(c.oracle, WrongEpsSign(kmap.field), d)),
        "exact-map-changed-coefficient": (
            lambda: check_exact_step(c.oracle, kmap, d),
            lambda: check_exact_step(c.oracle, KahanMap(changed_coefficient(kmap.field)), d)),
        "exact-equations-changed": (lambda: check_exact_step(c.oracle, kmap, d),
                                    lambda: check_exact_step(c.oracle, perturbed_equations(kmap.field), d)),
        "exact-explicit-changed": (lambda: check_exact_step(c.oracle, kmap, d),
                                   lambda: check_exact_step(c.oracle, PerturbedExplicit(kmap.field), d)),
        "modular-eps-sign": (lambda: check_modular(kmap, d, p), lambda: check_modular(kmap, d, p, modular=flip)),
        "modular-tangent-transposed": (
            lambda: check_modular(kmap, d, p),
            lambda: check_modular(kmap, d, p, modular=lambda k, q, v: WrongTangent(k, v, q))),
        "modular-explicit-off-by-one": (
            lambda: check_modular(kmap, d, p),
            lambda: check_modular(kmap, d, p, modular=lambda k, q, v: WrongExplicit(k, v, q))),
        "batch-mulmod-in-float64": (batch, lambda: (monkeypatch.setattr(batch_map, "mulmod_sum", float_mulmod_sum),
                                                    batch())),
        "batch-hides-singular-point": (batch, lambda: batch(GuessingBatch)),
        "float-arithmetic-in-float32": (lambda: check_arithmetic_orbit(kmap, d, Float64()),
                                        lambda: check_arithmetic_orbit(kmap, d, SinglePrecision())),
        "mpmath-from-float64": (lambda: check_arithmetic_orbit(kmap, d, MPMath(50)),
                                lambda: check_arithmetic_orbit(kmap, d, MPMathFromFloats(50))),
        "not-reversible-euler": (lambda: check_reversible(kmap, d, p),
                                 lambda: check_reversible(ExplicitEuler(kmap.field), d, p)),
        "explicit-inverse-same-eps": (lambda: check_reversible(kmap, d, p),
                                      lambda: check_reversible(InverseSameEps(kmap.field), d, p)),
        "modular-inverse-same-eps": (
            lambda: check_reversible(kmap, d, p),
            lambda: check_reversible(kmap, d, p, modular=lambda k, q, v: k.mod(q, {**v, EPS: abs(v[EPS])}))),
        "float-arithmetic-changed-coefficient": (
            lambda: check_ranks(kmap, candidate_basis(kmap), [d], {**four_arithmetics(p), "float": Float64()}),
            lambda: check_ranks(kmap, candidate_basis(kmap), [d], {**four_arithmetics(p), "float": ChangedScene()})),
    }
    good, bad = checks[fault]
    good()
    with pytest.raises(AssertionError):
        bad()
