"""`hkproof map SYSTEM`: the explicit Kahan map N/Delta of a catalogue or TOML system."""
from __future__ import annotations

import argparse

from hkproof.algebra.fraction import poly_str
from hkproof.commands import Result, add_command, add_system_argument
from hkproof.dynamics.catalogue import SYSTEMS, kahan_map

__all__ = ["register", "run_map", "run_systems"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "map", "print the explicit Kahan map x~ = N(x)/Delta(x) of a system", run_map)
    add_system_argument(p)
    p = add_command(sub, "systems", "list the catalogue of systems", run_systems)


def run_map(args: argparse.Namespace) -> Result:
    f = kahan_map(args.system)
    nums, delta = f.explicit
    comps = {f"{v}_tilde": str(c) for v, c in zip(f.variables, f.components(), strict=True)}
    payload = {"system": f.field.name, "variables": list(f.variables), "parameters": list(f.field.parameters),
               "ring": f"Q[{', '.join(f.ring.names)}]", "denominator": poly_str(delta),
               "numerators": {f"{v}_tilde": poly_str(p) for v, p in zip(f.variables, nums, strict=True)},
               "components": comps}
    lines = [f"Kahan map of {f.field.name} in Q[{', '.join(f.ring.names)}]:",
             f"  Delta = {poly_str(delta)}"]
    lines += [f"  {v}~ = ({poly_str(p)}) / Delta" for v, p in zip(f.variables, nums, strict=True)]
    return Result(payload, "\n".join(lines))


def run_systems(args: argparse.Namespace) -> Result:
    payload = [{"name": f.name, "variables": list(f.variables), "parameters": list(f.parameters),
                "rhs": list(f.rhs_text), "description": f.description} for f in SYSTEMS.values()]
    text = "\n".join(f"{f.name}: {f.description}\n    " +
                     "\n    ".join(f"{v}' = {r}" for v, r in zip(f.variables, f.rhs_text, strict=True)) for f in SYSTEMS.values())
    return Result(payload, text)
