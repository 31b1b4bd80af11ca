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
from hkproof.proof.certificate import Certificate
from hkproof.proof.export import Conclusion, darboux_step, document, substitution_step
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
