"""The certificate of `discover` (docs/certificates.md): the steps that proved each verified integral, moved to the
field the search ran on, and carried to the system by a reparametrization or an affine change where the search ran on a
slice or in a normal form."""
from __future__ import annotations

from typing import Any, Mapping, Sequence

from hkproof.algebra.formula import LIMITS, rename, tokens
from hkproof.algebra.fraction import Frac
from hkproof.pipelines.discover.report import DiscoveryReport, FoundIntegral
from hkproof.proof.certificate import Certificate
from hkproof.proof.export import affine_change_step, claimed, document, field_data

__all__ = ["discover_document", "discover_steps"]


def discover_steps(report: DiscoveryReport) -> list[dict]:
    """The steps (fields as data, for `proof.export.document` or a claim's `checks`) that prove each verified
    integral of `discover` under its own name: its substitution, or the Prop. "prop: even" step of its basis with the
    integral concluded as c_a / c_b; on a slice or in a chart, the last step carries them to the system."""
    return _steps(report)[0]


def discover_document(report: DiscoveryReport) -> dict:
    """The certificate file of `discover`: `discover_steps`, the claim naming the integrals on the system."""
    steps, where, chart = _steps(report)
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


def _steps(report: DiscoveryReport) -> tuple[list[dict], Any, Any]:
    """The steps, and the slice and the chart they were carried from (None when not)."""
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
    return steps, where, chart


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


