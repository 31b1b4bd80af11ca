"""hkproof: exact, certified proofs of integrability of Kahan / Hirota-Kimura discretizations of quadratic ODEs.

The notebook API (`import hkproof as hk`): `hk.system`, `hk.kahan_map`, `hk.discover`, `hk.measure`, `hk.degrees`,
`hk.orbit`, `hk.orbit_figure`, `hk.scan`, `hk.check_integral`, `hk.prove`, `hk.to_sympy`, the classes
`QuadraticField` and `KahanMap`, and `hk.sage` (Sage interop, the `sage` extra); results show in Jupyter as Markdown
with LaTeX (docs/tutorial.ipynb). Names are loaded on first use, so
`import hkproof` stays light. hkproof's eps is half the time step (x~ - x = 2 eps * polarized field).
"""
from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

__all__ = ["KahanMap", "QuadraticField", "check_integral", "degrees", "discover", "kahan_map", "measure", "orbit",
           "orbit_figure", "poisson", "prove", "sage", "scan", "system", "to_sympy"]

_HOMES = {"KahanMap": "hkproof.dynamics.kahan", "QuadraticField": "hkproof.dynamics.field"}

if TYPE_CHECKING:
    from hkproof.api import (check_integral, degrees, discover, kahan_map, measure, orbit, orbit_figure, poisson, prove,
                             scan, system, to_sympy)
    from hkproof.dynamics.field import QuadraticField
    from hkproof.dynamics.kahan import KahanMap
    from hkproof import sage


def __getattr__(name: str) -> Any:
    if name not in __all__:
        raise AttributeError(f"module 'hkproof' has no attribute {name!r}")
    if name == "sage":      # the Sage interop module (Sage itself is imported on first use)
        return importlib.import_module("hkproof.sage")
    return getattr(importlib.import_module(_HOMES.get(name, "hkproof.api")), name)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
