"""The registry of the paper's theorems: each claim has an id, the paper's formulas as claims, the claims it cites
(`uses`) and a prover; and the run's certificate cache, so that a cited claim is proven once per run."""
from __future__ import annotations

import importlib
import pkgutil
import time
from contextvars import ContextVar
from dataclasses import dataclass, field
from typing import Callable, Iterable, Mapping

from hkproof.errors import UnknownClaimError
from hkproof.budget import Budget
from hkproof.proof.certificate import Certificate, ProofStopped
from hkproof.proof.status import Status

__all__ = ["cached", "Claim", "claim", "get_claim", "load_all", "proven", "Prover", "REGISTRY", "remember",
           "require_proven", "select"]

Prover = Callable[[Certificate, Mapping[str, str]], None]


@dataclass
class Claim:
    """A theorem of the paper: `claimed` holds its printed formulas, which the prover checks, never returns;
    `uses` the claims whose certificates the prover cites (the edges of the claim graph)."""

    id: str
    group: str
    title: str
    paper_ref: str
    statement: str
    prover: Prover
    claimed: dict[str, str] = field(default_factory=dict)
    slow: bool = False
    expected: Status = Status.VERIFIED
    uses: tuple[str, ...] = ()
    shares: str = ""            # a per-process intermediate (an lru-cached computation) claims of the same key read:
                                # a run proves them one after the other on one worker, which computes it once

    def succeeded(self, cert: Certificate) -> bool:
        """The certificate reaches what the claim promises: `verified`, or the weaker `expected` of an open claim."""
        return cert.status >= self.expected

    @property
    def is_open(self) -> bool:
        """A conjecture or a specialized result: the registry promises less than `verified`."""
        return self.expected < Status.VERIFIED

    def prove(self, overrides: Mapping[str, str] | None = None, seconds: float | None = None) -> Certificate:
        """The certificate of this claim: the run's cached one when unperturbed (proven at most once per run);
        with `overrides` (replacing claimed formulas: a perturbed claim must be refuted) proven afresh, never cached.
        With `seconds`, the proof runs within that budget; when it runs out, the certificate is `unknown` and says so."""
        if seconds is None:
            return self.certify(overrides) if overrides else proven(self.id)
        before = set(_CACHE)
        with Budget(seconds, raise_with="a larger per-claim time budget").active() as budget:
            cert = self.certify(overrides) if overrides else proven(self.id)
        if budget.expired:      # what ran out is not this run's answer for later citations: forget it
            for cid in set(_CACHE) - before:
                if _CACHE[cid].status is Status.UNKNOWN:
                    del _CACHE[cid]
            if cert.status is Status.UNKNOWN:
                cert.notes.append(RAN_OUT)
        return cert

    def certify(self, overrides: Mapping[str, str] | None = None) -> Certificate:
        """Run the prover now. Total: any exception of the prover (a bug included, KeyboardInterrupt excepted)
        ends in an `unknown` certificate that records the error's type and message."""
        unknown = set(overrides or {}) - set(self.claimed)
        if unknown:
            raise UnknownClaimError(f"{self.id} has no claimed formula(s) {sorted(unknown)}; "
                                    f"it has {sorted(self.claimed)}")
        cert = Certificate(self.id, self.title, self.paper_ref, self.statement)
        token = _PROVING.set(cert)
        start = time.perf_counter()
        try:
            self.prover(cert, {**self.claimed, **(overrides or {})})
        except ProofStopped as exc:
            cert.error = str(exc)
        except Exception as exc:  # noqa: BLE001 -- a prover never aborts a run; the error is the certificate's
            cert.error = f"{type(exc).__name__}: {exc}"
        finally:
            _PROVING.reset(token)
            cert.elapsed = time.perf_counter() - start
        return cert


RAN_OUT = "stopped by the per-claim time budget: unknown, not refuted"
REGISTRY: dict[str, Claim] = {}
_CACHE: dict[str, Certificate] = {}  # the run's certificates of unperturbed claims, by id
_PROVING: ContextVar[Certificate | None] = ContextVar("hkproof_proving", default=None)


def claim(id: str, group: str, title: str, paper_ref: str, statement: str,
          claimed: Mapping[str, str] | None = None, slow: bool = False,
          expected: Status = Status.VERIFIED, uses: Iterable[str] = (), shares: str = "") -> Callable[[Prover], Prover]:
    """Register a prover as the proof of a claim; `expected` < verified marks an open claim (evidence only);
    `uses` lists the claims it cites (require_proven refuses any other); `shares` names the per-process
    intermediate it computes with other claims (Claim.shares)."""
    def register(prover: Prover) -> Prover:
        if id in REGISTRY:
            raise ValueError(f"claim id {id} registered twice")
        REGISTRY[id] = Claim(id, group, title, paper_ref, statement, prover, dict(claimed or {}), slow, expected,
                             tuple(uses), shares)
        return prover
    return register


def load_all() -> dict[str, Claim]:
    """Import every theorem group of hkproof.theorems (in the paper's order, hkproof.theorems.GROUPS, then any other),
    which registers its claims (loaded by name, like plug-ins: the theorems sit above the registry and import it,
    never the other way)."""
    pkg = importlib.import_module("hkproof.theorems")
    names = [m.name for m in pkgutil.iter_modules(pkg.__path__) if not m.name.startswith("_")]
    ordered = [g for g in getattr(pkg, "GROUPS", ()) if g in names] + sorted(set(names) - set(pkg.GROUPS))
    for name in ordered:
        importlib.import_module(f"{pkg.__name__}.{name}")
    return REGISTRY


def get_claim(claim_id: str) -> Claim:
    load_all()
    if claim_id not in REGISTRY:
        raise UnknownClaimError(f"no theorem '{claim_id}'; `hkproof list` shows the ids")
    return REGISTRY[claim_id]


def select(ids: Iterable[str] = (), groups: Iterable[str] = (), include_slow: bool = True) -> list[Claim]:
    """Claims by id or group, in registration order."""
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


def cached(claim_id: str) -> Certificate | None:
    """The run's certificate of an unperturbed claim, if it was proven already."""
    return _CACHE.get(claim_id)


def remember(certs: Iterable[Certificate]) -> None:
    """Put certificates of unperturbed claims proven elsewhere (a worker, the scheduler) into the run's cache (not
    those a per-claim budget stopped)."""
    for cert in certs:
        if RAN_OUT not in cert.notes:
            _CACHE[cert.claim_id] = cert


def proven(claim_id: str) -> Certificate:
    """The certificate of an unperturbed claim, proven once per run (the run's cache). Inside a prover this is a
    citation: it must be declared in the citing claim's `uses`, and is recorded in its certificate's `cites`."""
    citing = _PROVING.get()
    if citing is not None:
        declared = REGISTRY[citing.claim_id].uses if citing.claim_id in REGISTRY else ()
        if claim_id not in declared:
            raise ProofStopped(f"{citing.claim_id} cites {claim_id}, which is not declared in its "
                               f"@claim(uses=...) {list(declared)}: declare it (the claim graph schedules it first)")
        if claim_id not in citing.cites:
            citing.cites.append(claim_id)
    if claim_id not in _CACHE:
        _CACHE[claim_id] = get_claim(claim_id).certify()
    return _CACHE[claim_id]


def require_proven(cert: Certificate, claim_id: str) -> Certificate:
    """A step citing an earlier theorem declared in `uses`: it must be verified, or this proof stops."""
    with cert.step(f"uses {claim_id}", "citation of an earlier certificate", "-") as s:
        declared = REGISTRY[cert.claim_id].uses if cert.claim_id in REGISTRY else ()
        if claim_id not in declared:
            s.inconclusive(f"{cert.claim_id} cites {claim_id}, which is not declared in its @claim(uses=...) "
                           f"{list(declared)}: an undeclared citation is refused")
        dep = proven(claim_id)
        if claim_id not in cert.cites:
            cert.cites.append(claim_id)
        if dep.status is not Status.VERIFIED:
            s.inconclusive(f"{claim_id} is {dep.status.label}, not verified")
        s.note(f"{claim_id} verified")
    return dep
