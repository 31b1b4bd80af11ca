"""Kahan maps of quadratic fields: equations, explicit map, reversibility, iterates, orbits, and bad input."""
from __future__ import annotations

import pytest
import sympy

from hkproof.algebra import Frac
from hkproof.dynamics import QuadraticField, get_system, kahan_map
from hkproof.errors import NotQuadraticError, ParseError, SingularPointError, UnknownSymbolError, UnknownSystemError


@pytest.mark.parametrize("name", ["lotka-volterra", "euler-top", "clebsch", "clebsch-flow2"])
def test_map_solves_the_kahan_equations(name):
    f = kahan_map(name)
    t = f.field.tilde_ring
    nums = [p.project_to_context(t.ctx) for p in f.numerators]
    den = f.denominator.project_to_context(t.ctx)
    for e in f.equations:
        assert Frac(t, e).pullback(nums, den, f.field.tilde_variables).is_zero()


def test_kahan_scheme_against_sympy_for_a_users_field():
    field = QuadraticField("user", ("u", "v"), ("k",), ("k*u*v + v - 1", "u**2/3 - k*v"))
    f = kahan_map(field)
    u, v, ut, vt, eps, k = sympy.symbols("u v u_t v_t eps k")
    F = [k * u * v + v - 1, u**2 / 3 - k * v]
    x, xt = [u, v], [ut, vt]

    def polar(expr):  # 2 * symmetric bilinear form + linear parts, eq. "Kahan gen"
        mid = {u: (u + ut) / 2, v: (v + vt) / 2}
        return 4 * expr.subs(mid, simultaneous=True) - expr - expr.subs({u: ut, v: vt}, simultaneous=True)

    sol = sympy.solve([xt[i] - x[i] - eps * polar(F[i]) for i in range(2)], xt, dict=True)[0]
    for var, comp in zip(xt, f.components()):
        assert sympy.cancel(comp.to_sympy() - sol[var]) == 0


@pytest.mark.parametrize("name", ["lotka-volterra", "euler-top", "clebsch", "clebsch-general"])
def test_reversibility_of_the_equations(name):
    assert kahan_map(name).equations_reversible()


def test_reversibility_fails_for_a_non_kahan_scheme():
    f = kahan_map("lotka-volterra")
    t = f.field.tilde_ring
    broken = type(f)(f.field)
    broken.__dict__["equations"] = f.equations[:1] + (f.equations[1] + t.gen("x") * t.gen("eps") ** 2,)
    assert not broken.equations_reversible()


@pytest.mark.parametrize("name", ["lotka-volterra", "euler-top"])
def test_reversibility_by_composition(name):
    f = kahan_map(name)
    r = f.ring
    inv_nums, inv_den = f.inverse_explicit
    nums, den = f.explicit
    for k, v in enumerate(f.variables):
        assert Frac(r, inv_nums[k], inv_den).pullback(nums, den, f.variables) == Frac(r, r.gen(v))
    # the same sign of eps does not invert the map
    assert Frac(r, nums[0], den).pullback(nums, den, f.variables) != Frac(r, r.gen(f.variables[0]))


def test_iterates_agree_with_exact_orbits():
    f = kahan_map("euler-top")
    point = {"x1": 1, "x2": "1/2", "x3": "-2/3", "eps": "1/5", "a1": 2, "a2": -1, "a3": "3/7"}
    orbit = f.orbit_exact(point, 3)
    for k in (1, 2, 3):
        nums, den = f.iterate(k)
        for v, p in zip(f.variables, nums):
            assert Frac(f.ring, p, den).evaluate(point) == orbit[k][v]
    plain_nums, plain_den = f.iterate(2, reduced=False)
    assert Frac(f.ring, plain_nums[0], plain_den) == Frac(f.ring, f.iterate(2)[0][0], f.iterate(2)[1])


def test_singular_point_is_reported():
    f = kahan_map("lotka-volterra")
    # Delta = 1 - eps^2 - eps(1 - eps) x + eps(1 + eps) y vanishes at eps = 1/2, x = 3, y = 0
    with pytest.raises(SingularPointError, match="not defined"):
        f.step_exact({"x": 3, "y": 0, "eps": "1/2"})
    with pytest.raises(SingularPointError, match="step 1"):
        f.orbit_exact({"x": 3, "y": 0, "eps": "1/2"}, 5)


def test_bad_fields_are_refused():
    with pytest.raises(NotQuadraticError, match="degree 3"):
        QuadraticField("cubic", ("x", "y"), (), ("x**3", "y"))
    with pytest.raises(NotQuadraticError, match="not polynomial"):
        QuadraticField("rational", ("x", "y"), (), ("1/x", "y"))
    with pytest.raises(UnknownSymbolError):
        QuadraticField("typo", ("x", "y"), ("a",), ("a*x*y", "b*y"))
    with pytest.raises(ParseError, match="eps"):
        QuadraticField("eps", ("x",), (), ("eps*x",))
    with pytest.raises(ParseError):
        QuadraticField("count", ("x", "y"), (), ("x",))
    with pytest.raises(UnknownSystemError):
        get_system("no-such-system")


def test_toml_system(tmp_path):
    path = tmp_path / "sys.toml"
    path.write_text('name = "mine"\nvariables = ["u", "v"]\nparameters = ["k"]\n[rhs]\nu = "k*v"\nv = "-u*v"\n')
    field = get_system(str(path))
    assert field.name == "mine" and field.parameters == ("k",)
    bad = tmp_path / "bad.toml"
    bad.write_text('variables = ["u"]\n[rhs]\nw = "u"\n')
    with pytest.raises(ParseError, match="one right-hand side per variable"):
        get_system(str(bad))


def test_parameters_with_denominators():
    field = QuadraticField("rational-coefficients", ("x", "y"), ("a", "b"), ("x*y/(a - b)", "(a + b)/2*x**2"))
    f = kahan_map(field)
    point = {"x": 1, "y": 2, "eps": "1/3", "a": 3, "b": 1}
    step = f.step_exact(point)
    for v, comp in zip(f.variables, f.components()):
        assert comp.evaluate(point) == step[v]


def test_batch_mulmod_is_exact_near_the_largest_prime_and_silent():
    """mulmod against Python's integers on residues near p < 2^50 (the products wrap in int64), 1-d and 2-d arrays
    and a Python int against an array, with numpy warnings as errors (no errstate is entered)."""
    import random
    import warnings

    import numpy as np

    from hkproof.dynamics.batch_map import mulmod
    rng = random.Random(3)
    p = 2**50 - 27
    a = [rng.choice([p - 1 - rng.randrange(1000), rng.randrange(p)]) for _ in range(600)]
    b = [rng.choice([p - 1 - rng.randrange(1000), rng.randrange(p)]) for _ in range(600)]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        flat = mulmod(np.array(a, dtype=np.int64), np.array(b, dtype=np.int64), p)
        square = mulmod(np.array(a, dtype=np.int64).reshape(20, 30), np.array(b, dtype=np.int64).reshape(20, 30), p)
        scaled = mulmod(a[0], np.array(b, dtype=np.int64), p)
    assert [int(v) for v in flat] == [x * y % p for x, y in zip(a, b)]
    assert [int(v) for v in square.ravel()] == [x * y % p for x, y in zip(a, b)]
    assert [int(v) for v in scaled] == [a[0] * y % p for y in b]


def test_dotmod_and_mulmod_sum_against_python_integers():
    """Sums of products mod p < 2^50 with residues near p and p itself (which stands for 0): dotmod for 0 to 200
    products (chunks of 64), mulmod_sum for two pairs, 2-d arrays, with numpy warnings as errors."""
    import random
    import warnings

    import numpy as np

    from hkproof.dynamics.batch_map import dotmod, mulmod_sum
    rng = random.Random(7)
    p = 2**50 - 27

    def residue() -> int:
        return rng.choice([p, p - 1 - rng.randrange(1000), rng.randrange(p)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for m in (0, 1, 63, 64, 65, 200):
            a = np.array([[residue() for _ in range(m)] for _ in range(6)], dtype=np.int64).reshape(2, 3, m)
            b = np.array([[residue() for _ in range(m)] for _ in range(6)], dtype=np.int64).reshape(2, 3, m)
            got = dotmod(a, b, p)
            assert got.shape == (2, 3)
            assert [int(v) for v in got.ravel()] == [
                sum(int(x) * int(y) for x, y in zip(r, t)) % p for r, t in zip(a.reshape(6, m), b.reshape(6, m))]
        x = [np.array([residue() for _ in range(40)], dtype=np.int64).reshape(4, 10) for _ in range(4)]
        got = mulmod_sum(((x[0], x[1]), (x[2], x[3])), p)
    assert [int(v) for v in got.ravel()] == [(int(a) * int(b) + int(c) * int(d)) % p
                                             for a, b, c, d in zip(*(y.ravel() for y in x))]


def test_batch_solve_projective_satisfies_the_systems_and_flags_singular_ones():
    """A N = D b mod p on random batches of sizes 1..7 (checked with Python's integers), D != 0 where A is
    invertible mod p (flint's determinant), D = 0 on a batch member made singular (two equal rows)."""
    import random

    import flint
    import numpy as np

    from hkproof.dynamics.batch_map import solve_projective
    rng = random.Random(5)
    p = 2**50 - 27
    for n in range(1, 8):
        count = 6
        a = np.array([[[rng.randrange(p) for _ in range(n)] for _ in range(n)] for _ in range(count)], dtype=np.int64)
        b = np.array([[rng.randrange(p) for _ in range(n)] for _ in range(count)], dtype=np.int64)
        if n > 1:
            a[0, 1] = a[0, 0]
        nums, den = solve_projective(np.concatenate([a, b[:, :, None]], axis=2), p)
        for t in range(count):
            rows = [[int(v) for v in row] for row in a[t]]
            for i in range(n):
                assert sum(rows[i][k] * int(nums[t, k]) for k in range(n)) % p == int(den[t]) * int(b[t, i]) % p
            singular = int(flint.nmod_mat(rows, p).det()) == 0
            assert (int(den[t]) == 0) == singular     # no unlucky pivot at these random residues
        if n > 1:
            assert int(den[0]) == 0
