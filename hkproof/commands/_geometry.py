"""Wording shared by the geometry commands (degrees, orbit, measure, hamiltonian)."""
from __future__ import annotations

from hkproof.dynamics.field import STEP_CONVENTION as EPS_CONVENTION

__all__ = ["EPS_CONVENTION"]
