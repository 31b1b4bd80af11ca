"""`discover`: HK-bases by algorithm (N) on monomials, kernel coordinates reconstructed, integrals certified."""
from hkproof.pipelines.discover.report import DiscoveryReport, FoundIntegral
from hkproof.pipelines.discover.run import discover

__all__ = ["DiscoveryReport", "FoundIntegral", "discover"]
