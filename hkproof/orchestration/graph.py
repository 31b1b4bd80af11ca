"""The claim graph: an edge from a claim to each claim it cites (`@claim(uses=...)`), dependencies first."""
from __future__ import annotations

from typing import Callable, Iterable, Mapping, Sequence

from hkproof.errors import CitationCycleError, UnknownClaimError
from hkproof.orchestration.registry import Claim

__all__ = ["critical_path_first", "in_dependency_order"]


def in_dependency_order(ids: Iterable[str], registry: Mapping[str, Claim]) -> list[str]:
    """`ids` and every claim they cite, transitively, in layers: each layer cites only earlier ones, and keeps
    registration order. A citation of an unregistered id or a cycle of citations is refused.

    >>> from types import SimpleNamespace as C
    >>> in_dependency_order(["c"], {"a": C(uses=()), "b": C(uses=("a",)), "c": C(uses=("b", "a"))})
    ['a', 'b', 'c']
    """
    position = {cid: k for k, cid in enumerate(registry)}
    wanted: set[str] = set()
    stack = list(ids)
    while stack:
        cid = stack.pop()
        if cid in wanted:
            continue
        if cid not in registry:
            raise UnknownClaimError(f"'{cid}' is cited (uses=) but is not a registered claim")
        wanted.add(cid)
        stack.extend(registry[cid].uses)
    order: list[str] = []
    placed: set[str] = set()
    waiting = sorted(wanted, key=position.__getitem__)
    while waiting:
        ready = [cid for cid in waiting if placed.issuperset(registry[cid].uses)]
        if not ready:
            raise CitationCycleError(f"the citations (uses=) of {waiting} form a cycle")
        order += ready
        placed.update(ready)
        waiting = [cid for cid in waiting if cid not in placed]
    return order


def critical_path_first(order: Sequence[str], registry: Mapping[str, Claim], weight: Callable[[Claim], float]
                        ) -> list[str]:
    """`order` (dependencies first) sorted by each claim's level, its weight plus the largest level among the claims
    of `order` that cite it, highest first (stable): list scheduling on the longest chain, so that a short claim
    that a long chain waits for starts before a long claim that nothing waits for.

    >>> from types import SimpleNamespace as C
    >>> reg = {"a": C(uses=(), w=1), "b": C(uses=("a",), w=5), "c": C(uses=(), w=3)}
    >>> critical_path_first(["a", "c", "b"], reg, lambda claim: claim.w)
    ['a', 'b', 'c']
    """
    level: dict[str, float] = {}
    for cid in reversed(order):
        citing = [level[d] for d in order if d in level and cid in registry[d].uses]
        level[cid] = weight(registry[cid]) + max(citing, default=0)
    return sorted(order, key=lambda cid: -level[cid])
