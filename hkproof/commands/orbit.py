"""`hkproof orbit SYSTEM POINT --steps N [--plot FILE.png]`: an exact orbit over Q, its period, and a float picture."""
from __future__ import annotations

import argparse
from typing import Any
import random

from hkproof.commands import (Result, add_budget_option, add_command, add_system_argument, add_values_options,
                              at_least, fixed_values)
from hkproof.commands._geometry import EPS_CONVENTION
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.orbits import exact_orbit
from hkproof.dynamics.values import parse_point
from hkproof.experiments.orbit_plot import check_plot_path, plot_orbit
from hkproof.experiments.points import random_values

__all__ = ["register", "run_orbit"]


def register(sub: argparse._SubParsersAction) -> None:
    p = add_command(sub, "orbit", "the exact orbit of a rational point under the Kahan map (over Q), stopped when it "
                    "closes (periodic orbit), and a PNG of a float orbit in coordinate projections. "
                    f"{EPS_CONVENTION}.", run_orbit)
    add_budget_option(p)
    add_system_argument(p)
    p.add_argument("point", help='the initial point: exact rationals separated by commas, e.g. "1/2, 3, -1"')
    p.add_argument("--steps", type=at_least(0), default=20, help="exact steps (default 20)")
    p.add_argument("--plot", metavar="FILE.png", help="write a picture of the float orbit to FILE.png")
    p.add_argument("--plot-steps", type=at_least(1), default=3000, help="float steps drawn in the picture (default 3000)")
    p.add_argument("--max-digits", type=at_least(1), default=100_000,
                   help="stop the exact orbit when a coordinate has more digits (default 100000)")
    add_values_options(p)


def run_orbit(args: argparse.Namespace) -> Result:
    f = kahan_map(args.system)
    point = parse_point(f.field, args.point)
    if args.plot:
        check_plot_path(args.plot)
    values = random_values(f, random.Random(args.seed), fixed_values(args))  # checked there, the others random
    orbit = exact_orbit(f, point, values, args.steps, args.max_digits)
    at = ", ".join(f"{k} = {v}" for k, v in values.items())
    payload: dict[str, Any] = {"system": f.field.name, "values": {k: str(v) for k, v in values.items()},
               "eps_convention": EPS_CONVENTION, "variables": list(f.variables),
               "orbit": [[str(x[v]) for v in f.variables] for x in orbit.points],
               "period": orbit.period, "preperiod": orbit.preperiod, "closes": orbit.closes, "stopped": orbit.stopped,
               "digits": [orbit.height(i) for i in range(len(orbit.points))]}
    lines = [f"exact orbit of ({', '.join(str(point[v]) for v in f.variables)}) under the Kahan map of {f.field.name}"
             f" at {at} ({EPS_CONVENTION})"]
    for i, x in enumerate(orbit.points):
        text = ", ".join(str(x[v]) for v in f.variables)
        if len(text) > 160:
            text = text[:150] + f" ... ({orbit.height(i)} digits)"
        lines.append(f"  x_{i} = ({text})")
    lines.append(orbit.outcome())
    if args.plot:
        drawn = plot_orbit(f, values, [point[v] for v in f.variables], args.plot_steps, args.plot)
        payload["plot"] = {"file": args.plot, "points": drawn, "arithmetic": "float64"}
        lines.append(f"wrote {args.plot}: {drawn} points of the float64 orbit")
    return Result(payload, "\n".join(lines))
