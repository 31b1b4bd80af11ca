"""The certificate checker: re-verifies a certificate file (docs/certificates.md) from the file alone.

It trusts python-flint (polynomial arithmetic, gcd, determinants over Q), hkproof's formula parser
(hkproof.algebra.formula) and the fraction type it returns (hkproof.algebra.fraction.Frac: lowest terms by a gcd,
parity in eps by eps -> -eps), and Prop. "prop: even" of the paper as a theorem. It imports nothing else of hkproof:
it rebuilds the Kahan map (and its equations, and det Df) from the field's right-hand sides by its own Cramer's rule,
and every identity it reports as verified is an exact polynomial identity it computed. Step kinds: substitution
(h o f = h), prop-even (Prop. "prop: even", one basis or several solved together), darboux (P o f = K P; integrals
and invariant densities from Darboux polynomials; a cofactor "det Df" is computed here), recipe-g
(D delta = sum lambda_i E_i), degrees (deg f^n by exact iterates) and reparametrization (integrals of another
field carried by a substitution of its parameters that sends its right-hand sides to this field's). What it cannot
check, it refuses (malformed, exit 2).

    verified   every step's identities hold exactly, and every claimed integral and density is concluded by a step
    refuted    a stated identity is false (h o f != h, a row not satisfied, a component not even, det = 0 at the point,
               P o f != K P, K != det Df for a density, D delta != sum lambda_i E_i, a degree of f^n differs)
    malformed  not a certificate this checker can read (format, version, convention, entries, step kind, scope)
"""
from __future__ import annotations

import json
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping, Sequence

import flint

from hkproof.algebra.formula import check_name, parse_formula, parse_rational, tokens
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring
from hkproof.errors import CertificateError, HKProofError

__all__ = ["check_document", "check_file", "CheckReport", "KahanData", "MAX_BYTES"]

FORMAT, VERSIONS, CONVENTION = "hkproof-certificate", (1, 2, 3, 4, 5), "eps = h/2"   # 2: darboux, recipe-g;
# 3: degrees; 4: prop-even with blocks (several bases solved together); 5: reparametrization
EPS = "eps"
DET_DF = "det Df"      # a darboux step's cofactor written as the Jacobian determinant the checker computes itself
MAX_BYTES = 200_000_000
Poly = flint.fmpz_mpoly


class _Refutation(Exception):
    """A stated identity is false (control flow inside the checker)."""


@dataclass
class CheckReport:
    """The verdict on a certificate file, with one line per step."""

    verdict: str                                   # "verified", "refuted" or "malformed"
    lines: list[str] = field(default_factory=list)
    seconds: float = 0.0

    def text(self) -> str:
        return "\n".join([f"{self.verdict} ({self.seconds:.3f} s)", *(f"  {line}" for line in self.lines)])


def check_file(path: str | Path) -> CheckReport:
    """Read a certificate file (JSON, numbers as strings) and check it."""
    start = time.perf_counter()
    try:
        raw = Path(path).read_bytes()
        if len(raw) > MAX_BYTES:
            raise CertificateError(f"{path} has {len(raw)} bytes; the checker reads at most {MAX_BYTES}")
        doc = json.loads(raw.decode("utf-8"), parse_float=_no_float, parse_constant=_no_float)
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        return CheckReport("malformed", [f"cannot read {path} as a JSON certificate: {exc}"],
                           time.perf_counter() - start)
    except CertificateError as exc:
        return CheckReport("malformed", [str(exc)], time.perf_counter() - start)
    return check_document(doc)


def check_document(doc: Any) -> CheckReport:
    """Check every step of a certificate (a decoded JSON object) in order; the first failing step decides."""
    start = time.perf_counter()
    report = CheckReport("verified")
    try:
        _check(doc, report)
    except _Refutation as exc:
        report.verdict = "refuted"
        report.lines.append(f"refuted: {exc}")
    except (HKProofError, ZeroDivisionError) as exc:
        report.verdict = "malformed"
        report.lines.append(f"malformed: {exc}")
    report.seconds = time.perf_counter() - start
    return report


def _no_float(text: str) -> None:
    raise CertificateError(f"the number {text} is written as a JSON float; certificates write numbers as exact text "
                           "('3/7')")


def _get(obj: Any, key: str, kind: type, where: str) -> Any:
    """obj[key] of the given JSON type, or a CertificateError naming the place."""
    if not isinstance(obj, dict) or key not in obj:
        raise CertificateError(f"{where}: the entry {key!r} is missing")
    value = obj[key]
    if not isinstance(value, kind) or isinstance(value, bool):
        raise CertificateError(f"{where}: {key!r} must be a JSON {kind.__name__}, got {type(value).__name__}")
    return value


def _strings(obj: Any, key: str, where: str) -> list[str]:
    values = _get(obj, key, list, where)
    if not all(isinstance(v, str) for v in values):
        raise CertificateError(f"{where}: every entry of {key!r} must be a string")
    return values


def _check(doc: Any, report: CheckReport) -> None:
    if _get(doc, "format", str, "certificate") != FORMAT:
        raise CertificateError(f"the format is {doc['format']!r}, not {FORMAT!r}")
    if _get(doc, "version", int, "certificate") not in VERSIONS:
        raise CertificateError(f"version {doc['version']} is not a version this checker reads {VERSIONS}")
    if _get(doc, "convention", str, "certificate") != CONVENTION:
        raise CertificateError(f"the step convention {doc['convention']!r} is not {CONVENTION!r}: this checker "
                               "rebuilds the Kahan map as x~ - x = 2 eps F(x, x~) only")
    fields = {k: KahanData(k, v) for k, v in _get(doc, "fields", dict, "certificate").items()}
    proven: dict[str, tuple[str, Frac]] = {}            # integral name -> (field key, value)
    densities: set[str] = set()
    steps = _get(doc, "steps", list, "certificate")
    if not steps:
        raise CertificateError("the certificate has no steps")
    for k, step in enumerate(steps, 1):
        where = f"step {k}"
        key = _get(step, "field", str, where)
        if key not in fields:
            raise CertificateError(f"{where}: no field {key!r} in 'fields'")
        kind = _get(step, "kind", str, where)
        if kind not in _KINDS:
            raise CertificateError(f"{where}: cannot check this step kind {kind!r} (this checker knows "
                                   f"{', '.join(sorted(_KINDS))})")
        if "densities" in step and kind != "darboux":
            raise CertificateError(f"{where}: only a darboux step concludes densities")
        f = fields[key]
        if kind == "reparametrization":
            source = _get(step, "source", str, where)
            if source not in fields or source == key:
                raise CertificateError(f"{where}: the source {source!r} must be another field of 'fields'")
            local = _reparametrization(f, fields[source], step, {n: v for n, (g, v) in proven.items() if g == source},
                                       where)
        else:
            local = _STEPS[kind](f, step, {n: v for n, (g, v) in proven.items() if g == key}, where)
        for entry in _get(step, "integrals", list, where):
            name, value = _conclude(f, entry, local, {**proven, **dict.fromkeys(densities)}, where,
                                    optional=kind == "reparametrization")
            proven[name] = (key, value)
        for entry in step.get("densities", []):
            name, _ = _conclude(f, entry, local, {**proven, **dict.fromkeys(densities)}, where)
            densities.add(name)
        concluded = [_get(e, "name", str, where) for e in [*step["integrals"], *step.get("densities", [])]]
        checked = (f"Darboux polynomials {', '.join(local)}; " if kind == "darboux" else
                   f"deg f^n = {step['degrees']}; " if kind == "degrees" else "")
        report.lines.append(f"{where} ({kind}, field {key}): verified; {checked}concludes {', '.join(concluded) or '-'}")
    claim = _get(doc, "claim", dict, "certificate")
    missing = [n for n in _strings(claim, "integrals", "claim") if n not in proven]
    missing += [n for n in (_strings(claim, "densities", "claim") if "densities" in claim else []) if n not in densities]
    if missing:
        raise CertificateError(f"the claim names integrals or densities no step concludes: {', '.join(missing)}")


def _conclude(f: KahanData, entry: Any, local: Mapping[str, Frac], proven: Mapping[str, object],
              where: str, optional: bool = False) -> tuple[str, Frac]:
    """An integral (or density) concluded by a step: `from`, a formula in the step's proven quantities (and eps,
    parameters), must equal `formula` exactly; where `optional`, a missing formula means the value of `from`."""
    name = check_name(_get(entry, "name", str, where), "integral name")
    if name in proven or name in f.ring.names:
        raise CertificateError(f"{where}: the integral name {name!r} is already taken")
    value = f.parse_in(_get(entry, "from", str, where), local, where)
    if optional and isinstance(entry, dict) and "formula" not in entry:
        return name, value
    formula = f.parse(_get(entry, "formula", str, where), where)
    if value != formula:
        raise _Refutation(f"{where}: {name} = {entry['from']} is not the stated formula")
    return name, formula


class KahanData:
    """A field read from a certificate and its Kahan map f = N / Delta, rebuilt by Cramer's rule on
    x~ - x = 2 eps F(x, x~), F(x, y) = 2 F((x + y)/2) - (F(x) + F(y))/2 (eq. "Kahan gen", eps = h/2)."""

    def __init__(self, key: str, data: Any):
        where = f"field {key}"
        self.variables = [check_name(v, "variable") for v in _strings(data, "variables", where)]
        self.parameters = [check_name(v, "parameter") for v in _strings(data, "parameters", where)]
        names = [*self.variables, EPS, *self.parameters]
        if len(set(names)) != len(names) or not self.variables:
            raise CertificateError(f"{where}: the variables, eps and the parameters must be distinct names")
        self.ring = Ring(names)
        self._rhs = rhs = [self.parse(t, where) for t in _strings(data, "rhs", where)]
        self._jacobian: Frac | None = None
        if len(rhs) != len(self.variables):
            raise CertificateError(f"{where}: {len(self.variables)} variables but {len(rhs)} right-hand sides")
        for v, g in zip(self.variables, rhs, strict=True):
            if EPS in g.variables() or g.den_variables_in(self.variables) or g.degrees_in(self.variables)[0] > 2:
                raise CertificateError(f"{where}: {v}' = {g} is not a quadratic polynomial in the phase variables "
                                       "free of eps")
        self.nums, self.delta = self._kahan()
        if self.delta.is_zero():
            raise CertificateError(f"{where}: the Kahan system is singular (det M = 0)")

    def parse(self, text: str, where: str) -> Frac:
        """A formula over the field's names, read exactly."""
        return _read(self.ring, text, where)

    def parse_in(self, text: str, known: Mapping[str, Frac], where: str) -> Frac:
        """A formula in the names `known`, eps and the parameters only (no phase variable directly)."""
        allowed = {EPS, *self.parameters, *known}
        for tok in tokens(text):
            if tok.kind == "name" and tok.text not in allowed:
                raise CertificateError(f"{where}: {tok.text!r} in {text[:80]!r} is neither an integral proven "
                                       "before nor eps nor a parameter")
        return _read(self.ring, text, where, known)

    def equations(self, tilde: Sequence[str]) -> tuple[Ring, list[Poly]]:
        """The Kahan equations E_i = d_i (y_i - x_i) - eps (4 g_i((x+y)/2) - g_i(x) - g_i(y)) for F_i = g_i/d_i, in
        Z[x, eps, params, y] with y named `tilde` (eq. "Kahan gen", eps = h/2)."""
        n, big = len(self.variables), Ring([*self.ring.names, *tilde])
        xs, ys = [big.gen(v) for v in self.variables], [big.gen(v) for v in tilde]
        z = flint.fmpz_mpoly_ctx.get((*self.ring.names, "_z"), "degrevlex")
        out = []
        for i, g in enumerate(self._rhs):
            num, den = (p.compose(*big.gens()[:len(self.ring.names)], ctx=big.ctx) for p in (g.num, g.den))
            hom = _homogenize(g.num, [self.ring.index(v) for v in self.variables], 2, z)
            mid = hom.compose(*[xs[k] + ys[k] if k < n else big.gens()[k] for k in range(len(self.ring.names))],
                              big.constant(2), ctx=big.ctx)
            at_y = big.substitute(num, dict(zip(self.variables, ys, strict=True)))
            out.append(den * (ys[i] - xs[i]) - big.gen(EPS) * (mid - num - at_y))
        return big, out

    def _kahan(self) -> tuple[list[Poly], Poly]:
        """(N_1..N_n, Delta) with f = N/Delta: the equations are linear in y = x~; Cramer's rule (fraction-free
        determinants)."""
        n = len(self.variables)
        big, equations = self.equations([f"{v}_y" for v in self.variables])
        rows = [[self._down(big, e.derivative(big.index(f"{v}_y"))) for v in self.variables] for e in equations]
        rhs_b = [-self._down(big, e) for e in equations]
        delta = _det(rows)
        nums = [_det([[rhs_b[r] if c == j else rows[r][c] for c in range(n)] for r in range(n)]) for j in range(n)]
        return nums, delta

    def jacobian(self) -> Frac:
        """det Df from the map itself (computed once): Df = (Delta dN - N grad(Delta)^T) / Delta^2, and
        det(Delta J - u v^T) = Delta^(n-1) det [[Delta, v^T], [u, J]] (Schur complement), so
        det Df = det [[Delta, grad(Delta)^T], [N, dN]] / Delta^(n+1): one bordered determinant of the small entries."""
        if self._jacobian is None:
            idx = [self.ring.index(v) for v in self.variables]
            rows = [[self.delta, *(self.delta.derivative(k) for k in idx)],
                    *([p, *(p.derivative(k) for k in idx)] for p in self.nums)]
            self._jacobian = Frac(self.ring, _det(rows), self.delta ** (len(idx) + 1))
        return self._jacobian

    def _down(self, big: Ring, p: Poly) -> Poly:
        """p with y = 0, in the field's ring."""
        return big.substitute(p, {f"{v}_y": 0 for v in self.variables}, self.ring)

    def image(self, i: int) -> tuple[list[Poly], Poly]:
        """f^i = (N, Delta) for i in {-1, 1} (f^-1(x, eps) = f(x, -eps)); the identity for i = 0."""
        if i == 0:
            return [self.ring.gen(v) for v in self.variables], self.ring.constant(1)
        if i == 1:
            return self.nums, self.delta
        flip = {EPS: -self.ring.gen(EPS)}
        return [self.ring.substitute(p, flip) for p in self.nums], self.ring.substitute(self.delta, flip)

    def pull(self, h: Frac, i: int) -> Frac:
        """h o f^i, exactly."""
        nums, delta = self.image(i)
        idx = [self.ring.index(v) for v in self.variables]
        (pn, dn), (pd, dd) = (self._compose(p, idx, nums, delta) for p in (h.num, h.den))
        if pd.is_zero():
            raise _Refutation(f"the denominator of {h} vanishes on the image of the Kahan map")
        return Frac(self.ring, pn * delta ** max(dd - dn, 0), pd * delta ** max(dn - dd, 0))

    def _compose(self, p: Poly, idx: list[int], nums: list[Poly], delta: Poly) -> tuple[Poly, int]:
        """(p(N/Delta) Delta^d, d), d the degree of p in the phase variables: one compose of p homogenized."""
        d = max((sum(m[k] for k in idx) for m in p.monoms()), default=0)
        z = flint.fmpz_mpoly_ctx.get((*self.ring.names, "_z"), "degrevlex")
        args = list(self.ring.gens())
        for k, image in zip(idx, nums, strict=True):
            args[k] = image
        return _homogenize(p, idx, d, z).compose(*args, delta, ctx=self.ring.ctx), d


def _read(ring: Ring, text: str, where: str, known: Mapping[str, Frac] | None = None) -> Frac:
    """A formula over `ring` (names in `known` stand for their values), read exactly; a CertificateError otherwise."""
    try:
        return parse_formula(ring, text, known)
    except HKProofError as exc:
        raise CertificateError(f"{where}: {exc}") from None


def _homogenize(p: Poly, idx: list[int], d: int, ctx: flint.fmpz_mpoly_ctx) -> Poly:
    """p with the extra last variable z making every term of degree d in the variables `idx` (and z)."""
    return ctx.from_dict({(*m, d - sum(m[k] for k in idx)): c for m, c in p.to_dict().items()})


def _det(matrix: list[list[Poly]]) -> Poly:
    """The determinant of a square polynomial matrix by Laplace expansion, row by row from the bottom, each minor of
    the last rows (keyed by its columns) computed once: no division, products of the matrix's own entries."""
    n = len(matrix)
    zero = matrix[0][0] - matrix[0][0]
    minors: dict[tuple[int, ...], Poly] = {(): zero + 1}
    for row in reversed(matrix):
        grown: dict[tuple[int, ...], Poly] = {}
        for cols, sub in minors.items():
            for j in range(n):
                if j in cols or row[j].is_zero():
                    continue
                key = tuple(sorted((*cols, j)))
                term = row[j] * sub
                grown[key] = grown.get(key, zero) + (-term if sum(c < j for c in cols) % 2 else term)
        minors = grown
    return minors.get(tuple(range(n)), zero)


def _substitution(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """h o f - h = 0 (sec. 3): h(N/Delta) Delta^d over a common denominator, compared exactly."""
    h = f.parse(_get(step, "function", str, where), where)
    names = [_get(e, "name", str, where) for e in _get(step, "integrals", list, where)]
    if len(names) != 1:
        raise CertificateError(f"{where}: a substitution step concludes exactly one integral")
    if f.pull(h, 1) != h:
        raise _Refutation(f"{where}: h(f(x)) - h(x) is not 0 for h = {str(h)[:200]}")
    return {names[0]: h}


def _prop_even(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """Prop. "prop: even" for one basis, or for several solved together ("blocks": the unknowns of the bases form one
    vector, block after block): (1) det != 0 at a rational point, (2) basis functions even in eps, rows i in a
    non-symmetric range of {-1, 0, 1} containing 0, relation data even in eps and written in integrals proven before,
    (3) every component even in eps, (4) every row and relation satisfied exactly. Then the components are
    integrals."""
    raw = _get(step, "blocks", list, where) if "blocks" in step else [step]
    blocks = [([f.parse(t, where) for t in _strings(b, "basis", where)], f.parse(_get(b, "target", str, where), where))
              for b in raw]
    width = sum(len(basis) for basis, _ in blocks)
    names = [check_name(n, "component name") for n in _strings(step, "names", where)]
    solution = [f.parse(t, where) for t in _strings(step, "solution", where)]
    iterates = _get(step, "iterates", list, where)
    if sorted(iterates) not in ([0, 1], [-1, 0]):
        raise CertificateError(f"{where}: iterates {iterates}: this checker takes rows i in {{0, 1}} or {{-1, 0}}")
    if not blocks or not all(phi.is_even_in(EPS) for basis, target in blocks for phi in (*basis, target)):
        raise CertificateError(f"{where}: Prop. \"prop: even\" needs basis functions even in eps")
    if len(names) != width or len(solution) != width or set(names) & {*f.ring.names, *known}:
        raise CertificateError(f"{where}: {width} basis functions need as many new component names and values")
    scope, rows = dict(known), []
    for k, rel in enumerate(_get(step, "relations", list, where)):
        uses = _strings(rel, "uses", where)
        if any(u not in known and not (u.startswith("_l") and u[2:].isdigit() and int(u[2:]) < k) for u in uses):
            raise CertificateError(f"{where}: relation {k + 1} uses {uses}, not all proven before it")
        coefficients = [f.parse_in(t, scope, where) for t in _strings(rel, "coefficients", where)]
        rhs = f.parse_in(_get(rel, "rhs", str, where), scope, where)
        if len(coefficients) != width:
            raise CertificateError(f"{where}: relation {k + 1} has {len(coefficients)} coefficients, not {width}")
        if not all(c.is_even_in(EPS) for c in (*coefficients, rhs)):
            raise _Refutation(f"{where}: relation {k + 1} has a coefficient or right-hand side not even in eps")
        scope[f"_l{k}"] = rhs
        rows.append((coefficients, rhs))
    if len(blocks) * len(iterates) + len(rows) < width:
        raise CertificateError(f"{where}: {len(blocks) * len(iterates)} rows and {len(rows)} relations for {width} "
                               "unknowns: the system must determine them")
    point = {n: parse_rational(_get(_get(step, "point", dict, where), n, str, where)) for n in f.ring.names}
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
        raise _Refutation(f"{where}: the system does not have full rank at the stated point")
    for n, a in zip(names, solution, strict=True):
        if not a.is_even_in(EPS):
            raise _Refutation(f"{where}: the component {n} is not even in eps")
    for b, (start, pulled) in enumerate(moved, 1):
        for i in iterates:
            row = pulled[i]
            part = solution[start:start + len(row) - 1]
            if sum((a * m for a, m in zip(part, row[:-1], strict=True)), Frac(f.ring, 0)) != row[-1]:
                raise _Refutation(f"{where}: the row i = {i} of block {b} is not satisfied by the solution")
    for k, (coefficients, rhs) in enumerate(rows, 1):
        if sum((c * a for c, a in zip(coefficients, solution, strict=True)), Frac(f.ring, 0)) != rhs:
            raise _Refutation(f"{where}: the relation {k} is not satisfied by the solution")
    return dict(zip(names, solution, strict=True))


def _reparametrization(f: KahanData, source: KahanData, step: Any, known: Mapping[str, Frac],
                       where: str) -> dict[str, Frac]:
    """Integrals of the source field carried to this field by sigma: b -> b(a), the source parameters as polynomials
    with integer coefficients in this field's parameters (x and eps fixed). If the images are algebraically
    independent (a Jacobian of full rank at a rational point) sigma is an embedding of Q(x, eps, b) into Q(x, eps, a);
    if it sends every source right-hand side to this field's, it sends the source's Kahan map to this one (Cramer's
    rule commutes with it), so it sends each identity I(f(x)) = I(x) to sigma(I)(f(x)) = sigma(I)(x)."""
    if source.variables != f.variables:
        raise CertificateError(f"{where}: the source field has the variables {source.variables}, not {f.variables}")
    images_text = _get(step, "parameters", dict, where)
    if sorted(images_text) != sorted(source.parameters):
        raise CertificateError(f"{where}: 'parameters' must give an image for each source parameter "
                               f"{source.parameters}")
    images = {b: f.parse(_get(images_text, b, str, where), where) for b in source.parameters}
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
            raise _Refutation(f"{where}: the substitution does not carry the source's {v}' = {g} to {v}' = {h}")
    return {n: h.substitute(sigma, f.ring) for n, h in known.items()}


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
    polys = [f.parse(t, where) for t in _strings(step, "polynomials", where)]
    names = [check_name(n, "Darboux polynomial name") for n in _strings(step, "names", where)]
    if not names or len(names) != len(polys) or len(set(names)) != len(names) or set(names) & {*f.ring.names, *known}:
        raise CertificateError(f"{where}: {len(polys)} Darboux polynomials need as many new distinct names")
    text = _get(step, "cofactor", str, where)
    cofactor = f.jacobian() if text == DET_DF else f.parse(text, where)
    for n, p in zip(names, polys, strict=True):
        if p.is_zero() or f.pull(p, 1) != cofactor * p:
            raise _Refutation(f"{where}: {n}(f(x)) = K(x) {n}(x) fails for {n} = {str(p)[:200]}")
    local = dict(zip(names, polys, strict=True))
    scaled = Ring([*f.ring.names, *names, "_t"])
    t = Frac(scaled, scaled.gen("_t"))
    for degree, entries in ((0, _get(step, "integrals", list, where)), (-1, step.get("densities", []))):
        if degree == -1 and entries and cofactor != f.jacobian():
            raise _Refutation(f"{where}: the cofactor is not det Df = {str(f.jacobian())[:200]}: no density")
        for entry in entries if (degree, cofactor) != (0, Frac(f.ring, 1)) else []:
            text = _get(entry, "from", str, where)
            f.parse_in(text, {**known, **local}, where)             # only proven names, eps and parameters
            g = _read(scaled, text, where, {n: v.to_ring(scaled) for n, v in known.items()})
            if g.substitute({n: scaled.gen(n) * scaled.gen("_t") for n in names}) * t ** -degree != g:
                raise CertificateError(f"{where}: {text[:80]!r} is not homogeneous of degree {degree} in {names}")
    return local


def _degrees(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """deg f^n = d_n for n = 1..N: f^(n+1) = f^n o f composed exactly (each numerator and the denominator pulled back
    through f, brought to one power of Delta), the common gcd cancelled, the degree read in the phase variables."""
    stated = _get(step, "degrees", list, where)
    if not stated or not all(isinstance(d, int) and not isinstance(d, bool) and d >= 0 for d in stated):
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
            raise _Refutation(f"{where}: deg f^{n} = {degree}, the certificate says {d}")
    return {}


def _recipe_g(f: KahanData, step: Any, known: Mapping[str, Frac], where: str) -> dict[str, Frac]:
    """Recipe (G): D delta = sum_i lambda_i E_i in Q[x, eps, params, x~] with delta = p(x~) q(x) - p(x) q(x~) for
    h = p/q, E_i the Kahan equations (rebuilt here; the stated generators must be them) and D != 0 free of x~. At
    x~ = f(x) every E_i vanishes, so delta(x, f(x)) = 0: h o f = h, with q(f(x)) != 0 shown at a rational point."""
    h = f.parse(_get(step, "function", str, where), where)
    names = [_get(e, "name", str, where) for e in _get(step, "integrals", list, where)]
    tilde = [check_name(v, "name of x~") for v in _strings(step, "tilde", where)]
    if len(names) != 1 or len(tilde) != len(f.variables) or len({*tilde, *f.ring.names}) != len(f.ring.names) + len(
            tilde):
        raise CertificateError(f"{where}: a recipe-g step concludes one integral and names one new x~ per variable")
    big, equations = f.equations(tilde)
    stated = [_read(big, g, where) for g in _strings(step, "generators", where)]
    cofactors = [_read(big, c, where) for c in _strings(step, "cofactors", where)]
    if len(stated) != len(equations) or len(cofactors) != len(equations):
        raise CertificateError(f"{where}: {len(equations)} generators and cofactors expected")
    if any(a != Frac(big, e) for a, e in zip(stated, equations, strict=True)):
        raise _Refutation(f"{where}: the generators are not the Kahan equations x~ - x = 2 eps F(x, x~) of the field")
    multiplier = f.parse(_get(step, "multiplier", str, where), where)
    if multiplier.is_zero():
        raise CertificateError(f"{where}: the multiplier D must not be 0")
    p, q = (Frac(f.ring, c).to_ring(big) for c in (h.num, h.den))
    to_y = {v: big.gen(y) for v, y in zip(f.variables, tilde, strict=True)}
    delta = p.substitute(to_y) * q - p * q.substitute(to_y)
    if sum((c * Frac(big, e) for c, e in zip(cofactors, equations, strict=True)), Frac(big, 0)) != \
            multiplier.to_ring(big) * delta:
        raise _Refutation(f"{where}: D delta != sum lambda_i E_i")
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


_STEPS = {"substitution": _substitution, "prop-even": _prop_even, "darboux": _darboux, "recipe-g": _recipe_g,
          "degrees": _degrees}
_KINDS = (*_STEPS, "reparametrization")      # a reparametrization step reads two fields (_reparametrization)
