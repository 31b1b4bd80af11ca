"""The modified Hamiltonian as a candidate of `discover`: when the field is F = J grad H with J constant and skew and
H cubic (found from the field alone, hkproof.hk.hamiltonian_structure), the Kahan map preserves
H~ = H + (h/3) grad H^T (I - (h/2) F')^(-1) F (Celledoni, McLachlan, Owren, Quispel 2013); H~ is built by
hkproof.hk.modified_hamiltonian and proven like every other candidate, by exact substitution H~ o f = H~."""
from __future__ import annotations

import time
from hkproof.hk.certified_integrals import certify, is_phase_constant
from hkproof.hk.hamiltonian_structure import hamiltonian_structure
from hkproof.hk.modified_hamiltonian import CMOQ, modified_hamiltonian
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.report import DiscoveryReport, FoundIntegral

__all__ = ["KIND", "seed_modified_hamiltonian"]

KIND = "modified Hamiltonian"


def seed_modified_hamiltonian(ctx: SearchContext, report: DiscoveryReport) -> None:
    """Detect F = J grad H on the searched field, build H~ and append it to the report with its certificate (the
    substitution step); say what was done, timed as the stage "modified Hamiltonian". A field that is not of this
    form adds nothing."""
    kmap = ctx.full_map
    ctx.stages.start(KIND, "looking for F = J grad H with J constant and skew and H cubic")
    start = time.perf_counter()
    structure = hamiltonian_structure(kmap.field)
    if structure is None:
        ctx.stages.say("no constant skew J and cubic H with F = J grad H: no modified Hamiltonian to seed")
        return
    j, h = structure.poisson_text(), structure.hamiltonian
    h_tilde = modified_hamiltonian(kmap, h)
    if is_phase_constant(h_tilde, kmap.variables):
        ctx.stages.say(f"F = J grad H with H = {h} constant: its modified Hamiltonian is trivial")
        return
    name = f"I{len(report.integrals) + 1}"
    route = (f"modified Hamiltonian of H = {h}, J = {j} (Celledoni-McLachlan-Owren-Quispel 2013), "
             "proven by substitution")
    ctx.stages.say(f"{name}: F = J grad H with J = {j} and H = {h}; proving its modified Hamiltonian "
                   f"H~ ({len(h_tilde.num)} + {len(h_tilde.den)} terms) by substitution")
    cert = certify(kmap, h_tilde, ctx.fixed, name)
    if cert.stopped_by_budget:
        report.complete = False
        report.covered.append(f"the modified Hamiltonian {name}: its substitution was stopped by the budget")
    report.integrals.append(FoundIntegral(name, h_tilde, cert.status, KIND, [], "", time.perf_counter() - start,
                                          route, [cert.steps[-1].detail or cert.error, CMOQ], certificate=cert))
    ctx.stages.say(f"{name}: the modified Hamiltonian is {cert.status.label}")
