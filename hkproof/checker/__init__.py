"""The certificate checker: re-verifies a certificate file (docs/certificates.md) from the file alone.

It trusts python-flint, hkproof's formula parser (hkproof.algebra.formula) and its fraction type (Frac: lowest terms
by a gcd, parity in eps read from the exponents of numerator and denominator), Prop. "prop: even" of the paper (a
theorem) and the chain rule (the Nambu structure of Byrnes, Haggar and Quispel (1999) follows from it and identities
the checker expands). It imports nothing else of hkproof: it reads the file strictly (reading.py), rebuilds the
Kahan map, its equations and det Df from the field by its own Cramer's rule (kahan.py), and every identity it reports
as verified is one it computed exactly. Step kinds (steps.py, bivectors.py): substitution, prop-even, darboux,
recipe-g, degrees, reparametrization; from version 7 bivector-invariance, jacobi, casimir, involution and exclusion
(rows the checker computes itself), from 8 affine-change, from 9 no-poisson, from 10 nambu (P W(grad I) for proven
integrals and a proven density 1/P; its universal identities expanded, rank 2 checked at a point). Every claimed
quantity names its field
(version 6), and a step concludes for its own field only. What it cannot check, it refuses (malformed, exit 2); what
is too large to check here, it refuses with a ResourceLimitError (exit 4).

    verified   every step's identities hold exactly, and every claimed integral and density is concluded by a step on
               the field the claim names
    refuted    a stated identity is false (h o f != h, a row not satisfied, a component not even, P o f != K P,
               K != det Df for a density, D delta != sum lambda_i E_i, a degree of f^n differs)
    malformed  not a certificate this checker can read (format, version, convention, entries, step kind, scope, a
               degenerate point)
"""
from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Mapping

from hkproof.algebra.formula import check_name
from hkproof.algebra.fraction import Frac
from hkproof.checker.bivectors import BIVECTOR_STEPS, Matrix
from hkproof.checker.kahan import KahanData
from hkproof.checker.reading import (CONVENTION, FORMAT, MAX_BYTES, VERSIONS, entries, field_key, get, load,
                                     version_gate)
from hkproof.checker.steps import CARRIERS, DET_DF, STEPS
from hkproof.errors import CertificateError, HKProofError, Refutation, ResourceLimitError

__all__ = ["check_document", "check_file", "CheckReport", "DET_DF", "KahanData", "MAX_BYTES", "load"]


@dataclass
class CheckReport:
    """The verdict on a certificate file, one line per step, and what was verified: each claimed integral and
    density with its formula, and the right-hand sides of the fields they belong to."""

    verdict: str                                   # "verified", "refuted" or "malformed"
    lines: list[str] = field(default_factory=list)
    facts: list[str] = field(default_factory=list)
    seconds: float = 0.0

    def text(self) -> str:
        facts = ["what was verified:", *(f"  {fact}" for fact in self.facts)] if self.facts else []
        return "\n".join([f"{self.verdict} ({self.seconds:.3f} s)", *(f"  {line}" for line in [*self.lines, *facts])])


def check_file(path: str | Path) -> CheckReport:
    """Read a certificate file (JSON, numbers as strings) and check it."""
    start = time.perf_counter()
    try:
        raw = Path(path).read_bytes()
        if len(raw) > MAX_BYTES:
            raise CertificateError(f"{path} has {len(raw)} bytes; the checker reads at most {MAX_BYTES}")
        doc = load(raw)
    except OSError as exc:
        return CheckReport("malformed", [f"cannot read {path}: {exc}"], seconds=time.perf_counter() - start)
    except CertificateError as exc:
        return CheckReport("malformed", [f"{path}: {exc}"], seconds=time.perf_counter() - start)
    return check_document(doc)


def check_document(doc: Any) -> CheckReport:
    """Check every step of a certificate (a decoded JSON object) in order; the first failing step decides. A
    certificate too large to check raises ResourceLimitError."""
    start = time.perf_counter()
    report = CheckReport("verified")
    try:
        _check(doc, report)
    except Refutation as exc:
        report.verdict = "refuted"
        report.lines.append(f"refuted: {exc}")
    except ResourceLimitError:
        raise
    except (HKProofError, ZeroDivisionError) as exc:
        report.verdict = "malformed"
        report.lines.append(f"malformed: {exc}")
    if report.verdict != "verified":
        report.facts = []
    report.seconds = time.perf_counter() - start
    return report


def _check(doc: Any, report: CheckReport) -> None:
    if get(doc, "format", str, "certificate") != FORMAT:
        raise CertificateError(f"the format is {doc['format']!r}, not {FORMAT!r}")
    version = get(doc, "version", int, "certificate")
    if version not in VERSIONS:
        raise CertificateError(f"version {version} is not a version this checker reads {VERSIONS}")
    if get(doc, "convention", str, "certificate") != CONVENTION:
        raise CertificateError(f"the step convention {doc['convention']!r} is not {CONVENTION!r}: this checker "
                               "rebuilds the Kahan map as x~ - x = 2 eps F(x, x~) only")
    fields = {field_key(k, version): KahanData(k, v) for k, v in get(doc, "fields", dict, "certificate").items()}
    claimed = _claimed(get(doc, "claim", dict, "certificate"), fields, version)
    proven: dict[str, tuple[str, Frac]] = {}            # integral name -> (field key, value)
    bivectors: dict[str, tuple[str, Matrix]] = {}       # bivector name -> (field key, matrix), version 7
    kinds = (*STEPS, *BIVECTOR_STEPS, *CARRIERS)
    densities: dict[str, tuple[str, Frac]] = {}
    facts: list[str] = []
    steps = entries(doc, "steps", "certificate")
    if not steps:
        raise CertificateError("the certificate has no steps")
    for k, step in enumerate(steps, 1):
        where = f"step {k}"
        key, kind = get(step, "field", str, where), get(step, "kind", str, where)
        if key not in fields:
            raise CertificateError(f"{where}: no field {key!r} in 'fields'")
        if kind not in kinds:
            raise CertificateError(f"{where}: cannot check this step kind {kind!r} (this checker knows "
                                   f"{', '.join(sorted(kinds))})")
        _gate(step, kind, version, where)
        f = fields[key]
        if kind in BIVECTOR_STEPS:
            if step.get("integrals") or "densities" in step:
                raise CertificateError(f"{where}: a {kind} step concludes no integral or density")
            new, fact = BIVECTOR_STEPS[kind](f, step, _of(proven, key),
                                             _of(densities if kind == "nambu" else bivectors, key), where)
            for name, m in new.items():
                if name in {**proven, **densities, **bivectors}:
                    raise CertificateError(f"{where}: the name {name!r} is already taken")
                bivectors[name] = (key, m)
            facts.append(f"field {key}: {_shown(fact)}")
            report.lines.append(f"{where} ({kind}, field {key}): verified; {_shown(fact, 120)}")
            continue
        if kind in CARRIERS:
            source = get(step, "source", str, where)
            if source not in fields or source == key:
                raise CertificateError(f"{where}: the source {source!r} must be another field of 'fields'")
            local = CARRIERS[kind](f, fields[source], step, _of(proven, source), where)
        else:
            local = STEPS[kind](f, step, _of(proven, key), where)
        taken = {**proven, **densities, **bivectors}
        for entry in entries(step, "integrals", where):
            name, value = _conclude(f, entry, local, taken, where, optional=kind in CARRIERS)
            proven[name] = taken[name] = (key, value)
        for entry in entries(step, "densities", where, required=False):
            name, value = _conclude(f, entry, local, taken, where)
            densities[name] = taken[name] = (key, value)
        concluded = [get(e, "name", str, where) for e in [*step["integrals"], *step.get("densities", [])]]
        checked = (f"Darboux polynomials {', '.join(local)}; " if kind == "darboux" else
                   f"deg f^n = {step['degrees']}; " if kind == "degrees" else "")
        report.lines.append(f"{where} ({kind}, field {key}): verified; {checked}concludes {', '.join(concluded) or '-'}")
    for what, name, key in claimed:
        have = bivectors.get(name) if what == "bivector" else (proven if what == "integral" else densities).get(name)
        if have is None:
            raise CertificateError(f"the claim names the {what} {name}, which no step concludes")
        if have[0] != key:
            raise CertificateError(f"the claim says {name} is an {what} of field {key}, but the step that concludes it "
                                   f"speaks of field {have[0]}")
        report.facts.append(f"{what} {name} of field {key}: {_shown(_text(have[1]))}")
    report.facts += facts
    shown = [*(k for _, _, k in claimed), *(fact.split(":")[0][len("field "):] for fact in facts)]
    report.facts += [f"field {key}: {fields[key].summary()}" for key in dict.fromkeys(shown)]


def _claimed(claim: dict, fields: Mapping[str, KahanData], version: int) -> list[tuple[str, str, str]]:
    """(integral or density, name, field key) for each quantity the claim names. From version 6 each entry names its
    field; an older file (a list of names) is read only when it has one field, the only reading it then has."""
    out = []
    if "bivectors" in claim:
        version_gate("bivectors", version, "claim")
    for what, key in (("integral", "integrals"), ("density", "densities"), ("bivector", "bivectors")):
        items = get(claim, key, list, "claim") if key == "integrals" or key in claim else []
        for item in items:
            if version >= 6:
                name, owner = get(item, "name", str, "claim"), get(item, "field", str, "claim")
            elif isinstance(item, str) and len(fields) == 1:
                name, owner = item, next(iter(fields))
            else:
                raise CertificateError(f"claim: a version-{version} certificate names its {key} without their fields; "
                                       "with several fields that is ambiguous: export it again (version 6)")
            if owner not in fields:
                raise CertificateError(f"claim: the {what} {name!r} names the field {owner!r}, which is not in "
                                       "'fields'")
            out.append((what, check_name(name, f"{what} name"), owner))
    return out


def _gate(step: dict, kind: str, version: int, where: str) -> None:
    """The step kind and its features must exist in the file's version."""
    version_gate(kind, version, where)
    if "blocks" in step:
        version_gate("blocks", version, where)
    if "densities" in step:
        version_gate("densities", version, where)
        if kind != "darboux":
            raise CertificateError(f"{where}: only a darboux step concludes densities")
    if step.get("cofactor") == DET_DF:
        version_gate("det Df", version, where)


def _of(proven: Mapping[str, tuple[str, Any]], key: str) -> dict[str, Any]:
    """The integrals (or bivectors) proven so far for the field `key`."""
    return {n: v for n, (g, v) in proven.items() if g == key}


def _text(value: Frac | Matrix) -> str:
    """A concluded quantity as text: a formula, or a bivector's rows."""
    return str(value) if isinstance(value, Frac) else "[" + ", ".join(f"[{', '.join(map(str, r))}]" for r in value) + "]"


def _shown(text: str, width: int = 200) -> str:
    """A formula as the referee sees it: whole up to `width` characters, else its start, length and sha256."""
    if len(text) <= width:
        return text
    return f"{text[:width]} ... ({len(text)} characters, sha256 {hashlib.sha256(text.encode()).hexdigest()[:16]})"


def _conclude(f: KahanData, entry: Any, local: Mapping[str, Frac], taken: Mapping[str, object],
              where: str, optional: bool = False) -> tuple[str, Frac]:
    """An integral (or density) concluded by a step: `from`, a formula in the step's proven quantities (and eps,
    parameters), must equal `formula` exactly; where `optional`, a missing formula means the value of `from`."""
    name = check_name(get(entry, "name", str, where), "integral name")
    if name in taken or name in f.ring.names:
        raise CertificateError(f"{where}: the integral name {name!r} is already taken")
    value = f.parse_in(get(entry, "from", str, where), local, where)
    if optional and "formula" not in entry:
        return name, value
    formula = f.parse(get(entry, "formula", str, where), where)
    if value != formula:
        raise Refutation(f"{where}: {name} = {entry['from']} is not the stated formula")
    return name, formula
