"""The proof kernel: the status ladder, steps and certificates (orchestration lives in hkproof.orchestration)."""
from hkproof.proof.certificate import Certificate, ProofStopped, Refuted, Step
from hkproof.proof.status import Status

__all__ = ["Certificate", "ProofStopped", "Refuted", "Status", "Step"]
