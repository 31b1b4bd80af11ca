"""Wording shared by the geometry commands (degrees, orbit, measure, hamiltonian)."""
from __future__ import annotations

from hkproof.proof.status import Status

EPS_CONVENTION = ("hkproof's eps is HALF the time step: x~ - x = 2 eps * (polarized field), i.e. h = 2 eps in the "
                  "convention of Celledoni-McLachlan-Owren-Quispel")


def specialized_status(status: Status, fixed: dict) -> str:
    """The label of a status, lowered to verified(specialized: ...) when parameters were fixed."""
    if fixed and status is Status.VERIFIED:
        return f"verified(specialized: {', '.join(f'{k}={v}' for k, v in fixed.items())})"
    return status.label
