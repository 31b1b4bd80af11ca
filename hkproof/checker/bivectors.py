"""Step kinds on bivectors (version 7, docs/certificates.md): invariance Pi(f(x)) = Df Pi(x) Df^T, Jacobi and
compatibility (Schouten brackets), Casimirs, involution, and the exclusion of a class Q/D by a full column rank mod p
of invariance rows that the checker computes itself from its own Kahan map (no row is ever read from the file); from
version 9, no-poisson: the invariant Q/D of a class reduce mod p into a kernel none of whose members is Poisson; from
version 10, nambu: P W(grad I) for proven integrals and a proven density 1/P (the universal identities behind it
expanded here; rank 2 checked at a point)."""
from __future__ import annotations

import functools
import itertools
import math
import random
from typing import Any, Callable, Mapping

import flint

from hkproof.algebra.formula import check_name, parse_rational
from hkproof.algebra.fraction import Frac
from hkproof.checker.kahan import EPS, KahanData, det, minors, read
from hkproof.checker.reading import entries, get, integers, strings
from hkproof.checker.torus import CheckedTorus, read_torus
from hkproof.errors import CertificateError, HKProofError, Refutation, ResourceLimitError

__all__ = ["BIVECTOR_STEPS", "Matrix", "MAX_COLUMNS", "MAX_ROWS"]

Matrix = list[list[Frac]]
MAX_COLUMNS = 20_000       # unknowns of one block of an exclusion (its rank mod p is computed here)
MAX_ROWS = 60_000          # rows of one block of an exclusion
MAX_KERNEL = 6             # the dimension of a no-poisson kernel (its brackets: 21 at most)
Outcome = tuple[dict[str, Matrix], str]    # the bivectors a step concludes, and the fact it checked


def _pairs(n: int) -> list[tuple[int, int]]:
    return list(itertools.combinations(range(n), 2))


def _matrix(f: KahanData, step: Any, where: str) -> Matrix:
    """The n x n matrix of formulas `matrix`, antisymmetric exactly."""
    rows = get(step, "matrix", list, where)
    n = len(f.variables)
    if len(rows) != n or not all(isinstance(r, list) and len(r) == n and all(isinstance(t, str) for t in r)
                                 for r in rows):
        raise CertificateError(f"{where}: 'matrix' must be {n} rows of {n} formulas (strings)")
    m = [[f.parse(t, where) for t in r] for r in rows]
    if any(m[i][j] != -m[j][i] for i in range(n) for j in range(n)):
        raise CertificateError(f"{where}: the bivector's matrix is not antisymmetric")
    return m


def _differential(f: KahanData) -> tuple[list[list[flint.fmpz_mpoly]], flint.fmpz_mpoly]:
    """Df = J / Delta^2 with J = Delta dN - N grad(Delta)^T, from the checker's own map."""
    idx = [f.ring.index(v) for v in f.variables]
    return [[f.delta * p.derivative(k) - p * f.delta.derivative(k) for k in idx] for p in f.nums], f.delta ** 2


def _invariance(f: KahanData, step: Any, known: Mapping[str, Frac], have: Mapping[str, Matrix], where: str
                ) -> Outcome:
    """Pi(f(x)) = Df Pi(x) Df^T entry by entry: Pi_ij o f by the checker's composition, Df Pi Df^T as
    J Q J^T / (L Delta^4) over the common denominator L of Pi."""
    name = check_name(get(step, "name", str, where), "bivector name")
    if name in have or name in known or name in f.ring.names:
        raise CertificateError(f"{where}: the bivector name {name!r} is already taken")
    pi = _matrix(f, step, where)
    n = len(f.variables)
    if all(pi[i][j].is_zero() for i, j in _pairs(n)):
        raise CertificateError(f"{where}: the zero bivector is invariant for every map: it proves nothing")
    common = f.ring.constant(1)
    for i, j in _pairs(n):
        common = common * pi[i][j].den / common.gcd(pi[i][j].den)
    q = [[pi[i][j].num * (common / pi[i][j].den) for j in range(n)] for i in range(n)]
    jac, square = _differential(f)
    jq = [[sum((jac[i][k] * q[k][j] for k in range(n)), f.ring.constant(0)) for j in range(n)] for i in range(n)]
    for i, j in _pairs(n):
        right = sum((jq[i][k] * jac[j][k] for k in range(n)), f.ring.constant(0))
        if f.pull(pi[i][j], 1) != Frac(f.ring, right, common * square ** 2):
            raise Refutation(f"{where}: {name}(f(x)) != Df {name}(x) Df^T at the entry ({f.variables[i]}, "
                             f"{f.variables[j]})")
    return {name: pi}, f"{name}(f(x)) = Df {name}(x) Df^T"


def _named(step: Any, key: str, have: Mapping[str, Matrix], where: str) -> list[str]:
    names = strings(step, key, where) if key == "bivectors" else [get(step, key, str, where)]
    for b in names:
        if b not in have:
            raise CertificateError(f"{where}: no earlier bivector-invariance step of this field proves {b!r}")
    return names


def _schouten(a: Matrix, b: Matrix, f: KahanData) -> list[Frac]:
    """[Pi_a, Pi_b]^ijk, i < j < k: the cyclic sum over (i, j, k) of sum_l Pi_a^il d_l Pi_b^jk + Pi_b^il d_l Pi_a^jk."""
    n, xs = len(f.variables), f.variables
    out = []
    for i, j, k in itertools.combinations(range(n), 3):
        total = Frac(f.ring, 0)
        for r, s, t in ((i, j, k), (j, k, i), (k, i, j)):
            for ll in range(n):
                total += a[r][ll] * b[s][t].derivative(xs[ll]) + b[r][ll] * a[s][t].derivative(xs[ll])
        out.append(total)
    return out


def _jacobi(f: KahanData, step: Any, known: Mapping[str, Frac], have: Mapping[str, Matrix], where: str) -> Outcome:
    """[Pi, Pi] = 0 (one name: Pi is Poisson) or [Pi_a, Pi_b] = 0 (two names: compatible), exactly."""
    names = _named(step, "bivectors", have, where)
    if len(names) not in (1, 2):
        raise CertificateError(f"{where}: a jacobi step names one bivector (Jacobi) or two (compatibility)")
    a, b = have[names[0]], have[names[-1]]
    if not all(c.is_zero() for c in _schouten(a, b, f)):
        raise Refutation(f"{where}: the Schouten bracket [{names[0]}, {names[-1]}] is not 0")
    return {}, (f"{names[0]} is Poisson: [{names[0]}, {names[0]}] = 0" if len(names) == 1 else
                f"{names[0]} and {names[1]} are compatible: [{names[0]}, {names[1]}] = 0")


def _functions(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> list[tuple[str, Frac]]:
    """Formulas in the phase variables, eps, the parameters and integrals proven before; none free of x."""
    out = [(t, read(f.ring, t, where, known)) for t in strings(step, "functions", where)]
    if not out or any(not (h.variables() & set(f.variables)) for _, h in out):
        raise CertificateError(f"{where}: 'functions' must be non-empty and each must depend on the phase variables")
    return out


def _casimir(f: KahanData, step: Any, known: Mapping[str, Frac], have: Mapping[str, Matrix], where: str) -> Outcome:
    """Pi grad C = 0 for each stated C, exactly."""
    name = _named(step, "bivector", have, where)[0]
    pi, n = have[name], len(f.variables)
    for text, c in _functions(f, step, known, where):
        grad = [c.derivative(v) for v in f.variables]
        if not all(sum((pi[i][j] * grad[j] for j in range(n)), Frac(f.ring, 0)).is_zero() for i in range(n)):
            raise Refutation(f"{where}: {name} grad ({text[:80]}) != 0")
    return {}, f"Casimirs of {name}: {', '.join(t for t, _ in _functions(f, step, known, where))}"


def _involution(f: KahanData, step: Any, known: Mapping[str, Frac], have: Mapping[str, Matrix], where: str
                ) -> Outcome:
    """{I, J} = grad I . Pi grad J = 0 for every pair of the stated functions, exactly."""
    name = _named(step, "bivector", have, where)[0]
    pi, n = have[name], len(f.variables)
    found = _functions(f, step, known, where)
    grads = [[h.derivative(v) for v in f.variables] for _, h in found]
    for (s, gs), (t, gt) in itertools.combinations(zip([t for t, _ in found], grads, strict=True), 2):
        value = sum((pi[i][j] * (gs[i] * gt[j] - gs[j] * gt[i]) for i, j in _pairs(n)), Frac(f.ring, 0))
        if not value.is_zero():
            raise Refutation(f"{where}: {{{s[:60]}, {t[:60]}}} != 0 for {name}")
    return {}, f"in involution for {name}: {', '.join(t for t, _ in found)}"


def _dual(rows: list[list[flint.fmpz_mpoly]]) -> list[list[flint.fmpz_mpoly]]:
    """W(g)^ij = det(e_i; e_j; g_1; ...; g_(n-2)) for n - 2 rows g_k of length n: (-1)^(i + j - 1) (i < j) times the
    minor of the rows on the other columns (Laplace expansion along e_i, then e_j)."""
    n = len(rows[0])
    m = minors(rows)
    zero = rows[0][0] - rows[0][0]
    w = [[zero] * n for _ in range(n)]
    for i, j in _pairs(n):
        w[i][j] = m[tuple(c for c in range(n) if c not in (i, j))] * (-1) ** (i + j - 1)
        w[j][i] = -w[i][j]
    return w


@functools.lru_cache(maxsize=None)
def _nambu_identities(n: int) -> bool:
    """The universal identities behind a nambu step for n phase variables, expanded here once per n, in rings of
    their own (nothing a file states enters them): (a) A W(g_1 A, ..., g_(n-2) A) A^T = det(A) W(g) in Z[A, g];
    (b) W(g) g_k = 0; (c) [phi W, phi W] = 0 in the ring of the 1-jet of phi and the 2-jets of the I_k (W built from
    their first derivatives I_k,i), the derivatives d_l total: d_l phi = phi_l, d_l I_k,i = I_k,il."""
    ctx = flint.fmpz_mpoly_ctx.get([f"a{p}_{q}" for p in range(n) for q in range(n)] +
                                   [f"g{k}_{i}" for k in range(n - 2) for i in range(n)], "degrevlex")
    gens = iter(ctx.gens())
    a = [[next(gens) for _ in range(n)] for _ in range(n)]
    g = [[next(gens) for _ in range(n)] for _ in range(n - 2)]
    w, wga = _dual(g), _dual([[sum((r[p] * a[p][q] for p in range(n)), ctx.from_dict({})) for q in range(n)]
                              for r in g])
    det_a = det(a)
    if any(sum((a[p][i] * a[q][j] * wga[i][j] for i in range(n) for j in range(n) if i != j), ctx.from_dict({}))
           != det_a * w[p][q] for p, q in _pairs(n)):
        return False
    if any(not sum((w[i][j] * r[j] for j in range(n)), ctx.from_dict({})).is_zero() for r in g for i in range(n)):
        return False
    second = [(k, i, l) for k in range(n - 2) for i in range(n) for l in range(i, n)]
    jets = flint.fmpz_mpoly_ctx.get(["phi"] + [f"phi_{l}" for l in range(n)] + [f"I{k}_{i}" for k in range(n - 2)
                                    for i in range(n)] + [f"I{k}_{i}_{l}" for k, i, l in second], "degrevlex")
    gen = dict(zip(jets.names(), jets.gens(), strict=True))
    pi = [[gen["phi"] * e for e in row] for row in _dual([[gen[f"I{k}_{i}"] for i in range(n)]
                                                            for k in range(n - 2)])]

    def total(q: flint.fmpz_mpoly, l: int) -> flint.fmpz_mpoly:
        out = q.derivative("phi") * gen[f"phi_{l}"]
        for k, i in itertools.product(range(n - 2), range(n)):
            out += q.derivative(f"I{k}_{i}") * gen[f"I{k}_{min(i, l)}_{max(i, l)}"]
        return out
    return all(sum((pi[r][l] * total(pi[s][t], l) for r, s, t in ((i, j, k), (j, k, i), (k, i, j)) for l in range(n)),
                   jets.from_dict({})).is_zero() for i, j, k in itertools.combinations(range(n), 3))


def _nambu(f: KahanData, step: Any, known: Mapping[str, Frac], densities: Mapping[str, Any], where: str) -> Outcome:
    """Pi = P W(grad I_1, ..., grad I_(n-2)) (W^ij = det(e_i; e_j; grad I_1; ...)) for integrals I_k and a density
    rho = 1/P proven before on this field is invariant, Poisson, of rank <= 2 with the I_k as Casimirs (the
    construction of Byrnes, Haggar and Quispel 1999), from identities expanded here (`_nambu_identities`): the chain
    rule on I_k o f = I_k gives grad I_k(x) = grad I_k(f(x)) Df(x), so (a) with A = Df and P o f = det Df P carries
    Pi(x) to Pi(f(x)); (b) gives the Casimirs; (c) Jacobi, whatever the functions. Rank 2 (independent gradients,
    P != 0) is checked at the stated point; the step concludes no matrix (it is never expanded)."""
    n, names = len(f.variables), strings(step, "casimirs", where)
    density = get(step, "density", str, where)
    if n < 3 or len(set(names)) != n - 2 or len(names) != n - 2 or any(c not in known for c in names) \
            or density not in densities:
        raise CertificateError(f"{where}: a nambu step names {n - 2} distinct integrals and a density, each proven "
                               "by an earlier step on this field (n >= 3)")
    point = {v: parse_rational(get(get(step, "point", dict, where), v, str, where)) for v in f.ring.names}
    try:
        grads = flint.fmpq_mat([[known[c].derivative(v).evaluate(point) for v in f.variables] for c in names])
        at = densities[density].evaluate(point)
    except (HKProofError, ZeroDivisionError):
        raise CertificateError(f"{where}: the stated point is a pole of an integral or of the density") from None
    if at == 0 or grads.rank() != n - 2:
        raise CertificateError(f"{where}: the gradients are dependent or P = 0 at the stated point: choose another")
    name = check_name(get(step, "name", str, where), "bivector name")
    if not _nambu_identities(n):
        raise RuntimeError(f"{where}: a universal identity of Nambu bivectors fails for n = {n}: the checker's own "
                           "arithmetic is wrong (an internal error, not a verdict on the file)")
    return {}, (f"{name} = P W({', '.join(f'grad {c}' for c in names)}), P = 1/{density}: invariant, Poisson, rank 2, "
                f"Casimirs {', '.join(names)}")


# ---- exclusion by a full column rank mod p; no Poisson member ---------------------------------------------------------
def _exclusion(f: KahanData, step: Any, known: Mapping[str, Frac], have: Mapping[str, Matrix], where: str
               ) -> Outcome:
    """No Q != 0 (antisymmetric, degree <= d in x, coefficients in Q(eps, params)) with Q/D invariant. The checker
    builds the rows Q(f(x)) D(x) - D(f(x)) Df Q(x) Df^T at the stated integer points from its own map, reduced at the
    stated values mod the stated prime, and requires full column rank in every block: a non-zero maximal minor mod p
    is the image of a maximal minor over Q(eps, params) (denominators: powers of Delta(x_k), units mod p). Blocks are
    the characters of sign symmetries S that it proves itself (S f(Sx) = f(x) or f^-1(x), D(Sx) = +-D(x)): each S
    maps invariant Q/D to invariant ones, so an invariant Q has an invariant part on the columns of one character."""
    c = _Class(f, step, where)
    sizes = c.full_rank(list(c.columns), where)
    return {}, (f"no invariant bivector Q/({c.denominator}) with deg Q <= {c.degree} (full column rank mod {c.p} in "
                f"{len(sizes)} block(s) of {sizes} columns)")


def _no_poisson(f: KahanData, step: Any, known: Mapping[str, Frac], have: Mapping[str, Matrix], where: str
                ) -> Outcome:
    """No invariant Q/D (deg Q <= d) is Poisson. The blocks off the sign characters of `kernels` have full column rank
    (as for an exclusion: no invariant Q has a part there); on each of those characters, in the field's coordinates,
    the rows at its points have a kernel mod p (computed here); with v_1..v_r the members of all of them, the brackets
    [v_a, v_b], a <= b, are linearly independent mod p, so no member sum c_a v_a != 0 over F_p satisfies Jacobi. Why
    that is a theorem: were Q/D invariant and Poisson over Q(eps, params), restrict Q to a generic line params =
    values + t u, divide by the power of t that divides every coefficient and set t = 0: a non-zero rational invariant
    bivector of the map at the values, Poisson, whose part on each character reduces mod p (the whole scaled to a
    primitive integer vector) into that character's kernel. A kernel with `fixed` (and a torus A, grad D . A x =
    chi D): the torus blocks of its character are stated too, but for the weight chi; the exact kernel of L_X - chi on
    the character's columns (X = A x) has as many vectors as that weight's block has columns, so no other weight is
    chi mod p and every invariant Q there lies in it; the rows are solved on its basis."""
    c = _Class(f, step, where)
    k = len(c.symmetries)
    plain = _columns(len(f.variables), c.degree, c.symmetries)
    blocks = entries(step, "kernels", where)
    signs = [tuple(integers(b, "character", where)) for b in blocks]
    if not blocks or len(set(signs)) != len(signs) or any(sign not in plain for sign in signs):
        raise CertificateError(f"{where}: the kernels' characters {[list(x) for x in signs]} must be distinct "
                               "characters of the columns")
    fixed = [get(b, "fixed", bool, where) if "fixed" in b else False for b in blocks]
    if any(fixed) and c.torus is None:
        raise CertificateError(f"{where}: a fixed kernel needs the torus whose flow fixes it")
    chi = int(c.torus.chi.p) * pow(int(c.torus.chi.q), -1, c.p) % c.p if c.torus is not None else 0
    kept = {ch for ch in c.columns for sign, fx in zip(signs, fixed, strict=True)
            if (ch == sign + (chi,) if fx else ch[:k] == sign)}
    c.full_rank([ch for ch in c.columns if ch not in kept], where)
    members: list[dict[tuple[int, tuple], int]] = []
    rows_of = _Rows(f, c.denominator.num, c.fixed, c.p)
    for b, sign, fx in zip(blocks, signs, fixed, strict=True):
        cols = plain[sign]
        basis = _fixed_basis(c.torus, cols, len(f.variables)) if fx and c.torus else None
        if basis is not None and len(basis) != len(c.columns.get(sign + (chi,), [])):
            raise CertificateError(f"{where}: L_X - chi has a kernel of dimension {len(basis)} on the character "
                                   f"{list(sign)}, not the {len(c.columns.get(sign + (chi,), []))} columns of weight "
                                   f"chi mod {c.p}: another weight is chi mod p (choose another prime)")
        rows = c.matrix(rows_of, cols, b, where, basis)
        basis = basis if basis is not None else [[(j, 1)] for j in range(len(cols))]
        space, nullity = flint.nmod_mat(rows, c.p).nullspace() if rows and basis else (None, 0)
        if space is None or not 1 <= nullity <= MAX_KERNEL:
            raise CertificateError(f"{where}: the rows at the points of the kernel {list(sign)} have a kernel of "
                                   f"dimension {nullity} mod {c.p} (this checker takes 1 to {MAX_KERNEL}): this "
                                   "proves nothing")
        for v in range(nullity):
            member: dict[tuple[int, tuple], int] = {}
            for u, vector in enumerate(basis):
                for j, e in vector:
                    member[cols[j]] = (member.get(cols[j], 0) + int(space[u, v]) * e) % c.p
            members.append(member)
    if len(members) > MAX_KERNEL or not _brackets_independent(f, c, members):
        raise CertificateError(f"{where}: the brackets of the kernels' {len(members)} members are dependent mod {c.p} "
                               f"(a member may satisfy Jacobi), or there are more than {MAX_KERNEL}: this excludes "
                               "nothing")
    return {}, (f"no invariant Poisson structure Q/({c.denominator}) with deg Q <= {c.degree} (kernels of dimension "
                f"{len(members)} in all mod {c.p}{' on fixed bivectors' if any(fixed) else ''}, no member Poisson)")


def _fixed_basis(torus: CheckedTorus, cols: list[tuple[int, tuple]], n: int) -> list[list[tuple[int, int]]]:
    """A basis over Z of ker(L_X - chi) on the columns, X = A x: (L_X Q)^ij = X(Q^ij) - A_ik Q^kj - A_jk Q^ik, scaled
    to integers, solved exactly on the connected pieces of columns (two meet when their images share a term); its
    reduction mod p must keep full rank (then a rational fixed vector has coordinates without p in their
    denominators, and its reduction lies in the span of the reduced basis)."""
    scale = 1
    for e in [*(e for row in torus.generator for e in row), torus.chi]:
        scale = scale * int(e.q) // math.gcd(scale, int(e.q))
    a = [[int(e * scale) for e in row] for row in torus.generator]
    index = {pair: k for k, pair in enumerate(_pairs(n))}
    images: list[dict[tuple[int, tuple], int]] = []
    for k, m in cols:
        image: dict[tuple[int, tuple], int] = {}

        def add(i: int, j: int, mono: tuple, v: int) -> None:
            if i != j and v:
                key = (index[(min(i, j), max(i, j))], mono)
                image[key] = image.get(key, 0) + (v if i < j else -v)
        i, j = _pairs(n)[k]
        for ll in range(n):
            for r in range(n):
                if m[ll] and a[ll][r]:
                    add(i, j, tuple(e - (t == ll) + (t == r) for t, e in enumerate(m)), a[ll][r] * m[ll])
        for r in range(n):
            add(r, j, m, -a[r][i])
            add(i, r, m, -a[r][j])
        add(i, j, m, -int(torus.chi * scale))
        images.append({key: v for key, v in image.items() if v})
    parent = list(range(len(cols)))

    def root(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x
    owner: dict[tuple[int, tuple], int] = {}
    for col, image in enumerate(images):
        for key in image:
            parent[root(col)] = root(owner.setdefault(key, col))
    pieces: dict[int, list[int]] = {}
    for col in range(len(cols)):
        pieces.setdefault(root(col), []).append(col)
    basis = []
    for piece in pieces.values():
        keys = sorted({key for col in piece for key in images[col]})
        if not keys:
            basis += [[(col, 1)] for col in piece]
            continue
        space, nullity = flint.fmpz_mat([[images[col].get(key, 0) for col in piece] for key in keys]).nullspace()
        if nullity and flint.nmod_mat([[int(space[t, b]) % torus.p for b in range(nullity)] for t in range(len(piece))],
                                      torus.p).rank() != nullity:
            raise CertificateError(f"the fixed bivectors' basis is degenerate mod {torus.p}: choose another prime")
        basis += [[(col, int(space[t, b])) for t, col in enumerate(piece) if space[t, b] != 0] for b in range(nullity)]
    return basis


def _brackets_independent(f: KahanData, c: "_Class", members: list[dict[tuple[int, tuple], int]]) -> bool:
    """The brackets [v_a/D, v_b/D] D^3 / 2 (a <= b; sum over cyclic (i, j, k) and l of v_a^il (D d_l v_b^jk -
    v_b^jk d_l D) + (a <-> b)), members' residues and D at the values, independent mod p (then sum c_a c_b [v_a, v_b]
    = 0 forces every c_a c_b = 0): their values at points mod p, a linear image of their coefficients, from those of
    v, D and their first derivatives, have full rank (points that do not show it prove nothing: refused)."""
    n, p, ring, rng = len(f.variables), c.p, f.ring, random.Random(c.p)
    d = ring.substitute(c.denominator.num, dict(zip(ring.names[n:], c.fixed, strict=True)))
    grad_d = [d.derivative(x) for x in f.variables]
    pair_index = {pair: k for k, pair in enumerate(_pairs(n))}
    brackets = list(itertools.combinations_with_replacement(range(len(members)), 2))
    values: list[list[int]] = [[] for _ in brackets]
    for _ in range(len(brackets) + 2 if n >= 3 else 0):
        x = [rng.randrange(p) for _ in ring.names]
        dx, grad = int(d(*x)) % p, [int(g(*x)) % p for g in grad_d]
        jets = []                                   # member -> (v^k(x), d_l v^k(x)) for each pair k
        for member in members:
            val, der = [0] * len(pair_index), [[0] * n for _ in pair_index]
            for (k, m), value in member.items():
                mono = [pow(x[t], e, p) for t, e in enumerate(m)]
                val[k] += value * math.prod(mono)
                for ll in (ll for ll in range(n) if m[ll]):
                    der[k][ll] += value * m[ll] * math.prod(mono[:ll] + [pow(x[ll], m[ll] - 1, p)] + mono[ll + 1:])
            jets.append((val, der))

        def entry(a: int, i: int, j: int, ll: int | None = None) -> int:
            k = pair_index.get((min(i, j), max(i, j)))
            v = 0 if k is None else jets[a][0][k] if ll is None else jets[a][1][k][ll]
            return v if i < j else -v

        def half(a: int, b: int, r: int, s_: int, t: int) -> int:
            return sum(entry(a, r, ll) * (dx * entry(b, s_, t, ll) - entry(b, s_, t) * grad[ll]) for ll in range(n))
        for row, (a, b) in zip(values, brackets, strict=True):
            row.extend(sum(half(a, b, *rst) + half(b, a, *rst) for rst in ((i, j, k), (j, k, i), (k, i, j))) % p
                       for i, j, k in itertools.combinations(range(n), 3))
        if flint.nmod_mat(values, p).rank() == len(brackets):
            return True
    return False


class _Class:
    """A class Q/D, deg Q <= degree, as an exclusion-type step states it: the prime, the values (residues), the sign
    symmetries (each proven here), the torus, and the columns grouped by character."""

    def __init__(self, f: KahanData, step: Any, where: str):
        if "rows" in step:
            raise CertificateError(f"{where}: a {step.get('kind')} step carries no rows: the checker computes them "
                                   "from the field")
        self.f = f
        self.p = p = get(step, "prime", int, where)
        if not 2 < p < 2**62 or not flint.fmpz(p).is_prime():
            raise CertificateError(f"{where}: the modulus {p} is not an odd prime below 2^62")
        self.degree = get(step, "degree", int, where)
        if not 0 <= self.degree <= 12:
            raise CertificateError(f"{where}: the degree of Q must be between 0 and 12")
        self.denominator = f.parse(get(step, "denominator", str, where), where)
        if not self.denominator.is_polynomial() or self.denominator.is_zero():
            raise CertificateError(f"{where}: the denominator D must be a non-zero polynomial")
        values = get(step, "values", dict, where)
        if sorted(values) != sorted([EPS, *f.parameters]):
            raise CertificateError(f"{where}: 'values' must fix eps and every parameter, nothing else")
        self.fixed = []
        for name in f.ring.names[len(f.variables):]:
            v = parse_rational(get(values, name, str, where))
            if v.q % p == 0:
                raise CertificateError(f"{where}: the value of {name} has a denominator divisible by {p}")
            self.fixed.append(int(v.p) * pow(int(v.q), -1, p) % p)
        self.symmetries = [_symmetry(f, s, self.denominator, where)
                           for s in _sign_lists(step, len(f.variables), where)]
        self.torus = (read_torus(f, step["torus"], self.denominator, p, where) if step.get("torus") is not None
                      else None)
        if self.torus is not None and any(v > 0 for s in self.symmetries for v in s):
            raise CertificateError(f"{where}: with a torus the only sign symmetry allowed is -I (diagonal in every "
                                   "chart)")
        self.columns = _columns(len(f.variables), self.degree, self.symmetries, self.torus)
        self.stated: dict[tuple[int, ...], Any] = {}
        for block in entries(step, "blocks", where):
            character = tuple(integers(block, "character", where))
            if character in self.stated:
                raise CertificateError(f"{where}: the character {list(character)} is stated twice")
            self.stated[character] = block

    def matrix(self, rows_of: "_Rows", cols: list[tuple[int, tuple]], block: Any, where: str,
               basis: list[list[tuple[int, int]]] | None = None) -> list[list[int]]:
        """The rows at the block's stated points, within the checker's limits; on a basis of vectors (column,
        coefficient) when one is given, point by point (the unknowns are then the basis vectors)."""
        points = [integers({"x": x}, "x", where) for x in get(block, "points", list, where)]
        width = len(cols) if basis is None else len(basis)
        if width > MAX_COLUMNS or len(points) * len(_pairs(len(self.f.variables))) > MAX_ROWS:
            raise ResourceLimitError(f"{where}: a block of {width} unknowns and {len(points)} points is above the "
                                     f"checker's limit ({MAX_COLUMNS} unknowns, {MAX_ROWS} rows)",
                                     limit=f"{MAX_COLUMNS} columns", raise_with="no option raises it")
        if basis is None:
            return [row for x in points for row in rows_of.at(x, cols, where)]
        return [[sum(row[j] * e for j, e in vector) % self.p for vector in basis]
                for x in points for row in rows_of.at(x, cols, where)]

    def full_rank(self, characters: list[tuple[int, ...]], where: str) -> list[int]:
        """Full column rank mod p in the blocks of these characters, which must be exactly the stated ones."""
        if set(self.stated) != set(characters):
            raise CertificateError(f"{where}: the blocks must be exactly the characters {sorted(characters)} of the "
                                   "columns")
        rows_of = _Rows(self.f, self.denominator.num, self.fixed, self.p, self.torus)
        for character in characters:
            cols = self.columns[character]
            matrix = self.matrix(rows_of, cols, self.stated[character], where)
            if not matrix or flint.nmod_mat(matrix, self.p).rank() != len(cols):
                raise CertificateError(f"{where}: the rows at the stated points do not have full column rank "
                                       f"{len(cols)} mod {self.p} in block {list(character)}: this refutes nothing, "
                                       "and excludes nothing")
        return [len(self.columns[ch]) for ch in characters]


def _sign_lists(step: Any, n: int, where: str) -> list[list[int]]:
    out = []
    for s in get(step, "symmetries", list, where):
        signs = integers({"s": s}, "s", where)
        if len(signs) != n or any(v not in (1, -1) for v in signs) or all(v == 1 for v in signs):
            raise CertificateError(f"{where}: a symmetry is a list of {n} signs +-1, not all +1")
        out.append(signs)
    return out


def _symmetry(f: KahanData, signs: list[int], denominator: Frac, where: str) -> list[int]:
    """Require S f(Sx) = f(x) or f^-1(x) and D(Sx) = +-D(x), exactly; then S maps invariant Q/D to invariant ones."""
    flip = {v: -f.ring.gen(v) for v, s in zip(f.variables, signs, strict=True) if s < 0}
    moved = Frac(f.ring, f.ring.substitute(denominator.num, flip))
    if moved != Frac(f.ring, denominator.num) and moved != -Frac(f.ring, denominator.num):
        raise CertificateError(f"{where}: D(Sx) != +-D(x) for S = {signs}")
    delta = Frac(f.ring, f.ring.substitute(f.delta, flip))
    image = [s * Frac(f.ring, f.ring.substitute(p, flip)) / delta for s, p in zip(signs, f.nums, strict=True)]
    for i in (1, -1):
        nums, den = f.image(i)
        if all(a == Frac(f.ring, p, den) for a, p in zip(image, nums, strict=True)):
            return signs
    raise Refutation(f"{where}: S = {signs} conjugates the Kahan map neither to itself nor to its inverse")


def _columns(n: int, degree: int, symmetries: list[list[int]], torus: CheckedTorus | None = None
             ) -> dict[tuple[int, ...], list[tuple[int, tuple]]]:
    """The columns (pair, exponents) of deg Q <= degree, grouped by their character s_i s_j S^m per symmetry, and
    by the torus weight (the character's last entry) when there is a torus."""
    monos = [m for d in range(degree + 1) for m in itertools.product(range(d + 1), repeat=n) if sum(m) == d]
    out: dict[tuple[int, ...], list[tuple[int, tuple]]] = {}
    for k, (i, j) in enumerate(_pairs(n)):
        for m in monos:
            ch = tuple(s[i] * s[j] * (-1) ** sum(e for e, sk in zip(m, s, strict=True) if sk < 0) for s in symmetries)
            if torus is not None:
                ch += (torus.weight((i, j), m),)
            out.setdefault(ch, []).append((k, m))
    return out


class _Rows:
    """The invariance rows mod p at integer points, from the checker's map (N, Delta and their derivatives); in the
    torus' coordinates y = T x (y~ = T f(x), Dg = T Df T^-1) when there is one."""

    def __init__(self, f: KahanData, denominator: flint.fmpz_mpoly, fixed: list[int], p: int,
                 torus: CheckedTorus | None = None):
        self.f, self.d, self.fixed, self.p, self.torus = f, denominator, fixed, p, torus
        self.idx = [f.ring.index(v) for v in f.variables]
        self.polys = [[q, *(q.derivative(k) for k in self.idx)] for q in (*f.nums, f.delta)]

    def _value(self, q: flint.fmpz_mpoly, x: list[int]) -> int:
        return int(q(*x, *self.fixed)) % self.p

    def at(self, x: list[int], cols: list[tuple[int, tuple]], where: str) -> list[list[int]]:
        p, n = self.p, len(x)
        if any(not 0 <= v < p for v in x) or len(x) != len(self.idx):
            raise CertificateError(f"{where}: a point is {len(self.idx)} residues in [0, p)")
        values = [[self._value(q, x) for q in qs] for qs in self.polys]
        delta, grad = values[-1][0], values[-1][1:]
        if delta == 0:
            raise CertificateError(f"{where}: Delta(x) = 0 mod {p} at the stated point {x}: choose another")
        inv = pow(delta, -1, p)
        fx = [v[0] * inv % p for v in values[:-1]]
        df = [[(delta * v[1 + c] - v[0] * grad[c]) * inv * inv % p for c in range(n)] for v in values[:-1]]
        dx, dfx = self._value(self.d, x), self._value(self.d, fx)
        if self.torus is not None:
            t = self.torus
            x, fx = t.apply(t.rows, x), t.apply(t.rows, fx)
            left = [t.apply(t.rows, [df[r][c] for r in range(n)]) for c in range(n)]     # columns of T Df
            df = [[sum(left[k][r] * t.inverse[k][c] for k in range(n)) % p for c in range(n)] for r in range(n)]
        pairs = _pairs(n)
        wedge = [[(df[a][c] * df[b][d] - df[a][d] * df[b][c]) * dfx % p for c, d in pairs] for a, b in pairs]
        monos = {m: tuple(math.prod(pow(u, e, p) for e, u in zip(m, y, strict=True)) % p for y in (x, fx))
                 for m in {m for _, m in cols}}                                               # once per point
        return [[((dx * monos[m][1] if r == k else 0) - wedge[r][k] * monos[m][0]) % p for k, m in cols]
                for r in range(len(pairs))]


BIVECTOR_STEPS: dict[str, Callable[[KahanData, Any, Mapping[str, Frac], Mapping[str, Matrix], str], Outcome]] = {
    "bivector-invariance": _invariance, "jacobi": _jacobi, "casimir": _casimir, "involution": _involution,
    "exclusion": _exclusion, "no-poisson": _no_poisson, "nambu": _nambu}
