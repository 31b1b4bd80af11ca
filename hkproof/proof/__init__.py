"""Claims, steps, certificates and the registry of the paper's theorems."""
from hkproof.proof.certificate import Certificate, ProofStopped, Refuted, Step
from hkproof.proof.registry import REGISTRY, Claim, claim, get_claim, load_all, proven, require_proven, select
from hkproof.proof.status import Status

__all__ = ["Certificate", "Claim", "ProofStopped", "REGISTRY", "Refuted", "Status", "Step", "claim", "get_claim",
           "load_all", "proven", "require_proven", "select"]
