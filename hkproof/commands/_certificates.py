"""--certificate FILE: the options and the writing shared by the commands that state a status (docs/certificates.md)."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Mapping, Sequence

from hkproof.algebra.printing import to_json
from hkproof.algebra.formula import LIMITS, rename, tokens
from hkproof.algebra.fraction import Frac
from hkproof.checker import DET_DF
from hkproof.commands.report import writable_target, write_atomically
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.darboux import cofactor_value
from hkproof.hk.modified_hamiltonian import ModifiedHamiltonianResult
from hkproof.pipelines.darboux import DarbouxSearch
from hkproof.pipelines.discover.report import DiscoveryReport, FoundIntegral
from hkproof.proof.certificate import Certificate
from hkproof.proof.export import (Conclusion, affine_change_step, claimed, darboux_step, document, field_data,
                                  substitution_step)
from hkproof.proof.status import Status


def add_certificate_option(p: argparse.ArgumentParser) -> None:
    """--certificate FILE on a command that proves something."""
    p.add_argument("--certificate", metavar="FILE",
                   help="write a self-contained JSON certificate of what was verified, for `hkproof check FILE` "
                        "(docs/certificates.md); FILE is replaced atomically")


def certificate_target(args: argparse.Namespace) -> Path | None:
    """FILE of --certificate, checked before the work starts (a regular file or a new name)."""
    return writable_target(args.certificate) if getattr(args, "certificate", None) else None


def write_certificate(target: Path | None, doc: dict | None, payload: dict) -> str:
    """Write the certificate (when asked for) and say so in the payload; the line for the text output. With nothing
    to write, the payload's `certificate_error` says so: the report is still printed, then the error (cli)."""
    if target is None:
        return ""
    if doc is None or not doc["steps"]:
        payload["certificate_error"] = (
            f"no certificate written to {target}: nothing was verified by a step a certificate can record (an exact "
            "substitution, Prop. \"prop: even\", a Darboux polynomial, recipe (G), an exclusion or no-poisson step of "
            "invariant bivectors, or the degrees of symbolic iterates: degrees --symbolic-up-to N)")
        return ""
    write_atomically(target, to_json(doc, indent=1) + "\n")
    payload["certificate"] = str(target)
    return f"\ncertificate: {target} ({len(doc['steps'])} step(s); check it with `hkproof check {target}`)"


def theorem_document(certs: Sequence[Certificate]) -> dict:
    """The recorded steps of the verified theorems' certificates, in the order they ran. A relation whose coefficients
    or right-hand side are integrals proven by another claim (written in the phase variables) gets each of them
    proven in the same file by a substitution step before it, and names it."""
    done = [c for c in certs if c.status >= Status.VERIFIED_SPECIALIZED and c.checks]
    steps: list[dict] = []
    cited: dict[tuple[str, str], str] = {}          # (field, formula) -> the name of its substitution step
    for c in done:
        for step in c.checks:
            steps += _with_cited_integrals(step, c.claim_id, cited) if "cites" in step else [step]
    return document(f"theorems {', '.join(c.claim_id for c in done)}", " ".join(c.statement for c in done), steps)


def _with_cited_integrals(step: dict, claim_id: str, cited: dict[tuple[str, str], str]) -> list[dict]:
    """The substitution steps proving the relation data of `step` that depends on the phase variables, then the
    step with that data replaced by their names (listed in the relation's `uses`)."""
    phase, before = set(step["field"]["variables"]), []

    def named(text: str, uses: list[str]) -> str:
        if not phase & {t.text for t in tokens(text) if t.kind == "name"}:
            return text
        key = (step["field"]["name"], text)
        if key not in cited:
            cited[key] = f"{claim_id.replace('-', '_')}_i{len(cited) + 1}"
            before.append(substitution_step(step["field"], cited[key], text))
        uses.append(cited[key])
        return cited[key]
    relations = []
    for rel in step["relations"]:
        uses = list(rel["uses"])
        relations.append({"coefficients": [named(c, uses) for c in rel["coefficients"]], "rhs": named(rel["rhs"], uses),
                          "uses": list(dict.fromkeys(uses))})
    return [*before, {**step, "relations": relations}]


def discover_document(report: DiscoveryReport) -> dict:
    """The steps that proved each verified integral of `discover`: its substitution, or the Prop. "prop: even" step
    of its basis with the integral concluded as c_a / c_b (the coordinates, the normalized one -1); after a search on
    the slice of a parameter translation, these steps speak of the slice and one reparametrization step carries
    their integrals to the system (the claim names those)."""
    steps: list[dict] = []
    seen: dict[int, dict] = {}
    concluded: list[tuple[FoundIntegral, str]] = []         # (integral, its name in the step that concludes it)
    for found in report.verified:
        cert, value = found.certificate, _searched(found)
        if cert is None or value is None or not cert.checks:
            continue
        if id(cert) not in seen:
            fresh = [_on_searched_field(dict(s), report) for s in cert.checks]
            for s in fresh:
                if s["kind"] == "prop-even":
                    s["integrals"] = []
            seen[id(cert)] = fresh[-1]
            steps += fresh
        step = seen[id(cert)]
        if step["kind"] == "prop-even":
            ratio = _as_ratio(value, cert, step["names"])
            if ratio is not None:
                step["integrals"].append({"name": found.name, "formula": str(value), "from": ratio})
                concluded.append((found, found.name))
        else:
            concluded += [(found, e["name"]) for e in step["integrals"] if e["formula"] == str(value)]
    where = report.on_slice if concluded else None
    if where is not None:
        on_slice = {e["name"]: f"{e['name']}_slice" for s in steps for e in s["integrals"]}
        steps = [_renamed(s, on_slice) for s in steps]
        steps.append({"kind": "reparametrization", "field": field_data(where.field),
                      "source": field_data(where.searched),
                      "parameters": {b: str(image) for b, image in where.images(where.field.ring).items()},
                      "identity": "sigma(F_slice) = F: sigma sends each integral of the slice's Kahan map to one of "
                                  "this map",
                      "integrals": [_carried(_in_chart(f), name, on_slice[name]) for f, name in concluded]})
    chart = report.chart if concluded else None
    if chart is not None:
        in_chart = {name: f"{name}_chart" for _, name in concluded}
        steps = [_renamed(s, in_chart) for s in steps]
        steps.append(affine_change_step(chart.field, chart.searched, chart.change.matrix, chart.change.shift,
                                        [_carried(f.frac, name, in_chart[name]) for f, name in concluded
                                         if f.frac is not None]))
    doc = document(f"integrals of the Kahan map of {report.system}", "", steps, report.fixed)
    if where is not None or chart is not None:
        doc["claim"]["integrals"] = [claimed(doc["steps"][-1], e) for e in doc["steps"][-1]["integrals"]]
    names = ", ".join(e["name"] for e in doc["claim"]["integrals"])
    doc["claim"]["statement"] = (f"the integrals {names} are integrals of the Kahan map of {report.system}"
                                 + ("" if where is None else f" ({where.describe()}; the steps that prove them on the "
                                    "slice name them <name>_slice)")
                                 + ("" if chart is None else f" ({chart.describe()}; the steps in the chart name "
                                    "them <name>_chart)"))
    return doc


def _renamed(step: dict, names: Mapping[str, str]) -> dict:
    """The step with the integrals it concludes and cites renamed (whole names, by tokens; names not in `names`
    kept)."""
    return {**step, "integrals": [{**e, "name": names.get(e["name"], e["name"]), "from": rename(e["from"], names)}
                                  for e in step["integrals"]],
            **({"relations": _renamed_relations(step["relations"], names)} if "relations" in step else {})}


def _on_searched_field(step: dict, report: DiscoveryReport) -> dict:
    """A step recorded on the field with the conserved coordinates made parameters, moved to the searched field: its
    Kahan map is the restriction of that one (x~_i = x_i), and a conserved coordinate in a relation is the integral
    conserved_<x_i> proven by the step before."""
    if report.searched is None or not report.conserved or step["field"]["variables"] == list(report.searched.variables):
        return step
    names = {v: f"conserved_{v}" for v in report.conserved}
    return {**step, "field": field_data(report.searched),
            "relations": _renamed_relations(step.get("relations", []), names)}


def _renamed_relations(relations: Sequence[dict], names: Mapping[str, str]) -> list[dict]:
    """Relations with names replaced in their texts (by tokens) and in `uses`, which also gets each new name that a
    text now cites."""
    out = []
    for rel in relations:
        cited = {t.text for text in [*rel["coefficients"], rel["rhs"]] for t in tokens(text) if t.kind == "name"}
        uses = [names.get(u, u) for u in rel["uses"]] + [new for old, new in names.items() if old in cited]
        out.append({"coefficients": [rename(c, names) for c in rel["coefficients"]], "rhs": rename(rel["rhs"], names),
                    "uses": list(dict.fromkeys(uses))})
    return out


def _carried(value: Frac | None, name: str, source: str) -> dict:
    """A conclusion `name` carried from `source` by a reparametrization or an affine change: the carried formula,
    unless it is longer than a formula may be (the step then defines the value exactly from the source's)."""
    text = str(value)
    return {"name": name, "from": source, **({"formula": text} if value is not None and len(text) <= LIMITS.length
                                             else {})}


def _in_chart(found: FoundIntegral) -> Frac | None:
    """The integral in the chart the search ran in (the user's, unless a normal form was searched)."""
    return found.in_chart if found.in_chart is not None else found.frac


def _searched(found: FoundIntegral) -> Frac | None:
    """The integral as its proof steps speak of it: on the slice when the search ran on one, else in its chart."""
    return found.searched if found.searched is not None else _in_chart(found)


def _as_ratio(value: Frac, cert: Certificate, names: Sequence[str]) -> str | None:
    """'c2', '(c2)/(c1)', '(c2)/(-1)' or '(-1)/(c1)': the coordinate or quotient of two coordinates (c_l = -1) that
    equals the integral `value`, if any."""
    values = [(n, cert.values[n]) for n in names if n in cert.values]
    if len(values) != len(names) or set(values[0][1].ring.names) != set(value.ring.names):
        return None
    if values[0][1].ring != value.ring:         # proven with a conserved coordinate as a parameter
        values = [(n, a.to_ring(value.ring)) for n, a in values]
    for name, a in values:
        if a == value:
            return name
    one = Frac(value.ring, -1)
    for top, a in [*values, ("-1", one)]:
        for bottom, b in [*values, ("-1", one)]:
            if top != bottom and not b.is_zero() and a / b == value:
                return f"({top})/({bottom})"
    return None


def measure_document(kmap: KahanMap, search: DarbouxSearch) -> dict:
    """One darboux step per cofactor K of `measure`'s verified Darboux polynomials (P_j o f = K P_j), concluding the
    integrals P_j/P_1 (each P_j when K = 1) and, when K = det Df, the densities 1/P_j (the density 1 as 1/P with P = 1
    when det Df = 1)."""
    one = tuple(0 for _ in search.atoms)
    groups: dict[tuple[int, ...], list[Frac]] = {one: [Frac(kmap.ring, 1)]} if search.jacobian.exponents == one else {}
    cofactors = {}
    for d in search.darboux:
        if d.status >= Status.VERIFIED_SPECIALIZED:
            groups.setdefault(d.cofactor.exponents, []).append(Frac(kmap.ring, d.poly))
            cofactors[d.cofactor.exponents] = d.cofactor
    steps, counts = [], {"I": 0, "rho": 0}

    def named(kind: str, value: Frac, text: str) -> Conclusion:
        counts[kind] += 1
        return f"{kind}{counts[kind]}", value, text
    for exps, polys in groups.items():
        names = [f"P{k + 1}" for k in range(len(polys))]
        pairs = list(zip(names, polys, strict=True))
        integrals = ([named("I", p, n) for n, p in pairs if not p.is_constant()] if exps == one else
                     [named("I", p / polys[0], f"({n})/({names[0]})") for n, p in pairs[1:]])
        densities = ([named("rho", 1 / p, f"1/({n})") for n, p in pairs]
                     if exps == search.jacobian.exponents and search.jacobian_lemma else [])
        k: Frac | str = DET_DF if exps == search.jacobian.exponents else (
            cofactor_value(kmap, search.atoms, cofactors[exps]) if exps in cofactors else Frac(kmap.ring, 1))
        steps.append(darboux_step(kmap.field, names, polys, k, integrals, densities))
    return document(f"Darboux polynomials of the Kahan map of {search.system}",
                    f"the Darboux polynomials of degree <= {search.degree} found give the integrals and invariant "
                    f"densities named here, for the Kahan map of {search.system}", steps,
                    {k: str(v) for k, v in search.fixed.items()})


def hamiltonian_document(kmap: KahanMap, res: ModifiedHamiltonianResult, fixed: dict[str, str]) -> dict:
    """The modified Hamiltonian H~ (a substitution step) and the density 1/det(I - eps F') (a darboux step with
    cofactor det Df), each when verified."""
    steps = [substitution_step(kmap.field, "Ht", res.h_tilde)] if res.integral >= Status.VERIFIED_SPECIALIZED else []
    if res.measure >= Status.VERIFIED_SPECIALIZED:
        p = res.density_denominator
        steps.append(darboux_step(kmap.field, ["P"], [p], res.jacobian, densities=[("rho", 1 / p, "1/(P)")]))
    return document(f"the modified Hamiltonian and measure of the Kahan map of {kmap.field.name}",
                    "H~ = H + (h/3) grad H^T (I - (h/2) F')^(-1) F is an integral and dx/det(I - (h/2) F') an invariant "
                    f"measure of the Kahan map of {kmap.field.name} (Celledoni-McLachlan-Owren-Quispel 2013)", steps,
                    fixed)
