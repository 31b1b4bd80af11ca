"""Deprecated location of the registry, kept only for importers not yet moved (hkproof/commands/depend.py):
the registry is orchestration, hkproof.orchestration.registry. Delete this module once nothing imports it."""
from hkproof.orchestration.registry import REGISTRY, Claim, claim, get_claim, load_all, proven, require_proven, select

__all__ = ["REGISTRY", "Claim", "claim", "get_claim", "load_all", "proven", "require_proven", "select"]
