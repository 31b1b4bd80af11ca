"""The step kinds of a certificate (docs/certificates.md): each checks its identities exactly on the checker's own
Kahan map and returns the quantities it proves, by name. A step whose data cannot make its argument is malformed
(CertificateError); a false identity is a Refutation."""
from __future__ import annotations

from typing import Any, Mapping

import flint

from hkproof.algebra.formula import check_name, parse_rational
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring
from hkproof.checker.kahan import EPS, KahanData, read
from hkproof.checker.reading import entries, get, integers, optional_list, strings
from hkproof.errors import CertificateError, HKProofError, Refutation

__all__ = ["CARRIERS", "DET_DF", "STEPS"]

DET_DF = "det Df"      # a darboux step's cofactor written as the Jacobian determinant the checker computes itself


def _substitution(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """h o f - h = 0 (sec. 3): h(N/Delta) Delta^d over a common denominator, compared exactly."""
    h = f.parse(get(step, "function", str, where), where)
    names = [get(e, "name", str, where) for e in entries(step, "integrals", where)]
    if len(names) != 1:
        raise CertificateError(f"{where}: a substitution step concludes exactly one integral")
    if f.pull(h, 1) != h:
        raise Refutation(f"{where}: h(f(x)) - h(x) is not 0 for h = {str(h)[:200]}")
    return {names[0]: h}


def _prop_even(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """Prop. "prop: even" for one basis, or for several solved together ("blocks": the unknowns of the bases form one
    vector, block after block): (1) det != 0 at a rational point, (2) basis functions even in eps, rows i in a
    non-symmetric range of {-1, 0, 1} containing 0, relation data even in eps and written in integrals proven before,
    (3) every component even in eps, (4) every row and relation satisfied exactly. Then the components are
    integrals."""
    raw = entries(step, "blocks", where) if "blocks" in step else [step]
    blocks = [([f.parse(t, where) for t in strings(b, "basis", where)], f.parse(get(b, "target", str, where), where))
              for b in raw]
    width = sum(len(basis) for basis, _ in blocks)
    names = [check_name(n, "component name") for n in strings(step, "names", where)]
    solution = [f.parse(t, where) for t in strings(step, "solution", where)]
    iterates = integers(step, "iterates", where)
    if sorted(iterates) not in ([0, 1], [-1, 0]):
        raise CertificateError(f"{where}: iterates {iterates}: this checker takes rows i in {{0, 1}} or {{-1, 0}}")
    if not blocks or not all(phi.is_even_in(EPS) for basis, target in blocks for phi in (*basis, target)):
        raise CertificateError(f"{where}: Prop. \"prop: even\" needs basis functions even in eps")
    if len(names) != width or len(solution) != width or set(names) & {*f.ring.names, *known}:
        raise CertificateError(f"{where}: {width} basis functions need as many new component names and values")
    scope, rows = dict(known), []
    for k, rel in enumerate(entries(step, "relations", where)):
        uses = strings(rel, "uses", where)
        if any(u not in known and not (u.startswith("_l") and u[2:].isdigit() and int(u[2:]) < k) for u in uses):
            raise CertificateError(f"{where}: relation {k + 1} uses {uses}, not all proven before it")
        coefficients = [f.parse_in(t, scope, where) for t in strings(rel, "coefficients", where)]
        rhs = f.parse_in(get(rel, "rhs", str, where), scope, where)
        if len(coefficients) != width:
            raise CertificateError(f"{where}: relation {k + 1} has {len(coefficients)} coefficients, not {width}")
        if not all(c.is_even_in(EPS) for c in (*coefficients, rhs)):
            raise Refutation(f"{where}: relation {k + 1} has a coefficient or right-hand side not even in eps")
        scope[f"_l{k}"] = rhs
        rows.append((coefficients, rhs))
    if len(blocks) * len(iterates) + len(rows) < width:
        raise CertificateError(f"{where}: {len(blocks) * len(iterates)} rows and {len(rows)} relations for {width} "
                               "unknowns: the system must determine them")
    point = {n: parse_rational(get(get(step, "point", dict, where), n, str, where)) for n in f.ring.names}
    zero = flint.fmpq(0)
    matrix, moved, start = [], [], 0
    for basis, target in blocks:
        pulled = {i: [f.pull(phi, i) for phi in (*basis, target)] for i in iterates}
        moved.append((start, pulled))
        for i in iterates:
            matrix.append([zero] * start + [_at(m, point) for m in pulled[i][:-1]] +
                          [zero] * (width - start - len(basis)))
        start += len(basis)
    matrix += [[_at(c, point) for c in coefficients] for coefficients, _ in rows]
    if flint.fmpq_mat(matrix).rank() != width:
        raise CertificateError(f"{where}: the stated point is degenerate (the system's rank is not full there): choose "
                               "another point; this refutes nothing, the determinant may vanish at this point only")
    for n, a in zip(names, solution, strict=True):
        if not a.is_even_in(EPS):
            raise Refutation(f"{where}: the component {n} is not even in eps")
    for b, (start, pulled) in enumerate(moved, 1):
        for i in iterates:
            row = pulled[i]
            part = solution[start:start + len(row) - 1]
            if sum((a * m for a, m in zip(part, row[:-1], strict=True)), Frac(f.ring, 0)) != row[-1]:
                raise Refutation(f"{where}: the row i = {i} of block {b} is not satisfied by the solution")
    for k, (coefficients, rhs) in enumerate(rows, 1):
        if sum((c * a for c, a in zip(coefficients, solution, strict=True)), Frac(f.ring, 0)) != rhs:
            raise Refutation(f"{where}: the relation {k} is not satisfied by the solution")
    return dict(zip(names, solution, strict=True))


def reparametrization(f: KahanData, source: KahanData, step: Any, known: Mapping[str, Frac],
                       where: str) -> dict[str, Frac]:
    """Integrals of the source field carried to this field by sigma: b -> b(a), the source parameters as polynomials
    with integer coefficients in this field's parameters (x and eps fixed). If the images are algebraically
    independent (a Jacobian of full rank at a rational point) sigma is an embedding of Q(x, eps, b) into Q(x, eps, a);
    if it sends every source right-hand side to this field's, it sends the source's Kahan map to this one (Cramer's
    rule commutes with it), so it sends each identity I(f(x)) = I(x) to sigma(I)(f(x)) = sigma(I)(x)."""
    if source.variables != f.variables:
        raise CertificateError(f"{where}: the source field has the variables {source.variables}, not {f.variables}")
    images_text = get(step, "parameters", dict, where)
    if sorted(images_text) != sorted(source.parameters):
        raise CertificateError(f"{where}: 'parameters' must give an image for each source parameter "
                               f"{source.parameters}")
    images = {b: f.parse(get(images_text, b, str, where), where) for b in source.parameters}
    for b, image in images.items():
        if not image.den.is_one() or image.variables() - set(f.parameters):
            raise CertificateError(f"{where}: the image of {b}, {image}, must be a polynomial with integer "
                                   "coefficients in the parameters")
    if images and not any(flint.fmpq_mat([[_at(images[b].derivative(a), point) for a in f.parameters]
                                          for b in source.parameters]).rank() == len(images)
                          for point in _trial_points(f)):
        raise CertificateError(f"{where}: the images of the source parameters are not independent (Jacobian rank)")
    sigma = {b: image.num for b, image in images.items()}
    for v, g, h in zip(f.variables, source._rhs, f._rhs, strict=True):
        if g.substitute(sigma, f.ring) != h:
            raise Refutation(f"{where}: the substitution does not carry the source's {v}' = {g} to {v}' = {h}")
    return {n: h.substitute(sigma, f.ring) for n, h in known.items()}


def _affine_change(f: KahanData, source: KahanData, step: Any, known: Mapping[str, Frac],
                   where: str) -> dict[str, Frac]:
    """Integrals J of the source field G (the same names, in the chart y = T x + c) carried to J(T x + c). T and c are
    constants in the parameters; if det T != 0 (at one rational point, so as a rational function) and G(T x + c) =
    T F(x) exactly, then g(T x + c) = T f(x) + c (eq. "Kahan gen" is affine in the polarized field) and each identity
    J(g(y)) = J(y) gives J(T x + c) o f = J(T x + c)."""
    if (source.variables, source.parameters) != (f.variables, f.parameters):
        raise CertificateError(f"{where}: the source field must have the variables {f.variables} and the parameters "
                               f"{f.parameters} of this field, in that order")
    n = len(f.variables)
    rows = get(step, "matrix", list, where)
    shift = strings(step, "shift", where)
    if len(rows) != n or len(shift) != n or any(not isinstance(r, list) or len(r) != n for r in rows):
        raise CertificateError(f"{where}: 'matrix' must be {n} x {n} and 'shift' of length {n}")
    t = [[_constant(f, e, where) for e in r] for r in rows]
    c = [_constant(f, e, where) for e in shift]
    if not any(flint.fmpq_mat([[_at(e, point) for e in r] for r in t]).det() != 0 for point in _trial_points(f)):
        raise CertificateError(f"{where}: det T vanishes at every trial point: not a change of coordinates")
    x = [Frac(f.ring, f.ring.gen(v)) for v in f.variables]
    images = [sum((a * xk for a, xk in zip(r, x, strict=True)), ck) for r, ck in zip(t, c, strict=True)]
    common = f.ring.constant(1)
    for img in images:
        common = common * img.den / common.gcd(img.den)
    polys = [img.num * (common / img.den) for img in images]
    for v, g, r in zip(f.variables, source._rhs, t, strict=True):
        if g.pullback(polys, common, f.variables) != sum((a * h for a, h in zip(r, f._rhs, strict=True)),
                                                         Frac(f.ring, 0)):
            raise Refutation(f"{where}: G(T x + c) != T F(x) in the component of {v}': the chart does not carry "
                             "the source field to this one")
    return {name: h.pullback(polys, common, f.variables) for name, h in known.items()}


def _constant(f: KahanData, text: Any, where: str) -> Frac:
    """An entry of T or c: a formula in the parameters only (constant along the map, free of eps)."""
    if not isinstance(text, str):
        raise CertificateError(f"{where}: every entry of 'matrix' and 'shift' must be a string")
    value = f.parse(text, where)
    if value.variables() - set(f.parameters):
        raise CertificateError(f"{where}: the entry {value} of the affine change involves "
                               f"{sorted(value.variables() - set(f.parameters))}: T and c may involve parameters only")
    return value


def _trial_points(f: KahanData) -> list[dict[str, flint.fmpq]]:
    """A few rational points fixing every name of the field's ring."""
    return [{n: flint.fmpq(k + j, 2 * j + 3) for j, n in enumerate(f.ring.names)} for k in range(1, 9)]


def _at(q: Frac, point: Mapping[str, flint.fmpq]) -> flint.fmpq:
    try:
        return q.evaluate(point)
    except HKProofError:
        raise CertificateError("the stated point is a pole of the system: the certificate must give another "
                               "point") from None


def _darboux(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """Darboux polynomials P_j o f = K P_j with one stated cofactor K (Celledoni et al. 2019), exactly. A conclusion
    g(P) homogeneous of degree 0 in the P_j (checked with the P_j free: g(t p) = g(p)) is an integral, any g when
    K = 1; one of degree -1 with K = det Df (computed from the map) is a density: rho(f(x)) det Df(x) = rho(x)."""
    polys = [f.parse(t, where) for t in strings(step, "polynomials", where)]
    names = [check_name(n, "Darboux polynomial name") for n in strings(step, "names", where)]
    if not names or len(names) != len(polys) or len(set(names)) != len(names) or set(names) & {*f.ring.names, *known}:
        raise CertificateError(f"{where}: {len(polys)} Darboux polynomials need as many new distinct names")
    text = get(step, "cofactor", str, where)
    cofactor = f.jacobian() if text == DET_DF else f.parse(text, where)
    if cofactor.is_zero():
        raise CertificateError(f"{where}: the cofactor K must not be 0")
    for n, p in zip(names, polys, strict=True):
        if p.is_zero() or f.pull(p, 1) != cofactor * p:
            raise Refutation(f"{where}: {n}(f(x)) = K(x) {n}(x) fails for {n} = {str(p)[:200]}")
    local = dict(zip(names, polys, strict=True))
    scaled = Ring([*f.ring.names, *names, "_t"])
    t = Frac(scaled, scaled.gen("_t"))
    for degree, concluded in ((0, entries(step, "integrals", where)), (-1, entries(step, "densities", where, False))):
        if degree == -1 and concluded and cofactor != f.jacobian():
            raise Refutation(f"{where}: the cofactor is not det Df = {str(f.jacobian())[:200]}: no density")
        for entry in concluded if (degree, cofactor) != (0, Frac(f.ring, 1)) else []:
            text = get(entry, "from", str, where)
            f.parse_in(text, {**known, **local}, where)             # only proven names, eps and parameters
            g = read(scaled, text, where, {n: v.to_ring(scaled) for n, v in known.items()})
            if g.substitute({n: scaled.gen(n) * scaled.gen("_t") for n in names}) * t ** -degree != g:
                raise CertificateError(f"{where}: {text[:80]!r} is not homogeneous of degree {degree} in {names}")
    return local


def _degrees(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """deg f^n = d_n for n = 1..N: f^(n+1) = f^n o f composed exactly (each numerator and the denominator pulled back
    through f, brought to one power of Delta), the common gcd cancelled, the degree read in the phase variables."""
    stated = integers(step, "degrees", where)
    if not stated or not all(d >= 0 for d in stated):
        raise CertificateError(f"{where}: 'degrees' must be a non-empty list of non-negative integers")
    idx = [f.ring.index(v) for v in f.variables]
    polys = [*f.nums, f.delta]
    for n, d in enumerate(stated, 1):
        if n > 1:
            pulled = [f._compose(p, idx, f.nums, f.delta) for p in polys]
            top = max(e for _, e in pulled)
            polys = [q * f.delta ** (top - e) for q, e in pulled]
        common = polys[0]
        for p in polys[1:]:
            common = common.gcd(p)
        polys = [p / common for p in polys]
        degree = max(sum(m[k] for k in idx) for p in polys for m in p.monoms())
        if degree != d:
            raise Refutation(f"{where}: deg f^{n} = {degree}, the certificate says {d}")
    return {}


def _recipe_g(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """Recipe (G): D delta = sum_i lambda_i E_i in Q(x, eps, params)[x~] with delta = p(x~) q(x) - p(x) q(x~) for
    h = p/q, E_i the Kahan equations (rebuilt here; the stated generators must be them), D != 0 and every lambda_i
    free of x~ in its denominator. x~ -> f(x) is then a ring map to Q(x, eps, params) sending every E_i to 0, so
    D delta(x, f(x)) = 0: h o f = h, with q(f(x)) != 0 shown at a rational point."""
    h = f.parse(get(step, "function", str, where), where)
    names = [get(e, "name", str, where) for e in entries(step, "integrals", where)]
    tilde = [check_name(v, "name of x~") for v in strings(step, "tilde", where)]
    if len(names) != 1 or len(tilde) != len(f.variables) or len({*tilde, *f.ring.names}) != len(f.ring.names) + len(
            tilde):
        raise CertificateError(f"{where}: a recipe-g step concludes one integral and names one new x~ per variable")
    big, equations = f.equations(tilde)
    stated = [read(big, g, where) for g in strings(step, "generators", where)]
    cofactors = [read(big, c, where) for c in strings(step, "cofactors", where)]
    if len(stated) != len(equations) or len(cofactors) != len(equations):
        raise CertificateError(f"{where}: {len(equations)} generators and cofactors expected")
    for i, c in enumerate(cofactors, 1):
        if c.den_variables_in(tilde):
            raise CertificateError(f"{where}: the cofactor lambda_{i} has x~ in its denominator: recipe (G) needs "
                                   "cofactors polynomial in x~ (denominators in x, eps and the parameters only); "
                                   "with x~ in a denominator, D delta = sum lambda_i E_i holds for any h and proves "
                                   "nothing at x~ = f(x), where that denominator vanishes")
    if any(a != Frac(big, e) for a, e in zip(stated, equations, strict=True)):
        raise Refutation(f"{where}: the generators are not the Kahan equations x~ - x = 2 eps F(x, x~) of the field")
    multiplier = f.parse(get(step, "multiplier", str, where), where)
    if multiplier.is_zero():
        raise CertificateError(f"{where}: the multiplier D must not be 0")
    p, q = (Frac(f.ring, c).to_ring(big) for c in (h.num, h.den))
    to_y = {v: big.gen(y) for v, y in zip(f.variables, tilde, strict=True)}
    delta = p.substitute(to_y) * q - p * q.substitute(to_y)
    if sum((c * Frac(big, e) for c, e in zip(cofactors, equations, strict=True)), Frac(big, 0)) != \
            multiplier.to_ring(big) * delta:
        raise Refutation(f"{where}: D delta != sum lambda_i E_i")
    if not _nonzero_on_image(f, Frac(f.ring, h.den)):
        raise CertificateError(f"{where}: q(f(x)) vanishes at every trial point; give h with another denominator")
    return {names[0]: h}


def _nonzero_on_image(f: KahanData, q: Frac) -> bool:
    """q(f(x)) != 0 at one of a few rational points (which proves q o f is not identically 0)."""
    for point in _trial_points(f):
        delta = Frac(f.ring, f.delta).evaluate(point)
        if delta != 0:
            image = {v: Frac(f.ring, n).evaluate(point) / delta for v, n in zip(f.variables, f.nums, strict=True)}
            if q.evaluate({**point, **image}) != 0:
                return True
    return False


CARRIERS = {"reparametrization": reparametrization, "affine-change": _affine_change}
STEPS = {"substitution": _substitution, "prop-even": _prop_even, "darboux": _darboux, "recipe-g": _recipe_g,
          "degrees": _degrees}
