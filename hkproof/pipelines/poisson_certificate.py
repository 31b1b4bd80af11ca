"""The certificate file of `hkproof poisson` (docs/certificates.md, version 7): the integrals it uses, each verified
bivector's invariance, Jacobi, Casimir, compatibility and involution steps (the Nambu structure too, when its matrix is
written out: the checker substitutes it into its own map), and each excluded class."""
from __future__ import annotations

from hkproof.algebra.formula import tokens
from hkproof.algebra.fraction import poly_str
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.nambu import bivector_steps
from hkproof.hk.torus import torus_data
from hkproof.pipelines.poisson import PoissonReport
from hkproof.proof.export import (bivector_invariance_step, casimir_step, document, exclusion_step, involution_step,
                                  jacobi_step, no_poisson_step, substitution_step)

__all__ = ["poisson_document", "poisson_steps"]


def poisson_document(kmap: KahanMap, report: PoissonReport) -> dict:
    """The certificate file of what `poisson` verified (empty steps: nothing to write)."""
    statement = (f"invariant bivectors of the Kahan map of {report.system}: "
                 f"{sum(s.status.is_verified for s in report.structures)} proven invariant, "
                 f"{sum(s.status.is_verified for s in report.nambu)} Nambu structure(s), "
                 f"{len(report.excluded)} class(es) excluded, "
                 f"{sum(k.no_poisson is not None for k in report.kernels)} without a Poisson member")
    return document(f"poisson {report.system}", statement, poisson_steps(kmap, report),
                    {k: str(v) for k, v in report.fixed.items()})


def poisson_steps(kmap: KahanMap, report: PoissonReport) -> list[dict]:
    """The re-checkable steps (proof.export) of what `poisson` verified, in the order the checker needs them."""
    field, steps = kmap.field, []
    proven = [(k, s) for k, s in enumerate(report.structures) if s.status.is_verified]
    nambu = [(nb, bivector_steps(field, nb, f"Nambu{k + 1}")) for k, nb in enumerate(report.nambu)]
    names = {n for n, _ in report.integrals}
    exported = dict(report.integrals) if proven else {}
    for nb, written in nambu:
        exported.update({n: h for n, h in nb.casimirs if written and n not in exported})
    steps += [substitution_step(field, n, h) for n, h in exported.items()]
    for k, s in proven:
        name = f"Pi{k + 1}"
        steps.append(bivector_invariance_step(field, name, s.bivector.texts()))
        if s.poisson:
            steps.append(jacobi_step(field, [name]))
        if s.casimirs:
            steps.append(casimir_step(field, name, [_in_integrals(c, value, names) for c, value in s.casimirs]))
    verified = {k for k, _ in proven}
    steps += [jacobi_step(field, [f"Pi{a + 1}", f"Pi{b + 1}"]) for a, b, ok in report.compatibility
              if ok and {a, b} <= verified]
    for k, cert in report.involution:
        casimirs = {c for c, _ in report.structures[k].casimirs}
        used = [n for n, _ in report.integrals if n not in casimirs]          # as the pipeline's involution step
        if cert.status.is_verified and k in verified and len(used) >= 2:
            steps.append(involution_step(field, f"Pi{k + 1}", used))
    steps += [step for _, written in nambu for step in written]
    for e in report.excluded:
        if e.certificate.status.is_verified:
            steps.append(exclusion_step(field, e.text, e.degree, e.prime, e.values,
                                        [s.signs for s in e.symmetries], [(b.character, b.points) for b in e.blocks],
                                        None if e.torus is None else torus_data(e.torus)))
    for screened in report.kernels:
        m = screened.member
        if screened.no_poisson is not None and m is not None:
            steps.append(no_poisson_step(field, screened.text, report.degree, m.prime, m.values,
                                         [s.signs for s in m.symmetries], [(b.character, b.points) for b in m.others],
                                         [(b.character, b.points, fx) for b, fx in zip(m.kernels, m.fixed,
                                                                                         strict=True)],
                                         None if m.torus is None else torus_data(m.torus)))
    return steps


def _in_integrals(label: str, value: object, names: set[str]) -> str:
    """A Casimir written in the integrals' names when its label is such a formula (I1, 1/I2, I1/I2), else its value."""
    used = {t.text for t in tokens(label) if t.kind == "name"}
    return label if used and used <= names and "c" not in used else str(value)
