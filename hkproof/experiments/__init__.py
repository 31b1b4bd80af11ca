"""Experiments that know their accuracy: algorithm (N) in four arithmetics and relation finding (recipe (E))."""
from hkproof.experiments.approximate import Float64, MPMath
from hkproof.experiments.arithmetics import ExactQ
from hkproof.experiments.choice import get_arithmetic
from hkproof.experiments.profiles_mod_p import Modular
from hkproof.experiments.profiles import KernelProfile, ProfileProblem, fundamental_finite, parse_basis
from hkproof.experiments.scan import ScanResult, scan
from hkproof.experiments.scene import Scene, make_scene

__all__ = ["ExactQ", "Float64", "KernelProfile", "MPMath", "Modular", "ProfileProblem", "ScanResult", "Scene",
           "fundamental_finite", "get_arithmetic", "make_scene", "parse_basis", "scan"]
