"""The registry of the paper's theorems: each claim has an id, the paper's formulas as claims, and a prover."""
from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass, field
from typing import Callable, Iterable, Mapping

from hkproof.errors import HKProofError, UnknownClaimError
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

Prover = Callable[[Certificate, Mapping[str, str]], None]


@dataclass
class Claim:
    """A theorem of the paper: `claimed` holds its printed formulas, which the prover checks, never returns."""

    id: str
    group: str
    title: str
    paper_ref: str
    statement: str
    prover: Prover
    claimed: dict[str, str] = field(default_factory=dict)
    slow: bool = False
    expected: Status = Status.VERIFIED

    def succeeded(self, cert: Certificate) -> bool:
        """The certificate reaches what the claim promises: `verified`, or the weaker `expected` of an open claim."""
        return cert.status >= self.expected

    @property
    def is_open(self) -> bool:
        """A conjecture or a specialized result: the registry promises less than `verified`."""
        return self.expected < Status.VERIFIED

    def prove(self, overrides: Mapping[str, str] | None = None) -> Certificate:
        """Run the proof; `overrides` replaces claimed formulas (a perturbed claim must be refuted)."""
        unknown = set(overrides or {}) - set(self.claimed)
        if unknown:
            raise UnknownClaimError(f"{self.id} has no claimed formula(s) {sorted(unknown)}; "
                                    f"it has {sorted(self.claimed)}")
        cert = Certificate(self.id, self.title, self.paper_ref, self.statement)
        try:
            self.prover(cert, {**self.claimed, **(overrides or {})})
        except ProofStopped as exc:
            cert.error = str(exc)
        except HKProofError as exc:
            cert.error = f"{type(exc).__name__}: {exc}"
        return cert


REGISTRY: dict[str, Claim] = {}
_CACHE: dict[str, Certificate] = {}


def claim(id: str, group: str, title: str, paper_ref: str, statement: str,
          claimed: Mapping[str, str] | None = None, slow: bool = False,
          expected: Status = Status.VERIFIED) -> Callable[[Prover], Prover]:
    """Register a prover as the proof of a claim; `expected` < verified marks an open claim (evidence only)."""
    def register(prover: Prover) -> Prover:
        if id in REGISTRY:
            raise ValueError(f"claim id {id} registered twice")
        REGISTRY[id] = Claim(id, group, title, paper_ref, statement, prover, dict(claimed or {}), slow, expected)
        return prover
    return register


def load_all() -> dict[str, Claim]:
    """Import every module of hkproof.theorems, which registers its claims."""
    import hkproof.theorems as pkg
    for mod in pkgutil.iter_modules(pkg.__path__):
        importlib.import_module(f"{pkg.__name__}.{mod.name}")
    return REGISTRY


def get_claim(claim_id: str) -> Claim:
    load_all()
    if claim_id not in REGISTRY:
        raise UnknownClaimError(f"no theorem '{claim_id}'; `hkproof list` shows the ids")
    return REGISTRY[claim_id]


def select(ids: Iterable[str] = (), groups: Iterable[str] = (), include_slow: bool = True) -> list[Claim]:
    """Claims by id or group, in registration order (dependencies come first)."""
    load_all()
    ids, groups = list(ids), list(groups)
    for i in ids:
        get_claim(i)
    known_groups = {c.group for c in REGISTRY.values()}
    for g in groups:
        if g not in known_groups:
            raise UnknownClaimError(f"no theorem group '{g}'; groups are {sorted(known_groups)}")
    out = [c for c in REGISTRY.values()
           if (not ids and not groups) or c.id in ids or c.group in groups]
    return [c for c in out if include_slow or not c.slow or c.id in ids]


def proven(claim_id: str) -> Certificate:
    """The certificate of an unperturbed claim, computed once per process (for proofs that cite it)."""
    if claim_id not in _CACHE:
        _CACHE[claim_id] = get_claim(claim_id).prove()
    return _CACHE[claim_id]


def require_proven(cert: Certificate, claim_id: str) -> Certificate:
    """A step citing an earlier theorem: it must be verified, or this proof stops."""
    with cert.step(f"uses {claim_id}", "citation of an earlier certificate", "-") as s:
        dep = proven(claim_id)
        if dep.status is not Status.VERIFIED:
            s.inconclusive(f"{claim_id} is {dep.status.label}, not verified")
        s.note(f"{claim_id} verified")
    return dep
