"""A picture of one orbit in float64, in the style of the paper's figures: 3D projections on triples of coordinates
(x1, x2, x3), (m, p) for Clebsch, and planar ones on the remaining pairs."""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Mapping, Sequence

import numpy as np

from hkproof.algebra.ring import Rational
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import HKProofError, ParseError, SingularPointError
from hkproof.experiments.figures import kahan_orbit

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["check_plot_path", "float_orbit", "orbit_figure", "panels", "plot_orbit"]


def float_orbit(kmap: KahanMap, values: Mapping[str, object], x0: Sequence[Rational], steps: int) -> np.ndarray:
    """The orbit in float64 (rows x_0..x_steps), by experiments.figures.kahan_orbit."""
    try:
        return kahan_orbit(kmap, {k: str(v) for k, v in values.items()}, [float(v) for v in x0], steps)
    except np.linalg.LinAlgError:
        raise SingularPointError("the float orbit meets a matrix M(x, eps) that is singular in float64; "
                                 "plot fewer steps or another point") from None


def panels(names: Sequence[str]) -> list[tuple[int, ...]]:
    """Coordinates in groups of three (3D panels), the rest in pairs or alone (planar panels)."""
    idx = list(range(len(names)))
    out = []
    while len(idx) >= 3 and len(idx) != 4:
        out.append(tuple(idx[:3]))
        idx = idx[3:]
    while idx:
        out.append(tuple(idx[:2]))
        idx = idx[2:]
    return out


def check_plot_path(path: str | Path) -> Path:
    """The picture's file: a .png in an existing directory."""
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise ParseError(f"the plot file {path} must end in .png")
    if not path.parent.resolve().is_dir():
        raise ParseError(f"the directory of the plot file {path} does not exist")
    return path


def orbit_figure(kmap: KahanMap, values: Mapping[str, object], x0: Sequence[Rational], steps: int) -> tuple[Figure, int]:
    """A matplotlib figure of the float orbit of x0 (no pyplot: it displays in Jupyter and saves with Agg), and the
    number of points drawn."""
    from matplotlib.figure import Figure

    orbit = float_orbit(kmap, values, x0, steps)
    orbit = orbit[np.all(np.isfinite(orbit), axis=1)]
    names = kmap.variables
    groups = panels(names)
    fig = Figure(figsize=(max(7.0, 5 * len(groups)), 5))
    shown = ", ".join(f"{k} = {v}" for k, v in values.items())
    for i, cols in enumerate(groups):
        ax = fig.add_subplot(1, len(groups), i + 1, **({"projection": "3d"} if len(cols) == 3 else {}))
        data = [orbit[:, c] for c in cols] if len(cols) > 1 else [np.arange(len(orbit)), orbit[:, cols[0]]]
        ax.plot(*data, ".", ms=1)
        labels = [names[c] for c in cols] if len(cols) > 1 else ["n", names[cols[0]]]
        for setter, label in zip((ax.set_xlabel, ax.set_ylabel, getattr(ax, "set_zlabel", None)), labels, strict=True):
            if setter is not None:
                setter(label)
        _percentile_limits(ax, np.array(data).T)
        ax.set_title(f"({', '.join(labels)})", fontsize=9)
    fig.suptitle(f"Kahan map of {kmap.field.name}, {len(orbit)} points (float64)\n{shown} (eps = half the time step)",
                 fontsize=10)
    fig.tight_layout()
    return fig, len(orbit)


def plot_orbit(kmap: KahanMap, values: Mapping[str, object], x0: Sequence[Rational], steps: int,
               path: str | Path) -> int:
    """Write a PNG of the float orbit of x0 (matplotlib, Agg); returns the number of points drawn."""
    path = check_plot_path(path)
    fig, drawn = orbit_figure(kmap, values, x0, steps)
    try:
        fig.savefig(path, dpi=110)
    except OSError as exc:
        raise HKProofError(f"cannot write the plot {path}: {exc}") from None
    return drawn


def _percentile_limits(ax, xyz: np.ndarray, q: float = 1.0) -> None:
    """Axis limits from the q-th to the (100-q)-th percentile: orbits passing near Delta = 0 jump far away."""
    lo, hi = np.nanpercentile(xyz, q, axis=0), np.nanpercentile(xyz, 100 - q, axis=0)
    pad = 0.1 * (hi - lo) + 1e-12
    setters = (ax.set_xlim, ax.set_ylim, getattr(ax, "set_zlim", None))
    for setter, a, b, c in zip(setters, lo, hi, pad, strict=True):
        setter(a - c, b + c)
