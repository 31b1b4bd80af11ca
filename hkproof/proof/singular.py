"""A certificate's substitution, darboux, recipe-g and bivector steps as a Singular script: a second computer algebra
system rebuilds the Kahan map and its equations from the field and re-checks h o f - h = 0, P o f = K P (for densities
K = det Df), D delta = sum lambda_i E_i, Pi(f(x)) = Df Pi(x) Df^T, [Pi_a, Pi_b] = 0, Pi grad C = 0 and {I, J} = 0 on
its own, every identity with its denominators cleared (docs/certificates.md, "A second opinion")."""
from __future__ import annotations

import itertools
from typing import Mapping, Sequence

import flint

from hkproof.algebra.formula import parse_formula
from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import lcm
from hkproof.algebra.ring import Ring, get_ring
from hkproof.checker import DET_DF
from hkproof.errors import CertificateError

__all__ = ["singular_script"]

_PULLBACK = """proc hkPullback(poly p, ideal hkN, poly hkD, int n)
{
  // p(N/D) * D^d with d the degree of p in the first n ring variables; returns list(p(N/D) D^d, d)
  int d = 0; int s; int k; intvec e; poly q = p; poly t; poly c; poly m; poly out = 0;
  while (q != 0) { e = leadexp(q); s = 0; for (k = 1; k <= n; k++) { s = s + e[k]; } if (s > d) { d = s; }
                   q = q - lead(q); }
  q = p;
  while (q != 0) {
    t = lead(q); e = leadexp(q); s = 0; c = t;
    for (k = 1; k <= n; k++) { c = subst(c, var(k), 1); s = s + e[k]; }
    m = c * hkD^(d - s);
    for (k = 1; k <= n; k++) { m = m * hkN[k]^e[k]; }
    out = out + m; q = q - t;
  }
  return(list(out, d));
}
proc hkSchouten(matrix A, poly La, matrix B, poly Lb, int n)
{
  // 1 iff La^2 Lb^2 [A/La, B/Lb]^ijk = 0 for all i < j < k: the cyclic sum over (i, j, k) of
  // sum_l (A/La)^il d_l (B/Lb)^jk + (B/Lb)^il d_l (A/La)^jk, cleared of denominators
  int i; int j; int k; int c; int l; int r; int s; int t; intvec v; poly q;
  for (i = 1; i <= n; i++) { for (j = i + 1; j <= n; j++) { for (k = j + 1; k <= n; k++) {
    v = i, j, k; q = 0;
    for (c = 0; c < 3; c++) {
      r = v[c mod 3 + 1]; s = v[(c + 1) mod 3 + 1]; t = v[(c + 2) mod 3 + 1];
      for (l = 1; l <= n; l++) {
        q = q + La * A[r, l] * (Lb * diff(B[s, t], var(l)) - B[s, t] * diff(Lb, var(l)))
              + Lb * B[r, l] * (La * diff(A[s, t], var(l)) - A[s, t] * diff(La, var(l)));
      }
    }
    if (q != 0) { return(0); }
  } } }
  return(1);
}
proc hkGrad(poly P, poly R, int n)
{
  // R^2 grad(P/R) = R grad P - P grad R as an n x 1 matrix
  matrix G[n][1]; int j;
  for (j = 1; j <= n; j++) { G[j, 1] = R * diff(P, var(j)) - P * diff(R, var(j)); }
  return(G);
}
"""


def singular_script(doc: Mapping) -> str:
    """A Singular script that prints 'verified: step k ...' (or 'refuted: step k ...') for each substitution, darboux,
    recipe-g, bivector-invariance, jacobi, casimir and involution step of a checked certificate; other step kinds are
    listed as not exported."""
    lines = ["// hkproof certificate re-checked in Singular: the Kahan map x~ - x = 2 eps F(x, x~) (eps = h/2) by",
             "// Cramer's rule, then h(N/Delta) Delta^d compared with h over a common denominator.", _PULLBACK,
             "int i; int j; int hkOk;"]
    for k, step in enumerate(doc["steps"], 1):
        kind = step["kind"]
        if kind not in _STEPS:
            why = f": {_WHY[kind]}" if kind in _WHY else ""
            lines.append(f'"step {k} ({kind}): not exported{why}";')
            continue
        field = doc["fields"][step["field"]]
        before = [s for s in doc["steps"][:k - 1] if s["field"] == step["field"]]
        ring, head = (_ring if kind in _MAPLESS else _kahan_map)(k, field)
        lines += head + _STEPS[kind](k, ring, field, step, before) + [f"kill hkR{k};"]
    lines.append("quit;")
    return "\n".join(lines) + "\n"


def _ring(k: int, field: Mapping) -> tuple[Ring, list[str]]:
    """The ring hkR<k> of step k: the phase variables, their tildes hkY<i> and eps over Q(parameters)."""
    xs, params = list(field["variables"]), list(field["parameters"])
    ys = [f"hkY{i + 1}" for i in range(len(xs))]
    ring = get_ring(tuple(xs) + ("eps",) + tuple(params))
    if set(ys) & set(ring.names):
        raise CertificateError(f"the names {sorted(set(ys) & set(ring.names))} are taken by the script")
    coefficients = f"(0, {', '.join(params)})" if params else "0"
    return ring, [f"ring hkR{k} = {coefficients}, ({', '.join(xs + ys)}, eps), dp;"]


def _kahan_map(k: int, field: Mapping) -> tuple[Ring, list[str]]:
    """The ring of step k and the Kahan map N/hkD in it, by Cramer's rule on the equations."""
    xs = list(field["variables"])
    ys = [f"hkY{i + 1}" for i in range(len(xs))]
    ring, out = _ring(k, field)
    n = len(xs)
    out += [f"map hkMid = hkR{k}, {', '.join(f'({x} + {y})/2' for x, y in zip(xs, ys))}, {', '.join(ys)}, eps;",
            f"map hkToY = hkR{k}, {', '.join(ys)}, {', '.join(ys)}, eps;",
            f"ideal hkF = {', '.join(_text(ring, t) for t in field['rhs'])};",
            "ideal hkFm = hkMid(hkF); ideal hkFy = hkToY(hkF);",
            f"matrix hkM[{n}][{n}]; ideal hkB; poly hkE;",
            f"for (i = 1; i <= {n}; i++) {{",
            f"  hkE = var({n} + i) - var(i) - 2*eps*(2*hkFm[i] - (hkF[i] + hkFy[i])/2);",
            f"  for (j = 1; j <= {n}; j++) {{ hkM[i, j] = diff(hkE, var({n} + j)); }}",
            f"  hkB[i] = -subst(hkE, {', '.join(f'{y}, 0' for y in ys)});",
            "}",
            "poly hkD = det(hkM); ideal hkN; matrix hkC;",
            f"for (j = 1; j <= {n}; j++) {{ hkC = hkM; for (i = 1; i <= {n}; i++) {{ hkC[i, j] = hkB[i]; }}"
            " hkN[j] = det(hkC); }"]
    return ring, out


def _pulled(ring: Ring, text: str, n: int) -> list[str]:
    """h = hkP/hkQ and the lists hkA = (hkP(N/D) D^a, a), hkBq = (hkQ(N/D) D^b, b) (declared by the step)."""
    h = parse_formula(ring, text)
    return [f"hkP = {_poly(h.num)}; hkQ = {_poly(h.den)};",
            f"hkA = hkPullback(hkP, hkN, hkD, {n}); hkBq = hkPullback(hkQ, hkN, hkD, {n});"]


def _substitution(k: int, ring: Ring, field: Mapping, step: Mapping, _before: Sequence[Mapping]) -> list[str]:
    """h(N/D) D^a D^b Q = P Q(N/D) D^b D^a: h o f = h."""
    n = len(field["variables"])
    name = step["integrals"][0]["name"]
    return [_DECLARE, *_pulled(ring, step["function"], n),
            "poly hkDiff = hkA[1] * hkD^hkBq[2] * hkQ - hkP * hkBq[1] * hkD^hkA[2];",
            f'if (hkD != 0 && hkBq[1] != 0 && hkDiff == 0) {{ "verified: step {k}, {name} o f = {name}"; }}',
            f'else {{ "refuted: step {k}, {name} o f - {name} is not 0"; }}']


def _darboux(k: int, ring: Ring, field: Mapping, step: Mapping, _before: Sequence[Mapping]) -> list[str]:
    """P_j(N/D) D^b Q_j K_den = K_num P_j Q_j(N/D) D^a for P_j = hkP/hkQ and K = K_num/K_den; with densities also
    K_num D^(2n) = K_den det(D dN_i/dx_j - N_i dD/dx_j) (K = det Df); a cofactor written "det Df" is that
    determinant over D^(2n)."""
    n = len(field["variables"])
    jacobian = _jacobian(n)
    if step["cofactor"] == DET_DF:
        out = [_DECLARE, *jacobian, f"poly hkKn = det(hkJ); poly hkKd = hkD^{2 * n}; hkOk = (hkD != 0);"]
    else:
        cofactor = parse_formula(ring, step["cofactor"])
        out = [_DECLARE, f"poly hkKn = {_poly(cofactor.num)}; poly hkKd = {_poly(cofactor.den)}; hkOk = (hkD != 0);"]
        if step.get("densities"):
            out += [*jacobian, f"hkOk = hkOk && (hkKn * hkD^{2 * n} - hkKd * det(hkJ) == 0);"]
    for text in step["polynomials"]:
        out += [*_pulled(ring, text, n),
                "hkOk = hkOk && (hkA[1] * hkD^hkBq[2] * hkQ * hkKd - hkKn * hkP * hkBq[1] * hkD^hkA[2] == 0);"]
    what = ", ".join(step["names"]) + " o f = K " + ", ".join(step["names"]) + (", K = det Df" if step.get(
        "densities") else "")
    return [*out, _verdict(k, what)]


def _recipe_g(k: int, ring: Ring, field: Mapping, step: Mapping, _before: Sequence[Mapping]) -> list[str]:
    """L D (p(x~) q(x) - p(x) q(x~)) = sum_i (L lambda_i) E_i with Singular's own Kahan equations E_i = d_i (x~_i - x_i
    - 2 eps F_i(x, x~)) (d_i the denominator of F_i, as the checker writes them), L the lcm of the denominators of the
    cofactors and of D (free of x~, which the checker requires), and q(f(x)) != 0."""
    n = len(field["variables"])
    ys = [f"hkY{i + 1}" for i in range(n)]
    stated, target = get_ring((*ring.names, *step["tilde"])), get_ring((*ring.names, *ys))
    cofactors = [parse_formula(stated, t) for t in step["cofactors"]]
    moved = [(c.num.compose(*target.gens(), ctx=target.ctx), c.den.compose(*target.gens(), ctx=target.ctx))
             for c in cofactors]
    multiplier = parse_formula(ring, step["multiplier"])
    big = [(multiplier.num.compose(*target.gens()[:len(ring.names)], ctx=target.ctx),
            multiplier.den.compose(*target.gens()[:len(ring.names)], ctx=target.ctx)), *moved]
    common = lcm([den for _, den in big])
    (d_num, d_den), lams = big[0], [num * (common / den) for num, den in moved]
    scales = [_poly(parse_formula(ring, t).den) for t in field["rhs"]]
    name = step["integrals"][0]["name"]
    return [_DECLARE, *_pulled(ring, step["function"], n), "ideal hkEg; poly hkS = 0;",
            *(f"hkEg[{i + 1}] = ({d}) * (var({n + i + 1}) - var({i + 1}) - 2*eps*(2*hkFm[{i + 1}] - (hkF[{i + 1}] + "
              f"hkFy[{i + 1}])/2));" for i, d in enumerate(scales)),
            *(f"hkS = hkS + ({_poly(lam)}) * hkEg[{i + 1}];" for i, lam in enumerate(lams)),
            f"poly hkLD = {_poly(d_num * (common / d_den))};",
            "poly hkDiff = hkLD * (hkToY(hkP) * hkQ - hkP * hkToY(hkQ)) - hkS;",
            f'if (hkD != 0 && hkLD != 0 && hkBq[1] != 0 && hkDiff == 0) {{ "verified: step {k}, D delta = sum '
            f'lambda_i E_i, so {name} o f = {name}"; }}',
            f'else {{ "refuted: step {k}, D delta - sum lambda_i E_i is not 0"; }}']


def _jacobian(n: int) -> list[str]:
    """hkJ = D^2 Df = D dN_i/dx_j - N_i dD/dx_j, from the script's own map."""
    return [f"matrix hkJ[{n}][{n}];",
            f"for (i = 1; i <= {n}; i++) {{ for (j = 1; j <= {n}; j++) {{"
            " hkJ[i, j] = hkD * diff(hkN[i], var(j)) - hkN[i] * diff(hkD, var(j)); } }"]


def _bivector(ring: Ring, tag: str, matrix: Sequence[Sequence[str]]) -> list[str]:
    """Pi = hkPi<tag> / hkL<tag>: the stated matrix, its entries brought over the lcm of their denominators."""
    entries = [[parse_formula(ring, t) for t in row] for row in matrix]
    common = lcm([e.den for row in entries for e in row])
    n = len(entries)
    cleared = ", ".join(_poly(e.num * (common / e.den)) for row in entries for e in row)
    return [f"matrix hkPi{tag}[{n}][{n}] = {cleared}; poly hkL{tag} = {_poly(common)};"]


def _stated(before: Sequence[Mapping], name: str) -> Sequence[Sequence[str]]:
    """The matrix of the bivector `name`, from the bivector-invariance step of the same field that states it."""
    for step in before:
        if step["kind"] == "bivector-invariance" and step["name"] == name:
            return step["matrix"]
    raise CertificateError(f"no earlier bivector-invariance step of this field states {name!r}")


def _functions(ring: Ring, step: Mapping, before: Sequence[Mapping]) -> list[tuple[str, Frac]]:
    """The step's functions, integral names replaced by the formulas the earlier steps of the field state for them."""
    known = {e["name"]: parse_formula(ring, e["formula"]) for s in before for e in s.get("integrals", [])
             if "formula" in e}
    return [(text, parse_formula(ring, text, known)) for text in step["functions"]]


def _gradients(ring: Ring, step: Mapping, before: Sequence[Mapping], n: int) -> tuple[list[str], list[str]]:
    """The texts of the step's functions C = P/R and the lines setting hkGs[m] = R grad P - P grad R (R^2 grad C),
    each required not 0 (C depends on x)."""
    found = _functions(ring, step, before)
    lines = ["list hkGs; hkOk = 1;",
             *(f"hkGs[{m}] = hkGrad({_poly(c.num)}, {_poly(c.den)}, {n}); hkOk = hkOk && size(ideal(hkGs[{m}])) > 0;"
               for m, (_, c) in enumerate(found, 1))]
    return [text[:80] for text, _ in found], lines


def _invariance(k: int, ring: Ring, field: Mapping, step: Mapping, _before: Sequence[Mapping]) -> list[str]:
    """Pi = Q/L antisymmetric and not 0, and Pi_ij(f(x)) = (J Q J^T)_ij / (L D^4) for i < j (Df = J/D^2), cleared:
    A D^b L D^4 = (J Q J^T)_ij B D^a with (A, a), (B, b) the pullbacks of Q_ij and L, B != 0."""
    n, name = len(field["variables"]), step["name"]
    return [_DECLARE, *_bivector(ring, "1", step["matrix"]), *_jacobian(n),
            "matrix hkW = hkJ * hkPi1 * transpose(hkJ);",
            f"hkBq = hkPullback(hkL1, hkN, hkD, {n});",
            "hkOk = hkD != 0 && hkBq[1] != 0 && size(ideal(hkPi1)) > 0 && size(ideal(hkPi1 + transpose(hkPi1))) == 0;",
            f"for (i = 1; i <= {n}; i++) {{ for (j = i + 1; j <= {n}; j++) {{",
            f"  hkA = hkPullback(hkPi1[i, j], hkN, hkD, {n});",
            "  hkOk = hkOk && (hkA[1] * hkD^hkBq[2] * hkL1 * hkD^4 - hkW[i, j] * hkBq[1] * hkD^hkA[2] == 0); } }",
            _verdict(k, f"{name}(f(x)) = Df {name}(x) Df^T")]


def _jacobi(k: int, ring: Ring, field: Mapping, step: Mapping, before: Sequence[Mapping]) -> list[str]:
    """[Pi_a, Pi_b] = 0 (a = b: Pi_a is Poisson), by the script's own Schouten bracket of the stated matrices."""
    a, b = step["bivectors"][0], step["bivectors"][-1]
    what = f"[{a}, {b}] = 0" + (f" ({a} is Poisson)" if a == b else f" ({a} and {b} are compatible)")
    return [*_bivector(ring, "1", _stated(before, a)), *_bivector(ring, "2", _stated(before, b)),
            f"hkOk = hkSchouten(hkPi1, hkL1, hkPi2, hkL2, {len(field['variables'])});", _verdict(k, what)]


def _casimir(k: int, ring: Ring, field: Mapping, step: Mapping, before: Sequence[Mapping]) -> list[str]:
    """Q G_C = 0 for each function C = P/R, G_C = R grad P - P grad R != 0, Pi = Q/L."""
    name = step["bivector"]
    texts, grads = _gradients(ring, step, before, len(field["variables"]))
    return [*_bivector(ring, "1", _stated(before, name)), *grads,
            *(f"hkOk = hkOk && size(ideal(hkPi1 * hkGs[{m}])) == 0;" for m in range(1, len(texts) + 1)),
            _verdict(k, f"{name} grad C = 0 for C in {', '.join(texts)}")]


def _involution(k: int, ring: Ring, field: Mapping, step: Mapping, before: Sequence[Mapping]) -> list[str]:
    """G_I^T Q G_J = 0 for every pair of the functions, G = R grad P - P grad R != 0 for each P/R, Pi = Q/L."""
    name = step["bivector"]
    texts, grads = _gradients(ring, step, before, len(field["variables"]))
    return [*_bivector(ring, "1", _stated(before, name)), *grads,
            *(f"hkOk = hkOk && (transpose(hkGs[{s}]) * hkPi1 * hkGs[{t}])[1, 1] == 0;"
              for s, t in itertools.combinations(range(1, len(texts) + 1), 2)),
            _verdict(k, f"{{I, J}} = 0 for {name}, I, J in {', '.join(texts)}")]


def _verdict(k: int, what: str) -> str:
    """The line that prints 'verified: step k, what' if hkOk, else 'refuted: step k, what fails'."""
    return f'if (hkOk) {{ "verified: step {k}, {what}"; }} else {{ "refuted: step {k}, {what} fails"; }}'


_DECLARE = "poly hkP; poly hkQ; list hkA; list hkBq;"
_STEPS = {"substitution": _substitution, "darboux": _darboux, "recipe-g": _recipe_g,
          "bivector-invariance": _invariance, "jacobi": _jacobi, "casimir": _casimir, "involution": _involution}
_MAPLESS = {"jacobi", "casimir", "involution"}      # identities of the bivectors alone: no Kahan map in the script
_WHY = {"exclusion": "a rank mod p of many rows that hkproof check recomputes itself from the field",
        "no-poisson": "a kernel mod p of many rows and its Schouten bracket, which hkproof check recomputes itself",
        "nambu": "universal identities hkproof check expands itself, applied by the chain rule to the integrals and the "
                 "density proven by the steps before it (Byrnes, Haggar, Quispel)"}


def _text(ring: Ring, text: str) -> str:
    """A right-hand side as Singular text: (numerator)/(denominator), powers with ^."""
    q = parse_formula(ring, text)
    return f"({_poly(q.num)})/({_poly(q.den)})"


def _poly(p: flint.fmpz_mpoly) -> str:
    return str(p) or "0"
