"""Certificates as data (docs/certificates.md): the steps a separate checker can re-check from a JSON file alone.

A prover records each exact identity it checked, with the data needed to check it again, in `Certificate.checks`
(`substitution_step` for h o f = h, `prop_even_step` for Prop. "prop: even"); `document` gathers the steps of one or
more certificates, the fields they speak of and the integrals they conclude into one versioned JSON object, which
`hkproof.checker` re-verifies.
"""
from __future__ import annotations

from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.field import QuadraticField
from hkproof.proof.certificate import Certificate

__all__ = ["CONVENTION", "document", "field_data", "FORMAT", "prop_even_step", "relation_data",
           "substitution_step", "VERSION"]

FORMAT = "hkproof-certificate"
VERSION = 1
CONVENTION = "eps = h/2"      # x~ - x = 2 eps F(x, x~): hkproof's eps is half the time step h


def field_data(field: QuadraticField) -> dict:
    """The vector field as data: names and right-hand sides as text (eq. "diff eq gen"), parameters fixed in."""
    return {"name": field.name, "variables": list(field.variables), "parameters": list(field.parameters),
            "rhs": [str(f) for f in field.rhs]}


def substitution_step(field: QuadraticField, name: str, h: Frac) -> dict:
    """The step "h o f - h = 0" (sec. 3, an integral) of the Kahan map of `field`."""
    ring = ", ".join(field.ring.names)
    return {"kind": "substitution", "field": field_data(field), "function": str(h),
            "identity": f"{name}(f(x)) - {name}(x) = 0 in Q({ring}), f the Kahan map (x~ - x = 2 eps F(x, x~))",
            "integrals": [{"name": name, "formula": str(h), "from": name}]}


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


def document(title: str, statement: str, steps: Sequence[dict], fixed: Mapping[str, str] | None = None,
             certificates: Sequence[Certificate] = ()) -> dict:
    """One certificate file: the fields (each once), the steps in order, and the integrals they conclude (a name
    concluded twice is renamed name_2, name_3, ...); `certificates` adds their recorded steps after `steps`."""
    fields: dict[str, dict] = {}
    out: list[dict] = []
    taken: set[str] = set()
    for step in [*steps, *(s for c in certificates for s in c.checks)]:
        step = dict(step)
        data = step.pop("field")
        key = next((k for k, v in fields.items() if v == data), None)
        if key is None:
            key = _fresh(data["name"], fields)
            fields[key] = data
        conclusions = []
        for entry in step.get("integrals", []):
            entry = {**entry, "name": _fresh(entry["name"], taken)}
            taken.add(entry["name"])
            conclusions.append(entry)
        out.append({"field": key, **step, "integrals": conclusions})
    return {"format": FORMAT, "version": VERSION, "convention": CONVENTION,
            "claim": {"title": title, "statement": statement, "fixed": dict(fixed or {}),
                      "integrals": [e["name"] for s in out for e in s["integrals"]]},
            "fields": fields, "steps": out}


def _fresh(name: str, taken: Mapping[str, object] | set[str]) -> str:
    if name not in taken:
        return name
    k = 2
    while f"{name}_{k}" in taken:
        k += 1
    return f"{name}_{k}"
