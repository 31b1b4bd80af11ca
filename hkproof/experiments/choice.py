"""Choose an arithmetic for algorithm (N) by name."""
from __future__ import annotations

from hkproof.experiments.approximate import Float64, MPMath
from hkproof.experiments.arithmetics import Arithmetic, ExactQ
from hkproof.experiments.profiles_mod_p import Modular

__all__ = ["get_arithmetic"]


def get_arithmetic(name: str, *, digits: int = 50, seed: int = 0) -> Arithmetic:
    """'exact', 'modular', 'float' or 'mpmath' (at `digits` decimal digits)."""
    if name == "exact":
        return ExactQ()
    if name == "modular":
        return Modular(seed=seed)
    if name == "float":
        return Float64()
    if name == "mpmath":
        return MPMath(digits)
    raise ValueError(f"unknown arithmetic {name!r}: use exact, modular, float or mpmath")
