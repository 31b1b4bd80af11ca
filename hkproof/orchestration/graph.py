"""The claim graph: an edge from a claim to each claim it cites (`@claim(uses=...)`), dependencies first."""
from __future__ import annotations

from typing import Iterable, Mapping

from hkproof.errors import CitationCycleError, UnknownClaimError
from hkproof.orchestration.registry import Claim

__all__ = ["in_dependency_order"]



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
