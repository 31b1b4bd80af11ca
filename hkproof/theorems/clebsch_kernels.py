"""Th. "dClebsch max basis" and Th. "dClebsch 1dim bases": proven bounds and exact kernel profiles (evidence)."""
from __future__ import annotations

from typing import Mapping

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.linalg import rank_q
from hkproof.algebra.ring import Rational, to_fmpq
from hkproof.dynamics.catalogue import kahan_map
from hkproof.experiments.profiles import HK_BASIS, exact_profiles
from hkproof.orchestration.registry import REGISTRY, claim, require_proven
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status
from hkproof.theorems._clebsch import PHI_MAX, SYSTEM, X, named, number, recall

__all__ = ["check_kernel_profiles", "GROUP", "kernel_evidence", "KERNEL_STATEMENT", "phi_max_profiles", "PHI_SUB",
           "POINTS", "prove_kernel_evidence", "prove_max_basis_bounds"]

GROUP = "clebsch-kernels"
# (eps, w1, w2, w3; m1, m2, m3, p1, p2, p3): rational points with distinct w and no singular step in 10 iterates
POINTS: tuple[tuple[dict[str, Rational], tuple[Rational, ...]], ...] = (
    ({"eps": "1/7", "w1": 1, "w2": 3, "w3": -2}, (1, 2, -1, 3, 1, 2)),
    ({"eps": "1/5", "w1": "1/2", "w2": 2, "w3": 5}, (2, -1, 3, 1, "1/2", -2)),
    ({"eps": "2/9", "w1": -3, "w2": 1, "w3": 4}, ("1/3", 1, 2, -1, 2, 1)),
)
PHI_SUB = {"Phi0": (0, 1, 2, 9), "Phi1": (0, 1, 2, 3, 4, 5, 6), "Phi2": (0, 1, 2, 3, 4, 5, 7),
           "Phi3": (0, 1, 2, 3, 4, 5, 8)}


def phi_max_profiles(basis_idx, points=POINTS):
    """Exact kernel profiles of the sub-basis of Phi with these indices at the sample points."""
    f = kahan_map(SYSTEM)
    return exact_profiles(f, [named(f, PHI_MAX[i]) for i in basis_idx], points)


@claim("dc-max-basis-bounds", GROUP, "Th. \"dClebsch max basis\", proven part: 3 <= dim K_Phi <= 4",
       "sec. 6.3, Th. \"dClebsch max basis\"",
       "At generic (m, p): K_Phi contains the null-vectors of Phi0, Psi and Theta (placed in R^10), which are "
       "independent, and rank X_[0,5] = 6; so `lower` <= dim K_Phi <= `upper` (part I alone; with Phi1, Phi2, Phi3 "
       "of part II, dim K_Phi = 4 is proven in dc345-max-basis).",
       claimed={"lower": "3", "upper": "4"}, uses=["dc-basis1-relations", "dc-basis2", "dc-theta"])
def prove_max_basis_bounds(cert: Certificate, claimed: Mapping[str, str]) -> None:
    f = kahan_map(SYSTEM)
    r = f.ring
    b1 = require_proven(cert, "dc-basis1-relations")
    b2 = require_proven(cert, "dc-basis2")
    th = require_proven(cert, "dc-theta")
    zero, minus = Frac(r, 0), Frac(r, -1)
    vectors = [
        [recall(b1, "c1", r), recall(b1, "c2", r), recall(b1, "c3", r)] + [zero] * 6 + [minus],
        [minus] * 3 + [zero] * 3 + [recall(b2, k, r) for k in ("d7", "d8", "d9")] + [zero],
        [recall(th, f"g{k}", r) for k in range(1, 7)] + [minus] * 3 + [zero],
    ]
    values, x = POINTS[0]
    point = {**dict(zip(X, x, strict=True)), **values}
    with cert.step("lower bound: K_Phi0, K_Psi, K_Theta in K_Phi, independent", "exact rank at a rational point",
                   r) as s:
        rank = rank_q([[v.evaluate(point) for v in vec] for vec in vectors])
        s.require(rank == number(claimed["lower"]), f"the three proven null-vectors have rank {rank}")
        s.note("each vector annihilates Phi along every orbit (proven integrals); rank 3 at one point, so the "
               "three are independent over Q(m, p, eps, w)")
    with cert.step("upper bound: rank X_[0,5] = 6", "exact rank at a rational point (orbit in Q)", r) as s:
        dim = phi_max_profiles(range(10), POINTS[:1])[0].dims[5]
        s.require(dim == number(claimed["upper"]), f"dim ker X_[0,5] = {dim} at the sample point")
        s.note("a non-zero 6x6 minor at one point is a non-zero rational function: dim K_Phi <= 4 off a proper "
               "algebraic subset")


KERNEL_STATEMENT = ("Th. \"dClebsch max basis\" and Th. \"dClebsch 1dim bases\" at sample points: the exact kernel "
                    "profile of Phi is `profile` (d = 4); Phi0, Phi1, Phi2, Phi3 have d = 1; their null-vectors, "
                    "placed in R^10, span K_Phi. Exact evidence at 3 points for the whole profile (the "
                    "statements about K_Phi and the four bases are proven in dc345-max-basis).")


@claim("dc-kernel-evidence", GROUP, "Th. \"dClebsch max basis\" and \"dClebsch 1dim bases\" at points",
       "sec. 6.3, Th. \"dClebsch max basis\", Th. \"dClebsch 1dim bases\"", KERNEL_STATEMENT,
       claimed={"profile": "9 8 7 6 5 4 4 4 4 4"}, expected=Status.EVIDENCE_EXACT)
def prove_kernel_evidence(cert: Certificate, claimed: Mapping[str, str]) -> None:
    check_kernel_profiles(cert, POINTS, claimed["profile"])


def kernel_evidence(points=POINTS) -> Certificate:
    """The open claim dc-kernel-evidence at other sample points (never verified, only evidence)."""
    c = REGISTRY["dc-kernel-evidence"]
    cert = Certificate(c.id, c.title, c.paper_ref, c.statement)
    try:
        check_kernel_profiles(cert, points, c.claimed["profile"])
    except ProofStopped as exc:
        cert.error = str(exc)
    return cert


def check_kernel_profiles(cert: Certificate, points, profile: str) -> None:
    """The steps of dc-kernel-evidence at `points`: exact profiles of Phi and Phi0..Phi3, and their direct sum."""
    r = kahan_map(SYSTEM).ring
    with cert.step("Phi: exact kernel profiles", "algorithm (N) in exact arithmetic over Q", r) as s:
        profile_max = [number(v) for v in profile.split()]
        full = phi_max_profiles(range(10), points)
        for p in full:
            s.require(p.dims == profile_max and p.verdict == HK_BASIS, f"profile {p.dims} at {p.point}")
        s.evidence(Status.EVIDENCE_EXACT, points=len(points))
        s.note("condition \"fundamental finite\" holds with d = 4 at each point")
    with cert.step("Phi0..Phi3: exact kernel profiles; the direct sum", "algorithm (N) over Q; exact ranks", r) as s:
        subs = {name: phi_max_profiles(idx, points) for name, idx in PHI_SUB.items()}
        for name, profiles in subs.items():
            for p in profiles:
                s.require(p.verdict == HK_BASIS and p.dimension == 1, f"{name}: profile {p.dims} at {p.point}")
        for j in range(len(points)):
            rows = []
            for name, idx in PHI_SUB.items():
                vec = [flint.fmpq(0)] * 10
                for i, v in zip(idx, subs[name][j].kernel[0], strict=True):
                    vec[i] = to_fmpq(str(v))
                rows.append(vec)
            span = rank_q(rows)
            s.require(span == full[j].dimension == 4, f"the four null-vectors span {span} dimensions")
        s.evidence(Status.EVIDENCE_EXACT, points=len(points))
        s.note("d = 1 for Phi0 (also proven: dc-basis1-relations), Phi1, Phi2, Phi3; K_Phi = sum of the four")
