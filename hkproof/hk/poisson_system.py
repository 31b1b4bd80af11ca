"""The linear system of invariant bivectors Pi = Q / D mod p, split by the map's sign symmetries (docs/poisson.md).

With D fixed, Pi(f(x)) = Df Pi(x) Df^T is linear in the coefficients of Q:  Q(f(x)) D(x) = D(f(x)) Df Q(x) Df^T.
A point x mod p gives n(n-1)/2 rows (the entries i < j), from f(x) and Df(x) of the modular map (tangent_orbit).

Exclusion (issue 38, item 4): the rows at integer points are rational functions of eps and the parameters; if an
invariant Q != 0 existed over Q(eps, params), every maximal minor would vanish identically, hence also at a
specialization where the denominators (powers of Delta(x_k)) are units mod p. Full column rank mod p at one
specialization therefore proves that the class has no invariant bivector.

Symmetries: a diagonal sign change S of the phase variables with f(Sx) = S f(x) (parameters fixed), and S = -I when
E(-x, -x~, -eps) = -E(x, x~, eps) and the map is reversible (then Pi(x) -> Pi(-x) maps invariant bivectors to
invariant ones, the composition of Pi(x; eps) -> Pi(x; -eps) and Pi -> (-I)_* Pi(.; -eps)), act linearly on the
invariant bivectors when D(Sx) = +-D(x): the column (ij, x^m) has the character s_i s_j S^m, so the space of invariant
bivectors is the direct sum of its parts on the columns of each character, and each part is searched (or excluded)
on its own columns: 2^k blocks of about 1/2^k of the columns.

Torus: with eigen-coordinates y = T x mod p of a linear symmetry A of the field (hkproof.hk.torus), the columns are
(ij, y^m) and their weight sum_c m_c l_c - l_i - l_j mod p is one more entry of the character; the rows are the same
invariance equations written in y (g = T f T^-1, Dg = T Df T^-1), built from points x.
"""
from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Sequence

import flint
import numpy as np

from hkproof.algebra.monomials import Exponents, exponents_upto
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.dynamics.modular_map import ModularKahanMap
from hkproof.errors import UnluckyPrimeError
from hkproof.hk.poisson import pairs
from hkproof.hk.symmetries import field_symmetries
from hkproof.hk.torus import Torus

__all__ = ["Block", "FactoredMod", "SignSymmetry", "blocks", "factored_mod", "invariance_rows", "sign_symmetries",
           "system_mod_p", "weight"]

Signs = tuple[int, ...]


@dataclass(frozen=True)
class SignSymmetry:
    """x -> S x with S = diag(signs), proven a symmetry of the Kahan map (`how` says by which identity)."""
    signs: Signs
    how: str


@dataclass(frozen=True)
class Block:
    """The columns (pair index, exponents of x^m) of one character of the sign symmetries."""
    character: Signs
    columns: tuple[tuple[int, Exponents], ...]


def _negated(kmap: KahanMap) -> bool:
    """E(-x, -x~, -eps) = -E(x, x~, eps), exactly (then f(-x, -eps) = -f(x, eps))."""
    t = kmap.field.tilde_ring
    images = {v: -t.gen(v) for v in (*kmap.variables, *kmap.field.tilde_variables, EPS)}
    return all(t.substitute(e, images) == -e for e in kmap.equations)


def sign_symmetries(kmap: KahanMap) -> list[SignSymmetry]:
    """The diagonal sign symmetries of the map that fix the parameters, each checked exactly, and -I when the
    equations are odd under (x, x~, eps) -> -(x, x~, eps) and reversible."""
    out = []
    for s in field_symmetries(kmap.field):
        if s.parameters or any(v != w for v, w, _ in s.variables) or all(sign > 0 for _, _, sign in s.variables):
            continue
        if s.commutes(kmap):
            signs = dict((v, sign) for v, _, sign in s.variables)
            out.append(SignSymmetry(tuple(signs.get(v, 1) for v in kmap.variables),
                                    f"f(Sx) = S f(x) for S: {s} (exact)"))
    if _negated(kmap) and kmap.equations_reversible():
        out.append(SignSymmetry(tuple(-1 for _ in kmap.variables),
                                "E(-x, -x~, -eps) = -E(x, x~, eps) and E(x~, x, -eps) = -E(x, x~, eps) (exact)"))
    return out


def _character(symmetries: Sequence[SignSymmetry], pair: tuple[int, int], m: Exponents) -> Signs:
    out = []
    for s in symmetries:
        sign = s.signs[pair[0]] * s.signs[pair[1]]
        for k, e in enumerate(m):
            if e % 2 and s.signs[k] < 0:
                sign = -sign
        out.append(sign)
    return tuple(out)


def denominator_character(kmap: KahanMap, denominator: flint.fmpz_mpoly, s: SignSymmetry) -> int | None:
    """+1 or -1 when D(Sx) = +-D(x) exactly, None otherwise."""
    ring = kmap.ring
    moved = ring.substitute(denominator, {v: ring.gen(v) * sign for v, sign in zip(kmap.variables, s.signs,
                                                                                    strict=True) if sign < 0})
    return 1 if moved == denominator else -1 if moved == -denominator else None


def blocks(kmap: KahanMap, degree: int, symmetries: Sequence[SignSymmetry], torus: Torus | None = None
           ) -> list[Block]:
    """The columns of deg Q <= degree grouped by character (one block without symmetries), with the torus weight as
    its last entry when a torus is given; the monomials of each entry highest degree first."""
    n = len(kmap.variables)
    monos = exponents_upto(n, degree)
    groups: dict[Signs, list[tuple[int, Exponents]]] = {}
    for k, pair in enumerate(pairs(n)):
        for m in monos:
            character = _character(symmetries, pair, m)
            if torus is not None:
                character += (weight(torus, pair, m),)
            groups.setdefault(character, []).append((k, m))
    return [Block(ch, tuple(cols)) for ch, cols in sorted(groups.items(), reverse=True)]


@dataclass(frozen=True)
class FactoredMod:
    """D mod p as factors with exponents: D(x) = prod F_k(x)^e_k mod p, evaluated factor by factor (a square of a
    factor with 3 833 terms is never expanded to its 321 410)."""
    factors: tuple[tuple[flint.nmod_mpoly, int], ...]
    p: int

    def __call__(self, *x: int) -> int:
        out = 1
        for f, e in self.factors:
            out = out * pow(int(f(*x)), e, self.p) % self.p
        return out


def factored_mod(mmap: ModularKahanMap, factors: Sequence[tuple[flint.fmpz_mpoly, int]]) -> FactoredMod:
    """The factors reduced at the map's values mod its prime."""
    return FactoredMod(tuple((mmap.reduce(f), e) for f, e in factors), mmap.p)


def weight(torus: Torus, pair: tuple[int, int], m: Exponents) -> int:
    """The eigenvalue mod p of L_A on y^m e_i ^ e_j: sum_c m_c l_c - l_i - l_j."""
    w = torus.weights
    return (sum(e * l for e, l in zip(m, w, strict=True)) - w[pair[0]] - w[pair[1]]) % torus.prime


def _dtype(p: int) -> type:
    """int64 where products of two residues fit (p < 2^31), Python integers otherwise."""
    return np.int64 if p < 2**31 else object


Layout = tuple[np.ndarray, np.ndarray, np.ndarray]


def layout(block: Block) -> Layout:
    """The block's distinct monomials as an exponent array, and per column its pair and its monomial's row in it."""
    monos = sorted({m for _, m in block.columns})
    where = {m: k for k, m in enumerate(monos)}
    return (np.array(monos, dtype=np.int64).reshape(len(monos), -1),
            np.array([k for k, _ in block.columns], dtype=np.int64),
            np.array([where[m] for _, m in block.columns], dtype=np.int64))


def _values(exponents: np.ndarray, x: Sequence[int], p: int) -> np.ndarray:
    """x^m mod p for each monomial (a row of exponents), one vectorized product per variable (int64 below 2^31,
    Python integers above)."""
    out: np.ndarray = np.ones(exponents.shape[0], dtype=_dtype(p))
    for k, v in enumerate(x):
        column = exponents[:, k]
        table: np.ndarray = np.array([pow(int(v), e, p) for e in range(int(column.max(initial=0)) + 1)],
                                     dtype=_dtype(p))
        out = out * table[column] % p
    return out


def invariance_rows(mmap: ModularKahanMap, denominator: FactoredMod, block: Block, x: Sequence[int],
                    torus: Torus | None = None, columns: Layout | None = None) -> np.ndarray:
    """The rows Q(f(x)) D(x) - D(f(x)) Df Q(x) Df^T (entries i < j) at x on the block's columns, mod p (p < 2^31);
    in the torus' coordinates y = T x when one is given; UnluckyPrimeError where det M(x, eps) = 0 mod p.
    `columns`: the block's layout, computed once for many points."""
    p, n = mmap.p, mmap.n
    points, jacobians = mmap.tangent_orbit(x, 1)
    fx, jac = points[1], jacobians[1]
    dx, df = int(denominator(*x)) % p, int(denominator(*fx)) % p
    if torus is not None:          # y = T x, y~ = T f(x), Dg = T Df T^-1
        t, t_inv = flint.nmod_mat([list(r) for r in torus.rows], p), flint.nmod_mat([list(r) for r in torus.inverse], p)
        jac = t * jac * t_inv
        x = [int(v) for v in (t * flint.nmod_mat([[v] for v in x], p)).entries()]
        fx = [int(v) for v in (t * flint.nmod_mat([[v] for v in fx], p)).entries()]
    j = [[int(jac[r, c]) for c in range(n)] for r in range(n)]
    idx = pairs(n)
    wedge: np.ndarray = np.array([[(j[a][c] * j[b][d] - j[a][d] * j[b][c]) % p for c, d in idx] for a, b in idx], dtype=_dtype(p))
    exponents, pair_at, mono_at = columns if columns is not None else layout(block)
    mx, mf = _values(exponents, x, p), _values(exponents, fx, p)
    left = (dx * mf[mono_at]) % p                                  # D(x) x^m o f, on the column's own entry
    right = (((df * wedge) % p)[:, pair_at] * mx[mono_at]) % p     # D(f(x)) (Df ^ Df) x^m
    rows = (p - right) % p
    rows[pair_at, np.arange(len(block.columns))] = (rows[pair_at, np.arange(len(block.columns))] + left) % p
    return rows


def system_mod_p(mmap: ModularKahanMap, denominator: FactoredMod, block: Block, rng: random.Random,
                 extra: int = 4, torus: Torus | None = None, need: int | None = None
                 ) -> tuple[np.ndarray, list[list[int]]]:
    """The invariance rows at random points until there are `need` (default len(columns) + extra) of them: (rows mod
    p, points)."""
    p, n = mmap.p, mmap.n
    need = len(block.columns) + extra if need is None else need
    per_point = len(pairs(n))
    columns = layout(block)
    chunks: list[np.ndarray] = []
    points: list[list[int]] = []
    tries = 0
    while per_point * len(points) < need:
        tries += 1
        if tries > 4 * (need // per_point + 10):
            raise UnluckyPrimeError(f"det M(x, eps) = 0 mod {p} at too many random points")
        x = [rng.randrange(p) for _ in range(n)]
        try:
            chunks.append(invariance_rows(mmap, denominator, block, x, torus, columns))
        except UnluckyPrimeError:
            continue
        points.append(x)
    matrix = np.concatenate(chunks, axis=0)
    return matrix, points
