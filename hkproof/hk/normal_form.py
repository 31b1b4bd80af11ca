"""An affine chart in which a quadratic field is sparse, found from the field alone (hk.affine_chart proves the change).

Three moves, each accepted only when the right-hand sides get shorter (a frame: at least SPARSER times, so the
catalogue's charts stay as they are). Nothing here decides a result: the search runs in the chart and every integral
is proven back in the user's.

1. A translation y = x - x0 that removes the linear part (D F(x0) = 0: linear equations in x0, solved exactly with
   every parameter symbolic), making a homogeneous field homogeneous again; or, when the field has a linear part of
   its own, the translation that removes every part of D F(x0) that depends on x0, parameter monomial by parameter
   monomial (`centring_translation`).
2. A linear frame adapted to the invariants of the field, computed at a random rational value of the parameters:
   the integrals of degree <= 2 of the continuous flow (linear algebra on L_F I = 0) give quadratic forms Q_i and
   linear integrals l; the field itself gives the trace form K(y) = tr(A_y^2) of its quadratic part (A_y the
   Jacobian of the quadratic part at y) and its scaling derivations, the matrices W with D F(x) W x - W F(x) = c F(x)
   (the quasi-homogeneity x -> lambda^W x, time -> time / lambda^c, and the linear symmetries at c = 0; linear
   equations in W and c). Every one of these objects is carried by a change of chart, so the frame they define is
   the same up to the field's own symmetries in every chart. The linear integrals become coordinates. On W0 = {l = 0}
   a non-degenerate form Q0 (a combination of the homogeneous integrals, of all of them, or K) makes each
   Q0^-1 Q_i self-adjoint; W0 splits into the primary components over Q of these operators and of the derivations
   (the weights separate variables of different weight, as m from p in the Lagrange top; K separates them where the
   weights are equal, as in the Kirchhoff case), and each block gets a Q0-orthogonal basis that continues with the
   images of vectors already chosen (operators carry one block's frame to the next, projected along the other
   blocks) and is completed from the standard basis, scaled to equal Q0-norms where the ratio is a rational square
   (a rotation, not a stretch). The new coordinates are the dual basis.
3. A diagonal scaling that makes the numerical factors of the terms 1 where it can (p-adic valuations, one linear
   system per prime): a chart that stretched the axes is stretched back.
"""
from __future__ import annotations

import random
from dataclasses import replace
from typing import Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import cramer, nullspace_q, pivots_at, primitive_vector
from hkproof.algebra.ring import Rational
from hkproof.algebra.sampling import random_point
from hkproof.budget import check
from hkproof.dynamics.field import QuadraticField
from hkproof.errors import HKProofError
from hkproof.hk.affine_chart import AffineChange, transformed
from hkproof.hk.scaling_derivations import scaling_centre, scaling_derivations

__all__ = ["centring_translation", "diagonal_scaling", "field_size", "homogenizing_translation", "invariant_frames", "normal_form"]

Vector = list[flint.fmpq]
Matrix = tuple[tuple[str, ...], ...]
FRAME_TRIALS = 9            # random choices of the form Q0 the frame is built on (three per group of forms);
                            # the sparsest chart is kept
SPARSER = 2                 # a frame is taken when it shrinks the field at least this many times (a chart the user
                            # chose, such as the catalogue's, is kept unless another is much sparser)


def field_size(field: QuadraticField) -> int:
    """The length of the field's right-hand sides as text: terms and the sizes of their coefficients, the cost the
    normal form lowers."""
    return sum(len(str(f)) for f in field.rhs)


def normal_form(field: QuadraticField, seed: int = 0) -> tuple[AffineChange, QuadraticField] | None:
    """y = T x + c and the field in the chart y, when a translation or an invariant frame makes it sparser; None
    when the given chart is as sparse as these moves make it."""
    best = field
    moves: list[AffineChange] = []
    for shift in (scaling_centre(field, seed), homogenizing_translation(field), centring_translation(field)):
        if shift is not None and any(c != "0" for c in shift):
            moved = transformed(field, AffineChange.translation(shift), f"{field.name}[translated]")
            if field_size(moved) < field_size(best):
                best, moves = moved, [AffineChange.translation(shift)]
    base = best
    for frame in invariant_frames(base, random.Random(seed)):
        linear = AffineChange(frame, ("0",) * len(frame))
        try:
            moved = transformed(base, linear, f"{field.name}[frame]")
        except HKProofError:
            continue
        if SPARSER * field_size(moved) <= field_size(best):
            best, moves = moved, moves[:1] if moves and moves[0].is_translation() else []
            moves.append(linear)
    scaling = diagonal_scaling(best)
    if scaling is not None:
        n = len(scaling)
        diagonal = AffineChange(tuple(tuple(scaling[i] if i == j else "0" for j in range(n)) for i in range(n)),
                                ("0",) * n)
        moved = transformed(best, diagonal, f"{field.name}[scaled]")
        if field_size(moved) < field_size(best):
            best = moved
            moves.append(diagonal)
    if not moves:
        return None
    return _composed(field, moves), replace(best, name=f"{field.name}[normal form]",
                                            description=f"{field.name} in the chart y = T x + c")


def homogenizing_translation(field: QuadraticField) -> list[str] | None:
    """-x0 with D F(x0) = 0 (the linear part of F(y + x0) vanishes), solved exactly over Q(parameters); None when
    F has no linear part or no such x0 exists."""
    names = field.variables
    ring = field.ring
    rows: list[list[Frac]] = []
    rhs: list[Frac] = []
    for f in field.rhs:
        for v in names:
            d = f.derivative(v)                              # affine in x: d(0) + sum_k d_k x_k
            zero = d.substitute({u: 0 for u in names})
            rows.append([d.derivative(u) for u in names])
            rhs.append(-zero)
    if all(r.is_zero() for r in rhs):
        return None
    point: dict[str, Rational] = {v: 0 for v in ring.names}
    point.update(random_point(random.Random(1), list(field.parameters), 97))
    chosen, pivots = pivots_at(rows, point)
    if len(pivots) < len(names):
        return None
    try:
        x0, _ = cramer([rows[i] for i in chosen[:len(names)]], [rhs[i] for i in chosen[:len(names)]])
    except HKProofError:
        return None
    for row, b in zip(rows, rhs, strict=True):
        if sum((a * x for a, x in zip(row, x0, strict=True)), Frac(ring, 0)) != b:
            return None
    return [str(-x) for x in x0]


def centring_translation(field: QuadraticField) -> list[str] | None:
    """-x0 (rational numbers) with every part of D F(x0) that depends on x0 vanishing, coefficient by coefficient in
    the parameters: for each entry (i, j) and each monomial mu in eps-free parameters, the mu-part of d F_i/d x_j is
    affine in x0; the parts with a non-zero x0-coefficient are set to 0 (exact linear algebra over Q), the others
    (a linear part of the field such as b s2 in the Gaudin magnet) are what no translation changes. None when these
    equations have no solution or not a unique one."""
    names = field.variables
    ring = field.ring
    phase = [ring.index(v) for v in names]
    rows: dict[tuple, list[flint.fmpq]] = {}
    for i, f in enumerate(field.rhs):
        for j in phase:
            for m, c in f.num.derivative(j).to_dict().items():
                mu = tuple(e for k, e in enumerate(m) if k not in phase)
                row = rows.setdefault((i, j, mu), [flint.fmpq(0)] * (len(names) + 1))
                degree = [m[k] for k in phase]
                if sum(degree):
                    row[degree.index(1)] += flint.fmpq(c)
                else:
                    row[-1] -= flint.fmpq(c)
    system = [r for r in rows.values() if any(r[:-1])]
    if not system:
        return None
    x0 = _particular_solution(system)
    return None if x0 is None else [str(-v) for v in x0]


def _particular_solution(system: Sequence[Vector]) -> Vector | None:
    """A solution of the rows [a | b] (a x = b) with the free unknowns 0, None when there is none."""
    n = len(system[0]) - 1
    if flint.fmpq_mat([r[:-1] for r in system]).rank() != flint.fmpq_mat(list(system)).rank():
        return None
    reduced, rank = flint.fmpq_mat(list(system)).rref()
    x = [flint.fmpq(0)] * n
    for i in range(rank):
        pivot = next(j for j in range(n) if reduced[i, j] != 0)
        x[pivot] = reduced[i, n]
    return x


def diagonal_scaling(field: QuadraticField) -> list[str] | None:
    """lambda with y_i = lambda_i x_i making the numerical factors of the field's terms 1 where they can be: for each
    prime p, the p-adic valuations e (lambda_i = prod p^(e_i)) solve (e_j - m).e = -v_p(factor) over all terms
    x^m of F_j exactly (each prime with a consistent integer solution; the others left as they are); None when
    every factor is 1 already or no prime can be removed."""
    names = field.variables
    ring = field.ring
    phase = [ring.index(v) for v in names]
    terms: list[tuple[list[int], flint.fmpq]] = []
    for j, f in enumerate(field.rhs):
        groups: dict[tuple[int, ...], list[int]] = {}
        for m, c in f.num.to_dict().items():
            groups.setdefault(tuple(m[k] for k in phase), []).append(int(c))
        below = _content(f.den.coeffs())
        for m, coefficients in groups.items():
            row = [int(j == k) - m[k] for k in range(len(names))]
            terms.append((row, flint.fmpq(_content(coefficients), below)))
    primes = sorted({int(p) for _, c in terms for q in (c.p, c.q) for p, _ in flint.fmpz(q).factor()})
    scale = [flint.fmpq(1)] * len(names)
    for p in primes:
        system = [[flint.fmpq(e) for e in row] + [flint.fmpq(-_valuation(c, p))] for row, c in terms]
        e = _particular_solution(system)
        if e is None or any(v.q != 1 for v in e):
            continue
        scale = [s * flint.fmpq(p) ** int(v.p) for s, v in zip(scale, e, strict=True)]
    return None if all(s == 1 for s in scale) else [str(s) for s in scale]


def _content(coefficients: Sequence) -> int:
    g = flint.fmpz(0)
    for c in coefficients:
        g = g.gcd(flint.fmpz(c))
    return int(g)


def _valuation(c: flint.fmpq, p: int) -> int:
    """The p-adic valuation of a non-zero rational."""
    out = 0
    num, den = flint.fmpz(c.p), flint.fmpz(c.q)
    while num % p == 0:
        num, out = num // p, out + 1
    while den % p == 0:
        den, out = den // p, out - 1
    return out


def invariant_frames(field: QuadraticField, rng: random.Random) -> list[Matrix]:
    """Matrices T (rows as text) of frames adapted to the flow's integrals of degree <= 2 and to the field's trace form
    and scaling derivations (all at one random value of the parameters), one per random choice of the form Q0 they
    are built on; [] when no non-degenerate form exists. The linear integrals become coordinates; the frame of the
    subspace W0 where they vanish is built from the forms and derivations restricted to it (there the squares of
    linear integrals vanish and cannot couple the blocks)."""
    values = random_point(rng, list(field.parameters), 1009)
    special = field.specialize(values) if values else field
    homogeneous, forms, linear = _small_integrals(special)
    jac = _quadratic_jacobian(special)
    trace = [_trace_form(jac)]
    n = len(field.variables)
    inside = nullspace_q(linear) if linear else [[flint.fmpq(int(i == j)) for i in range(n)] for j in range(n)]
    m = len(inside)
    if not m:
        return []
    b0 = flint.fmpq_mat(n, m, [inside[j][i] for i in range(n) for j in range(m)])
    groups = [[b0.transpose() * q * b0 for q in group] for group in (homogeneous, forms, trace)]
    ambient = _derivation_operators(field, rng)
    derivations = [c for c in (_restricted(b0, w) for w in ambient) if c is not None]
    complements = [_form_complement(linear, forms, rng)]
    if linear and ambient:
        complements.append(_invariant_complement(linear, ambient))
    frames = []
    for trial in range(FRAME_TRIALS):
        check("choosing the frame of the normal form")
        order = groups[trial % 3:] + groups[:trial % 3]
        for complement in complements:
            for refined in (False, True):
                frame = _frame(b0, order, derivations, complement, jac if refined else None, rng)
                if frame is not None and frame not in frames:
                    frames.append(frame)
    return frames


def _form_complement(linear: list[Vector], forms: list[flint.fmpq_mat], rng: random.Random) -> list[Vector]:
    """Vectors dual to the linear integrals l: Q^-1 l for a non-degenerate form Q of the integrals (the Q-orthogonal
    complement of W0), else l itself."""
    n = len(linear[0]) if linear else 0
    ambient = _nondegenerate(forms, rng)
    return ([_column(ambient.inv() * flint.fmpq_mat(n, 1, ell)) for ell in linear] if ambient is not None
            else [[flint.fmpq(e) for e in ell] for ell in linear])


def _invariant_complement(linear: list[Vector], derivations: list[flint.fmpq_mat]) -> list[Vector]:
    """Vectors completing W0 = {l = 0} taken from the primary components of the scaling derivations on the whole
    space (the space of linear integrals is carried by every derivation, so W0 has a complement made of their
    blocks' vectors): each block's vectors in turn, kept while they are independent modulo W0."""
    n = len(linear[0])
    chosen: list[Vector] = []
    values: list[Vector] = []
    for block in _eigenspaces(n, derivations):
        for v in block:
            image = [sum((a * b for a, b in zip(ell, v, strict=True)), flint.fmpq(0)) for ell in linear]
            if any(image) and _independent(values + [image]):
                chosen.append(v)
                values.append(image)
    return chosen


def _frame(b0: flint.fmpq_mat, groups: list[list[flint.fmpq_mat]], derivations: list[flint.fmpq_mat],
           complement: list[Vector], jac: list[list[list[flint.fmpq]]] | None,
           rng: random.Random) -> Matrix | None:
    """One frame: Q0 a random non-degenerate combination of the first group of forms on W0 (the columns of b0) that
    has one, the primary components of the operators Q0^-1 Q and of the derivations, their bases, and the linear
    integrals' coordinates."""
    n, m = b0.nrows(), b0.ncols()
    q0 = next((q for q in (_nondegenerate(group, rng) for group in groups) if q is not None), None)
    if q0 is None:
        return None
    operators = derivations + [q0.inv() * q for group in groups for q in group]
    blocks = _eigenspaces(m, operators, groups, rng)
    vanishing = _vanishing_forms(blocks, [q for group in groups for q in group])
    if vanishing:
        groups = [*groups, vanishing]
        blocks = _eigenspaces(m, operators, groups, rng)
    if jac is not None:
        points = [_column(b0 * flint.fmpq_mat(m, 1, _random_in(block, rng))) for block in blocks]
        operators += [c for c in (_restricted(b0, _jacobian_at(jac, y)) for y in points) if c is not None]
        blocks = _eigenspaces(m, operators, groups, rng)
    splitting = flint.fmpq_mat(m, m, [v[i] for i in range(m) for v in (w for block in blocks for w in block)]).inv()
    starts = [sum(len(b) for b in blocks[:k]) for k in range(len(blocks) + 1)]
    chosen: list[Vector] = []
    sizes = [1] * len(complement)
    for k, block in enumerate(blocks):
        def part(v: Vector) -> Vector:
            return _component(v, block, splitting, starts[k])
        candidates = [part(_column(op * flint.fmpq_mat(m, 1, v))) for v in chosen for op in operators]
        free_from = len(candidates)
        candidates += [part([flint.fmpq(int(i == j)) for i in range(m)]) for j in range(m)]
        own: list[Vector] = []
        for index, v in enumerate(candidates):
            w = _orthogonalized(v, own, q0)
            if any(w) and _independent(own + [w]):
                if index >= free_from and own:
                    w = _equal_norm(w, own[0], q0)
                own.append(w)
            if len(own) == len(block):
                break
        chosen += own
        sizes.append(len(own))
    if len(chosen) != m:
        return None
    frame = [_column(b0 * flint.fmpq_mat(m, 1, v)) for v in chosen]
    vectors = complement + frame
    basis = flint.fmpq_mat(n, n, [vectors[j][i] for i in range(n) for j in range(n)])
    if basis.det() == 0:
        return None
    dual = basis.inv()
    rows = [[dual[i, j] for j in range(n)] for i in range(n)]
    bounds = [sum(sizes[:k]) for k in range(len(sizes) + 1)]
    scaled = [row for a, b in zip(bounds, bounds[1:]) for row in _primitive_matrix(rows[a:b])]
    return tuple(tuple(str(e) for e in row) for row in scaled)


def _vanishing_forms(blocks: list[list[Vector]], forms: list[flint.fmpq_mat]) -> list[flint.fmpq_mat]:
    """For each block, the forms of the span that vanish on it (a chart-free subspace once the blocks are: in the
    so(4) Euler top, the forms of the integrals span every form on each 2-dimensional block, but those vanishing on
    one block are diagonal on the others and split them into lines)."""
    out: list[flint.fmpq_mat] = []
    for block in blocks:
        m, k = len(block[0]), len(block)
        if k == m or not forms:
            continue
        basis = flint.fmpq_mat(m, k, [block[j][i] for i in range(m) for j in range(k)])
        flat = [(basis.transpose() * q * basis).entries() for q in forms]
        for c in nullspace_q([[f[r] for f in flat] for r in range(k * k)]):
            q = _combination(forms, c)
            if any(q.entries()) and _independent_form(out, q):
                out.append(q)
    return out


def _independent_form(known: list[flint.fmpq_mat], q: flint.fmpq_mat) -> bool:
    return flint.fmpq_mat([f.entries() for f in [*known, q]]).rank() == len(known) + 1


def _random_in(block: list[Vector], rng: random.Random) -> Vector:
    """A random integer combination of the block's vectors."""
    weights = [rng.randint(1, 97) for _ in block]
    return [sum((w * v[i] for w, v in zip(weights, block, strict=True)), flint.fmpq(0)) for i in range(len(block[0]))]


def _independent(vectors: list[Vector]) -> bool:
    return flint.fmpq_mat(vectors).rank() == len(vectors)


def _primitive_matrix(rows: list[Vector]) -> list[list[flint.fmpz]]:
    """The rows times one rational factor: integer entries with no common factor (the rows' relative scales kept)."""
    flat = primitive_vector([e for row in rows for e in row])
    n = len(rows[0])
    return [flat[i * n:(i + 1) * n] for i in range(len(rows))]


def _small_integrals(field: QuadraticField) -> tuple[list[flint.fmpq_mat], list[flint.fmpq_mat], list[Vector]]:
    """For a field with numbers for parameters: the quadratic forms Q of its homogeneous integrals x^T Q x, the
    quadratic parts of all its integrals x^T Q x + l.x, and its linear integrals l (linear algebra on L_F I = 0)."""
    names = field.variables
    n = len(names)
    xs = [Frac(field.ring, field.ring.gen(v)) for v in names]
    pairs = [(i, j) for i in range(n) for j in range(i, n)]
    quadratic = [xs[i] * field.rhs[j] + xs[j] * field.rhs[i] for i, j in pairs]      # L_F (x_i x_j)
    linear = list(field.rhs)                                                          # L_F x_i

    def kernel(derivs: Sequence[Frac]) -> list[Vector]:
        columns = [{tuple(m): flint.fmpq(c) / d.den.leading_coefficient() for m, c in d.num.to_dict().items()}
                   for d in derivs]
        monomials = sorted({m for col in columns for m in col})
        return nullspace_q([[col.get(m, 0) for col in columns] for m in monomials])

    def form(vec: Vector) -> flint.fmpq_mat:
        q = flint.fmpq_mat(n, n)
        for (i, j), c in zip(pairs, vec, strict=False):
            q[i, j] += c if i == j else c / 2
            if i != j:
                q[j, i] += c / 2
        return q

    everything = [form(v) for v in kernel(quadratic + linear) if any(v[:len(pairs)])]
    return [form(v) for v in kernel(quadratic)], everything, kernel(linear)


def _quadratic_jacobian(field: QuadraticField) -> list[list[list[flint.fmpq]]]:
    """J[k][i][a]: the coefficient of x_a in d F_k / d x_i for the quadratic part of a field with numbers for
    parameters (its Jacobian at y is A_y = sum_a J[.][.][a] y_a)."""
    names = field.variables
    n = len(names)
    phase = [field.ring.index(v) for v in names]

    def linear_part(f: Frac, i: int) -> list[flint.fmpq]:
        out = [flint.fmpq(0)] * n
        for mono, c in f.num.derivative(phase[i]).to_dict().items():
            degree = [mono[k] for k in phase]
            if sum(degree) == 1:
                out[degree.index(1)] += flint.fmpq(c) / f.den.leading_coefficient()
        return out

    return [[linear_part(field.rhs[k], i) for i in range(n)] for k in range(n)]


def _trace_form(jac: list[list[list[flint.fmpq]]]) -> flint.fmpq_mat:
    """The trace form K(y) = tr(A_y^2), A_y the Jacobian of the field's quadratic part at y (a quadratic form built
    from the field alone, so carried by every linear change of chart)."""
    n = len(jac)
    q = flint.fmpq_mat(n, n)
    for k in range(n):
        for i in range(n):
            for a in range(n):
                for b in range(n):
                    q[a, b] += (jac[k][i][a] * jac[i][k][b] + jac[k][i][b] * jac[i][k][a]) / 2
    return q


def _jacobian_at(jac: list[list[list[flint.fmpq]]], y: Vector) -> flint.fmpq_mat:
    """A_y, the Jacobian of the quadratic part at y."""
    n = len(jac)
    return flint.fmpq_mat(n, n, [sum((jac[k][i][a] * y[a] for a in range(n)), flint.fmpq(0))
                                 for k in range(n) for i in range(n)])


def _derivation_operators(field: QuadraticField, rng: random.Random) -> list[flint.fmpq_mat]:
    """The matrices W of the field's scaling derivations (hk.scaling_derivations, every parameter symbolic): a basis
    and one random combination of it (its primary components are the common refinement the basis alone may miss)."""
    basis = [d.linear for d in scaling_derivations(field) if any(d.linear.entries())]
    if len(basis) > 1:
        basis.append(_combination(basis, [rng.randint(1, 97) for _ in basis]))
    return basis


def _restricted(b0: flint.fmpq_mat, w: flint.fmpq_mat) -> flint.fmpq_mat | None:
    """The operator w on the span of b0's columns in their coordinates, or None when w does not keep that span."""
    return _solve_in(b0, w * b0)


def _nondegenerate(forms: Sequence[flint.fmpq_mat], rng: random.Random) -> flint.fmpq_mat | None:
    """A random integer combination of the forms with det != 0 (a few tries), or None."""
    if not forms:
        return None
    for _ in range(8):
        q = _combination(forms, [rng.randint(1, 97) for _ in forms])
        if q.det() != 0:
            return q
    return None


def _combination(matrices: Sequence[flint.fmpq_mat], coefficients: Sequence) -> flint.fmpq_mat:
    """sum_k c_k M_k."""
    out = matrices[0] * 0
    for c, m in zip(coefficients, matrices, strict=True):
        out += m * c
    return out


def _eigenspaces(m: int, operators: Sequence[flint.fmpq_mat], groups: Sequence[Sequence[flint.fmpq_mat]] = (),
                 rng: random.Random | None = None) -> list[list[Vector]]:
    """Split Q^m into the primary components over Q (kernels of g(M)^k for the irreducible factors g^k of the
    characteristic polynomial) of the operators, each applied to each block it leaves invariant, and of the pencils
    of the forms restricted to a block (Q0|^-1 Q| with Q0 a combination of one group, where no operator splits it),
    until nothing splits."""
    spaces = [_columns(_identity(m))]
    changed = True
    while changed:
        changed = False
        out: list[list[Vector]] = []
        for space in spaces:
            split = _split(space, operators, groups, rng or random.Random(m))
            changed |= len(split) > 1
            out += split
        spaces = out
    return spaces


def _split(space: list[Vector], operators: Sequence[flint.fmpq_mat], groups: Sequence[Sequence[flint.fmpq_mat]],
           rng: random.Random) -> list[list[Vector]]:
    """The primary components of the first operator that leaves `space` invariant and splits it; else of the first
    operator of the restricted pencils that splits it."""
    n, k = len(space[0]), len(space)
    basis = flint.fmpq_mat(n, k, [space[j][i] for i in range(n) for j in range(k)])
    inside = [c for c in (_solve_in(basis, m * basis) for m in operators) if c is not None]
    pencils: list[flint.fmpq_mat] = []
    if k < n:
        restricted = [[basis.transpose() * q * basis for q in group] for group in groups]
        every = [q for group in restricted for q in group]
        for group in restricted:
            q0 = _nondegenerate(group, rng)
            if q0 is not None:
                pencils += [q0.inv() * q for q in every]
    for coords in inside + pencils:
        factors = coords.charpoly().factor()[1]
        if len(factors) < 2:            # one primary component: the operator does not split the space
            continue
        pieces = []
        for factor, multiplicity in factors:
            kernel = nullspace_q((_at_matrix(factor, coords) ** multiplicity).tolist())
            pieces.append([_column(basis * flint.fmpq_mat(k, 1, v)) for v in kernel])
        if len(pieces) > 1 and sum(len(p) for p in pieces) == len(space):
            return pieces
    return [space]


def _at_matrix(g: flint.fmpq_poly, m: flint.fmpq_mat) -> flint.fmpq_mat:
    """g(M) by Horner's rule."""
    k = m.nrows()
    out = flint.fmpq_mat(k, k)
    for c in reversed(g.coeffs()):
        out = out * m + c * _identity(k)
    return out


def _identity(k: int) -> flint.fmpq_mat:
    return flint.fmpq_mat(k, k, [int(i == j) for i in range(k) for j in range(k)])


def _solve_in(basis: flint.fmpq_mat, image: flint.fmpq_mat) -> flint.fmpq_mat | None:
    """C with basis C = image, or None when the image leaves the span."""
    normal = basis.transpose() * basis
    c = normal.solve(basis.transpose() * image)
    return c if basis * c == image else None


def _component(v: Vector, block: list[Vector], splitting: flint.fmpq_mat, start: int) -> Vector:
    """The component of v in `block` along the other blocks of the direct sum (`splitting` is the inverse of the
    matrix whose columns are every block's vectors, `start` the block's first column)."""
    m = len(v)
    coords = splitting * flint.fmpq_mat(m, 1, v)
    return [sum((coords[start + j, 0] * b[i] for j, b in enumerate(block)), flint.fmpq(0)) for i in range(m)]


def _orthogonalized(v: Vector, basis: Sequence[Vector], q0: flint.fmpq_mat) -> Vector:
    """v minus its Q0-projections on the (Q0-orthogonal) vectors of `basis`."""
    out = list(v)
    for b in basis:
        nb = _form(q0, b, b)
        if nb != 0:
            c = _form(q0, out, b) / nb
            out = [x - c * y for x, y in zip(out, b, strict=True)]
    return out


def _equal_norm(w: Vector, ref: Vector, q0: flint.fmpq_mat) -> Vector:
    """w scaled to the Q0-norm of `ref` when the ratio of the norms is a rational square (otherwise w)."""
    a, b = _form(q0, ref, ref), _form(q0, w, w)
    if a == 0 or b == 0:
        return w
    ratio = a / b
    num, den = ratio.p, ratio.q
    if num < 0:
        return w
    rn, rd = flint.fmpz(num).sqrtrem(), flint.fmpz(den).sqrtrem()
    if rn[1] != 0 or rd[1] != 0:
        return w
    s = flint.fmpq(rn[0], rd[0])
    return [s * x for x in w]


def _form(q0: flint.fmpq_mat, u: Vector, v: Vector) -> flint.fmpq:
    n = len(u)
    return (flint.fmpq_mat(1, n, u) * q0 * flint.fmpq_mat(n, 1, v))[0, 0]


def _column(m: flint.fmpq_mat) -> Vector:
    return [m[i, 0] for i in range(m.nrows())]


def _columns(m: flint.fmpq_mat) -> list[Vector]:
    return [[m[i, j] for i in range(m.nrows())] for j in range(m.ncols())]


def _composed(field: QuadraticField, moves: Sequence[AffineChange]) -> AffineChange:
    """One change y = T x + c equal to the moves applied in order (each read in the field's ring)."""
    n = len(field.variables)
    t = [[Frac(field.ring, int(i == j)) for j in range(n)] for i in range(n)]
    c = [Frac(field.ring, 0) for _ in range(n)]
    for move in moves:
        tm, cm = move.entries(field)
        t = [[sum((tm[i][k] * t[k][j] for k in range(n)), Frac(field.ring, 0)) for j in range(n)] for i in range(n)]
        c = [sum((tm[i][k] * c[k] for k in range(n)), cm[i]) for i in range(n)]
    return AffineChange(tuple(tuple(str(e) for e in row) for row in t), tuple(str(e) for e in c))
