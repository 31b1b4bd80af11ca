"""A certificate's substitution steps as a Singular script: a second computer algebra system rebuilds the Kahan map
from the field and re-checks h o f - h = 0 on its own (docs/certificates.md, "A second opinion")."""
from __future__ import annotations

from typing import Mapping

import flint

from hkproof.algebra.formula import parse_formula
from hkproof.algebra.ring import Ring, get_ring
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
    """A Singular script that prints 'verified: NAME' (or 'refuted: NAME') for each substitution step of a checked
    certificate; other step kinds are listed as not exported."""
    lines = ["// hkproof certificate re-checked in Singular: the Kahan map x~ - x = 2 eps F(x, x~) (eps = h/2) by",
             "// Cramer's rule, then h(N/Delta) Delta^d compared with h over a common denominator.", _PULLBACK]
    for k, step in enumerate(doc["steps"], 1):
        if step["kind"] != "substitution":
            lines.append(f'"step {k} ({step["kind"]}): not exported";')
            continue
        lines += _substitution(k, doc["fields"][step["field"]], step)
    lines.append("quit;")
    return "\n".join(lines) + "\n"


def _substitution(k: int, field: Mapping, step: Mapping) -> list[str]:
    """One ring, the map, and the identity of one step."""
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
           f"matrix hkM[{n}][{n}]; ideal hkB; poly hkE; int i; int j;",
           f"for (i = 1; i <= {n}; i++) {{",
           f"  hkE = var({n} + i) - var(i) - 2*eps*(2*hkFm[i] - (hkF[i] + hkFy[i])/2);",
           f"  for (j = 1; j <= {n}; j++) {{ hkM[i, j] = diff(hkE, var({n} + j)); }}",
           f"  hkB[i] = -subst(hkE, {', '.join(f'{y}, 0' for y in ys)});",
           "}",
           "poly hkD = det(hkM); ideal hkN; matrix hkC;",
           f"for (j = 1; j <= {n}; j++) {{ hkC = hkM; for (i = 1; i <= {n}; i++) {{ hkC[i, j] = hkB[i]; }}"
           " hkN[j] = det(hkC); }"]
    h = parse_formula(ring, step["function"])
    name = step["integrals"][0]["name"]
    out += [f"poly hkP = {_poly(h.num)}; poly hkQ = {_poly(h.den)};",
            f"list hkA = hkPullback(hkP, hkN, hkD, {n}); list hkBq = hkPullback(hkQ, hkN, hkD, {n});",
            "poly hkDiff = hkA[1] * hkD^hkBq[2] * hkQ - hkP * hkBq[1] * hkD^hkA[2];",
            f'if (hkD != 0 && hkBq[1] != 0 && hkDiff == 0) {{ "verified: step {k}, {name} o f = {name}"; }}',
            f'else {{ "refuted: step {k}, {name} o f - {name} is not 0"; }}',
            f"kill hkR{k};"]
    return out


def _text(ring: Ring, text: str) -> str:
    """A right-hand side as Singular text: (numerator)/(denominator), powers with ^."""
    q = parse_formula(ring, text)
    return f"({_poly(q.num)})/({_poly(q.den)})"


def _poly(p: flint.fmpz_mpoly) -> str:
    return str(p) or "0"
