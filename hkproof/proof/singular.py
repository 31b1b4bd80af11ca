"""A certificate's substitution, darboux and recipe-g steps as a Singular script: a second computer algebra system
rebuilds the Kahan map and its equations from the field and re-checks h o f - h = 0, P o f = K P (for densities
K = det Df) and D delta = sum lambda_i E_i on its own (docs/certificates.md, "A second opinion")."""
from __future__ import annotations

from typing import Mapping

import flint

from hkproof.algebra.formula import parse_formula
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
"""


def singular_script(doc: Mapping) -> str:
    """A Singular script that prints 'verified: step k ...' (or 'refuted: step k ...') for each substitution, darboux
    and recipe-g step of a checked certificate; other step kinds are listed as not exported."""
    lines = ["// hkproof certificate re-checked in Singular: the Kahan map x~ - x = 2 eps F(x, x~) (eps = h/2) by",
             "// Cramer's rule, then h(N/Delta) Delta^d compared with h over a common denominator.", _PULLBACK,
             "int i; int j; int hkOk;"]
    for k, step in enumerate(doc["steps"], 1):
        if step["kind"] not in _STEPS:
            lines.append(f'"step {k} ({step["kind"]}): not exported";')
            continue
        field = doc["fields"][step["field"]]
        ring, map_lines = _kahan_map(k, field)
        lines += map_lines + _STEPS[step["kind"]](k, ring, field, step) + [f"kill hkR{k};"]
    lines.append("quit;")
    return "\n".join(lines) + "\n"


def _kahan_map(k: int, field: Mapping) -> tuple[Ring, list[str]]:
    """The ring of step k and the Kahan map N/hkD in it, by Cramer's rule on the equations."""
    xs, params = list(field["variables"]), list(field["parameters"])
    ys = [f"hkY{i + 1}" for i in range(len(xs))]
    ring = get_ring(tuple(xs) + ("eps",) + tuple(params))
    if set(ys) & set(ring.names):
        raise CertificateError(f"the names {sorted(set(ys) & set(ring.names))} are taken by the script")
    coefficients = f"(0, {', '.join(params)})" if params else "0"
    n = len(xs)
    out = [f"ring hkR{k} = {coefficients}, ({', '.join(xs + ys)}, eps), dp;",
           f"map hkMid = hkR{k}, {', '.join(f'({x} + {y})/2' for x, y in zip(xs, ys))}, {', '.join(ys)}, eps;",
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


def _substitution(k: int, ring: Ring, field: Mapping, step: Mapping) -> list[str]:
    """h(N/D) D^a D^b Q = P Q(N/D) D^b D^a: h o f = h."""
    n = len(field["variables"])
    name = step["integrals"][0]["name"]
    return [_DECLARE, *_pulled(ring, step["function"], n),
            "poly hkDiff = hkA[1] * hkD^hkBq[2] * hkQ - hkP * hkBq[1] * hkD^hkA[2];",
            f'if (hkD != 0 && hkBq[1] != 0 && hkDiff == 0) {{ "verified: step {k}, {name} o f = {name}"; }}',
            f'else {{ "refuted: step {k}, {name} o f - {name} is not 0"; }}']


def _darboux(k: int, ring: Ring, field: Mapping, step: Mapping) -> list[str]:
    """P_j(N/D) D^b Q_j K_den = K_num P_j Q_j(N/D) D^a for P_j = hkP/hkQ and K = K_num/K_den; with densities also
    K_num D^(2n) = K_den det(D dN_i/dx_j - N_i dD/dx_j) (K = det Df); a cofactor written "det Df" is that
    determinant over D^(2n)."""
    n = len(field["variables"])
    jacobian = [f"matrix hkJ[{n}][{n}];",
                f"for (i = 1; i <= {n}; i++) {{ for (j = 1; j <= {n}; j++) {{"
                " hkJ[i, j] = hkD * diff(hkN[i], var(j)) - hkN[i] * diff(hkD, var(j)); } }"]
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
    return [*out, f'if (hkOk) {{ "verified: step {k}, {what}"; }} else {{ "refuted: step {k}, {what} fails"; }}']


def _recipe_g(k: int, ring: Ring, field: Mapping, step: Mapping) -> list[str]:
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


_DECLARE = "poly hkP; poly hkQ; list hkA; list hkBq;"
_STEPS = {"substitution": _substitution, "darboux": _darboux, "recipe-g": _recipe_g}


def _text(ring: Ring, text: str) -> str:
    """A right-hand side as Singular text: (numerator)/(denominator), powers with ^."""
    q = parse_formula(ring, text)
    return f"({_poly(q.num)})/({_poly(q.den)})"


def _poly(p: flint.fmpz_mpoly) -> str:
    return str(p) or "0"
