"""One proof vocabulary (issue 24 item 1): every user command's result that states a status carries a Certificate of
the proof kernel (steps with method, ring, status, time), and its status is that certificate's."""
from __future__ import annotations

from pathlib import Path

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.experiments.degree_report import degree_report
from hkproof.experiments.scan import scan
from hkproof.hk.modified_hamiltonian import parse_matrix, verify
from hkproof.pipelines.darboux import search_darboux
from hkproof.pipelines.discover import discover
from hkproof.proof.certificate import Certificate
from hkproof.proof.status import Status

CUBIC = str(Path(__file__).resolve().parents[1] / "docs" / "examples" / "cubic-oscillator.toml")


def _kernel(cert: Certificate, status: Status) -> None:
    assert isinstance(cert, Certificate) and cert.steps and cert.status is status
    assert all(s.method and s.ring for s in cert.steps)


def test_degrees_exact_and_modular():
    f = kahan_map("euler-top")
    exact, modular = degree_report(f, 3, symbolic_up_to=3), degree_report(f, 4, symbolic_up_to=2)
    _kernel(exact.certificate, Status.VERIFIED)
    _kernel(modular.certificate, Status.EVIDENCE_EXACT)
    assert [s.status for s in modular.certificate.steps] == [Status.VERIFIED, Status.EVIDENCE_EXACT]
    assert exact.status is exact.certificate.status and modular.status is modular.certificate.status


def test_scan_is_evidence():
    res = scan("euler-top", "x1**2, x2**2, x3**2, 1", points=3)
    _kernel(res.certificate, Status.EVIDENCE_EXACT)
    assert res.certificate.steps[0].points == 3 and res.status is Status.EVIDENCE_EXACT


def test_measure_discover_and_hamiltonian():
    f = kahan_map("lotka-volterra")
    for d in search_darboux(f, 2).darboux:
        _kernel(d.certificate, Status.VERIFIED)
    for i in discover("euler-top").integrals:
        assert i.certificate is not None and i.certificate.status is i.status
    cubic = kahan_map(CUBIC)
    h = Frac.parse(cubic.ring, "p**2/2 + q**2/2 + a*q**3/3")
    res = verify(cubic, h, parse_matrix(cubic, "[[0, 1], [-1, 0]]"))
    _kernel(res.integral_certificate, Status.VERIFIED)
    _kernel(res.measure_certificate, Status.VERIFIED)
