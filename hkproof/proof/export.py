"""Certificates as data (docs/certificates.md): the steps a separate checker can re-check from a JSON file alone.

A prover records each exact identity it checked, with the data needed to check it again, in `Certificate.checks`
(`substitution_step` for h o f = h, `prop_even_step` for Prop. "prop: even", `darboux_step` for P o f = K P and the
integrals and densities it gives, `recipe_g_step` for recipe (G)); `document` gathers the steps of one or more
certificates, the fields they speak of and the integrals and densities they conclude into one versioned JSON object,
which `hkproof.checker` re-verifies.
"""
from __future__ import annotations

import re
from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.field import QuadraticField
from hkproof.proof.certificate import Certificate

__all__ = ["affine_change_step", "bivector_invariance_step", "casimir_step", "exclusion_step", "involution_step", "jacobi_step",
           "claimed", "CONVENTION", "Conclusion", "field_key", "darboux_step", "degrees_step", "document", "field_data", "FORMAT",
           "nambu_step", "no_poisson_step", "prop_even_blocks_step", "prop_even_step", "recipe_g_step", "relation_data", "substitution_step", "VERSION"]

FORMAT = "hkproof-certificate"
VERSION = 10                  # 2: darboux, recipe-g, densities; 3: degrees, cofactor "det Df"; 4: prop-even blocks;
# 5: reparametrization; 6: the claim names the field of each integral and density, field keys ASCII; 7: the bivector
# steps (bivector-invariance, jacobi, casimir, involution, exclusion) and the claim's bivectors; 8: affine-change;
# 9: no-poisson; 10: nambu
Conclusion = tuple[str, Frac, str]      # (name, value, the value written in the step's own names)
CONVENTION = "eps = h/2"      # x~ - x = 2 eps F(x, x~): hkproof's eps is half the time step h


def field_data(field: QuadraticField) -> dict:
    """The vector field as data: names and right-hand sides as text (eq. "diff eq gen"), parameters fixed in."""
    return {"name": field.name, "variables": list(field.variables), "parameters": list(field.parameters),
            "rhs": [str(f) for f in field.rhs]}


def substitution_step(field: QuadraticField | dict, name: str, h: Frac | str) -> dict:
    """The step "h o f - h = 0" (sec. 3, an integral) of the Kahan map of `field` (or of its `field_data`)."""
    data = field_data(field) if isinstance(field, QuadraticField) else field
    ring = ", ".join([*data["variables"], "eps", *data["parameters"]])
    return {"kind": "substitution", "field": data, "function": str(h),
            "identity": f"{name}(f(x)) - {name}(x) = 0 in Q({ring}), f the Kahan map (x~ - x = 2 eps F(x, x~))",
            "integrals": [{"name": name, "formula": str(h), "from": name}]}


def affine_change_step(field: QuadraticField, source: QuadraticField, matrix: Sequence[Sequence[str]],
                       shift: Sequence[str], integrals: Sequence[dict]) -> dict:
    """The step that carries integrals J of the Kahan map of `source` (the field in the chart y = T x + c) to
    integrals J(T x + c) of the map of `field`: G(T x + c) = T F(x) exactly, det T != 0 (hk.affine_chart)."""
    return {"kind": "affine-change", "field": field_data(field), "source": field_data(source),
            "matrix": [list(row) for row in matrix], "shift": list(shift),
            "identity": "G(T x + c) = T F(x) with det T != 0: g(T x + c) = T f(x) + c, and J(T x + c) is an integral "
                        "of f for each integral J of g",
            "integrals": list(integrals)}


def relation_data(coefficients: Sequence[Frac], rhs: Frac | str, uses: Sequence[str] = ()) -> dict:
    """A relation row l.c = R of recipe (E): R as text over the integrals `uses` (proven by earlier steps) and
    `_l<k>` (the right-hand side of relation k + 1 of the same step), or as a formula free of the phase variables."""
    return {"coefficients": [str(c) for c in coefficients], "rhs": str(rhs), "uses": list(uses)}


def prop_even_step(field: QuadraticField, basis: Sequence[Frac], target: Frac, names: Sequence[str],
                   solution: Sequence[Frac], iterates: Sequence[int], relations: Sequence[dict],
                   point: Mapping[str, Rational]) -> dict:
    """The step of Prop. "prop: even": rows i in `iterates` of (sum c_k phi_k) o f^i = phi_l o f^i and the relation
    rows; det at `point` != 0, every c_k and the relation data even in eps, every row satisfied exactly."""
    return {"kind": "prop-even", "field": field_data(field), "basis": [str(b) for b in basis], "target": str(target),
            "names": list(names), "solution": [str(a) for a in solution], "iterates": list(iterates),
            "relations": list(relations), "point": {k: str(to_fmpq(v)) for k, v in point.items()},
            "identity": "sum_k c_k phi_k(f^i(x)) = phi_l(f^i(x)) for i in iterates, and l.c = R for each relation",
            "integrals": [{"name": n, "formula": str(a), "from": n} for n, a in zip(names, solution, strict=True)]}


def prop_even_blocks_step(field: QuadraticField, blocks: Sequence[tuple[Sequence[Frac], Frac]], names: Sequence[str],
                          solution: Sequence[Frac], iterates: Sequence[int], relations: Sequence[dict],
                          point: Mapping[str, Rational]) -> dict:
    """Prop. "prop: even" for several bases solved together (sec. 6.7): the unknowns of the blocks (basis, target)
    form one vector, block after block; rows i in `iterates` of every block and relation rows over the whole vector;
    det at `point` != 0, every component and relation even in eps, every row and relation satisfied exactly."""
    return {"kind": "prop-even", "field": field_data(field),
            "blocks": [{"basis": [str(b) for b in basis], "target": str(target)} for basis, target in blocks],
            "names": list(names), "solution": [str(a) for a in solution], "iterates": list(iterates),
            "relations": list(relations), "point": {k: str(to_fmpq(v)) for k, v in point.items()},
            "identity": "for every block, sum_k c_k phi_k(f^i(x)) = phi_l(f^i(x)) for i in iterates; l.c = R for each "
                        "relation over all the blocks' unknowns",
            "integrals": [{"name": n, "formula": str(a), "from": n} for n, a in zip(names, solution, strict=True)]}


def darboux_step(field: QuadraticField, names: Sequence[str], polynomials: Sequence[Frac], cofactor: Frac | str,
                 integrals: Sequence[Conclusion] = (), densities: Sequence[Conclusion] = ()) -> dict:
    """The step "P_j o f = K P_j" (Darboux polynomials with one cofactor K, Celledoni et al. 2019): integrals as
    functions of the P_j homogeneous of degree 0, densities rho with rho(f(x)) det Df(x) = rho(x) as functions of
    degree -1 when K = det Df. K is a formula, or DET_DF ("det Df"): the checker computes it from the map (the
    Clebsch map's det Df has 1.5 million terms over 1.7 million)."""
    return {"kind": "darboux", "field": field_data(field), "names": list(names),
            "polynomials": [str(p) for p in polynomials], "cofactor": str(cofactor),
            "identity": "P_j(f(x)) = K(x) P_j(x) for each j" + (", K = det Df(x)" if densities else ""),
            "integrals": [_conclusion(c) for c in integrals], "densities": [_conclusion(c) for c in densities]}


def degrees_step(field: QuadraticField, degrees: Sequence[int]) -> dict:
    """The step "deg f^n = d_n for n = 1..N": the iterates composed exactly with eps and the parameters symbolic, the
    common factor of the numerators and the denominator cancelled, the degree taken in the phase variables."""
    return {"kind": "degrees", "field": field_data(field), "degrees": [int(d) for d in degrees],
            "identity": "deg f^n = degrees[n - 1] for n = 1..N, f^n = (N_1, ..., N_k) / D with gcd(N, D) = 1, "
                        "degree in the phase variables", "integrals": []}


def recipe_g_step(field: QuadraticField, name: str, h: Frac, generators: Sequence[object],
                  cofactors: Sequence[object], multiplier: object) -> dict:
    """Recipe (G): D delta = sum_i lambda_i E_i with delta = p(x~) q(x) - p(x) q(x~), h = p/q, E_i the Kahan equations
    in Z[x, x~, eps, params] (x~ named by the field's tilde variables), D free of x~."""
    return {"kind": "recipe-g", "field": field_data(field), "function": str(h),
            "tilde": list(field.tilde_variables), "generators": [str(g) for g in generators],
            "cofactors": [str(c) or "0" for c in cofactors], "multiplier": str(multiplier),
            "identity": "D * (p(x~) q(x) - p(x) q(x~)) = sum_i lambda_i E_i(x, x~) in Z[x, x~, eps, params]",
            "integrals": [{"name": name, "formula": str(h), "from": name}]}


def bivector_invariance_step(field: QuadraticField, name: str, matrix: Sequence[Sequence[object]]) -> dict:
    """The step "Pi(f(x)) = Df Pi(x) Df^T" (version 7): the bivector `name`, an antisymmetric matrix of formulas."""
    return {"kind": "bivector-invariance", "field": field_data(field), "name": name,
            "matrix": [[str(e) for e in row] for row in matrix],
            "identity": f"{name}(f(x)) = Df(x) {name}(x) Df(x)^T entry by entry", "integrals": []}


def jacobi_step(field: QuadraticField, names: Sequence[str]) -> dict:
    """The step "[Pi, Pi] = 0" (one name: Jacobi) or "[Pi_a, Pi_b] = 0" (two: compatibility), version 7."""
    return {"kind": "jacobi", "field": field_data(field), "bivectors": list(names),
            "identity": f"the Schouten bracket [{names[0]}, {names[-1]}] = 0", "integrals": []}


def casimir_step(field: QuadraticField, bivector: str, functions: Sequence[object]) -> dict:
    """The step "Pi grad C = 0" for each C (formulas in x, eps, parameters and integrals proven before), version 7."""
    return {"kind": "casimir", "field": field_data(field), "bivector": bivector,
            "functions": [str(c) for c in functions], "identity": f"{bivector} grad C = 0 for each C", "integrals": []}


def involution_step(field: QuadraticField, bivector: str, functions: Sequence[object]) -> dict:
    """The step "{I, J} = 0" for every pair of the functions (the Poisson bracket of `bivector`), version 7."""
    return {"kind": "involution", "field": field_data(field), "bivector": bivector,
            "functions": [str(c) for c in functions],
            "identity": f"grad I . {bivector} grad J = 0 for every pair", "integrals": []}


def nambu_step(field: QuadraticField, name: str, casimirs: Sequence[str], density: str,
               point: Mapping[str, Rational]) -> dict:
    """The step "P W(grad I_1, ..., grad I_(n-2)) is an invariant Poisson structure of rank 2 with the Casimirs I_k"
    (version 10) for integrals and a density 1/P concluded by earlier steps of the same field, by name; `point`: a
    rational point where the gradients are independent and P != 0."""
    return {"kind": "nambu", "field": field_data(field), "name": name, "casimirs": list(casimirs),
            "density": density, "point": {k: str(v) for k, v in point.items()},
            "identity": f"{name} = P W(grad {', grad '.join(casimirs)}) with 1/P = {density}", "integrals": []}


def exclusion_step(field: QuadraticField, denominator: object, degree: int, prime: int,
                   values: Mapping[str, Rational], symmetries: Sequence[Sequence[int]],
                   blocks: Sequence[tuple[Sequence[int], Sequence[Sequence[int]]]],
                   torus: Mapping[str, list] | None = None) -> dict:
    """The step "no invariant Q/D with deg Q <= degree" (version 7): the checker computes the invariance rows at each
    block's points (residues mod `prime`, eps and the parameters at `values`) and requires full column rank; with a
    torus (hkproof.hk.torus.torus_data) the columns are split by weight and the rows written in its coordinates."""
    return {"kind": "exclusion", "field": field_data(field), "denominator": str(denominator), "degree": int(degree),
            "prime": int(prime), "values": {k: str(to_fmpq(v)) for k, v in values.items()},
            "symmetries": [[int(s) for s in signs] for signs in symmetries], "torus": torus,
            "blocks": [{"character": [int(c) for c in ch], "points": [[int(v) for v in x] for x in points]}
                       for ch, points in blocks],
            "identity": "rank mod p of Q(f(x)) D(x) - D(f(x)) Df Q(x) Df^T at the points = the number of columns",
            "integrals": []}


def no_poisson_step(field: QuadraticField, denominator: object, degree: int, prime: int,
                    values: Mapping[str, Rational], symmetries: Sequence[Sequence[int]],
                    blocks: Sequence[tuple[Sequence[int], Sequence[Sequence[int]]]],
                    kernels: Sequence[tuple[Sequence[int], Sequence[Sequence[int]], bool]],
                    torus: Mapping[str, list] | None = None) -> dict:
    """The step "no invariant Q/D with deg Q <= degree is Poisson" (version 9): the blocks off the kernels' characters
    as for an exclusion (full column rank), and each kernel's block (sign character, points, fixed) in the field's
    coordinates (on the bivectors fixed by the torus' flow when fixed), where the checker finds small kernels mod p
    none of whose members satisfies Jacobi."""
    step = exclusion_step(field, denominator, degree, prime, values, symmetries, blocks, torus)
    return {**step, "kind": "no-poisson",
            "kernels": [{"character": [int(c) for c in ch], "points": [[int(v) for v in x] for x in points],
                         **({"fixed": True} if fixed else {})} for ch, points, fixed in kernels],
            "identity": "full column rank mod p off the kernels' characters; on them kernels mod p whose members' "
                        "Schouten brackets are linearly independent mod p"}


def _conclusion(c: Conclusion) -> dict:
    return {"name": c[0], "formula": str(c[1]), "from": c[2]}


def document(title: str, statement: str, steps: Sequence[dict], fixed: Mapping[str, str] | None = None,
             certificates: Sequence[Certificate] = ()) -> dict:
    """One certificate file: the fields (each once), the steps in order, and the integrals they conclude (a name
    concluded twice is renamed name_2, name_3, ...); `certificates` adds their recorded steps after `steps`."""
    fields: dict[str, dict] = {}
    out: list[dict] = []
    taken: set[str] = set()
    def keyed(data: dict) -> str:
        key = next((k for k, v in fields.items() if v == data), None)
        if key is None:
            key = _fresh(field_key(data["name"]), fields)
            fields[key] = data
        return key
    for step in [*steps, *(s for c in certificates for s in c.checks)]:
        step = dict(step)
        key = keyed(step.pop("field"))
        if "source" in step:      # a reparametrization or affine-change step reads the integrals of another field
            step["source"] = keyed(step["source"])
        for kind in ("integrals", "densities"):
            if kind in step or kind == "integrals":
                step[kind] = [{**e, "name": _fresh(e["name"], taken)} for e in step.get(kind, [])]
        out.append({"field": key, **step})
    bivectors = [{"name": s["name"], "field": s["field"]} for s in out if s["kind"] == "bivector-invariance"]
    return {"format": FORMAT, "version": VERSION, "convention": CONVENTION,
            "claim": {"title": title, "statement": statement, "fixed": dict(fixed or {}),
                      "integrals": [claimed(s, e) for s in out for e in s["integrals"]],
                      "densities": [claimed(s, e) for s in out for e in s.get("densities", [])],
                      **({"bivectors": bivectors} if bivectors else {})},
            "fields": fields, "steps": out}


def claimed(step: dict, conclusion: dict) -> dict:
    """A claim's entry for a quantity a step concludes: its name and the key of the field it belongs to."""
    return {"name": conclusion["name"], "field": step["field"]}


def field_key(name: str) -> str:
    """A field's key in a file: its name in ASCII letters, digits, '_', '.' and '-' (other runs become '_').

    >>> field_key("so4-euler-top[a4=0]"), field_key("3-body")
    ('so4-euler-top_a4_0', 'f_3-body')
    """
    key = re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_")[:90]
    return key if key[:1].isalpha() else f"f_{key}"


def _fresh(name: str, taken: Mapping[str, object] | set[str]) -> str:
    """`name`, or name_2, name_3, ... if taken; a set `taken` records the name returned."""
    k, fresh = 2, name
    while fresh in taken:
        fresh, k = f"{name}_{k}", k + 1
    if isinstance(taken, set):
        taken.add(fresh)
    return fresh
