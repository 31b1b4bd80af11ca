"""Regenerate the paper's figures with floats: Fig. "LV", Fig. "dET", plots 1-4 of section 6 (docs/figures/)."""
from __future__ import annotations

import itertools
import random
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from hkproof.dynamics import kahan_map  # noqa: E402
from hkproof.experiments.figures import euler_orbit, kahan_orbit, kernel_cloud  # noqa: E402
from hkproof.experiments.profiles import parse_basis  # noqa: E402

OUT = Path(__file__).resolve().parent.parent / "docs" / "figures"


def fig_lv() -> None:
    """Left: explicit Euler (step 0.01) spirals; right: three Kahan orbits (eps = 0.1) look closed."""
    f = kahan_map("lotka-volterra")
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4.5))
    e = euler_orbit(f, {}, [1.0, 0.5], 0.01, 6000)
    a.plot(e[:, 0], e[:, 1], lw=0.6)
    a.set_title("explicit Euler, step 0.01")
    for y0 in (0.3, 0.5, 0.7):
        o = kahan_orbit(f, {"eps": 0.1}, [1.0, y0], 1500)
        b.plot(o[:, 0], o[:, 1], ".", ms=1.2)
    b.set_title("Kahan map, eps = 0.1 (three orbits)")
    for ax in (a, b):
        ax.set_xlabel("x")
        ax.set_ylabel("y")
    fig.tight_layout()
    fig.savefig(OUT / "paper_fig_lv.png", dpi=110)


def fig_det() -> None:
    """Left: explicit Euler spiral for the Euler top (step 0.3); right: one HK orbit on an elliptic curve."""
    f = kahan_map("euler-top")
    alpha = {"a1": 1, "a2": -2, "a3": 1}
    fig = plt.figure(figsize=(10, 4.5))
    a = fig.add_subplot(1, 2, 1, projection="3d")
    e = euler_orbit(f, alpha, [0.3, 0.2, 0.1], 0.3, 600)
    e = e[: int(np.argmax(np.linalg.norm(e, axis=1) > 1)) or len(e)]   # until the spiral has left the picture
    a.plot(e[:, 0], e[:, 1], e[:, 2], ".-", lw=0.8, ms=3)
    a.set_title("explicit Euler, step 0.3")
    b = fig.add_subplot(1, 2, 2, projection="3d")
    o = kahan_orbit(f, {"eps": 0.3, **alpha}, [0.3, 0.2, 0.1], 3000)
    b.plot(o[:, 0], o[:, 1], o[:, 2], ".", ms=1)
    b.set_title("Hirota-Kimura map, eps = 0.3 (one orbit)")
    fig.tight_layout()
    fig.savefig(OUT / "paper_fig_det.png", dpi=110)


def plot_clebsch_orbit(name: str, omega: tuple[float, float, float], steps: int) -> None:
    """Plots 1 and 2: one orbit of the discrete Clebsch system from (1, ..., 1) with eps = 1."""
    f = kahan_map("clebsch")
    o = kahan_orbit(f, {"eps": 1, "w1": omega[0], "w2": omega[1], "w3": omega[2]}, [1.0] * 6, steps)
    fig = plt.figure(figsize=(10, 4.5))
    for i, (cols, label) in enumerate([((0, 1, 2), "m"), ((3, 4, 5), "p")]):
        ax = fig.add_subplot(1, 2, i + 1, projection="3d")
        ax.plot(o[:, cols[0]], o[:, cols[1]], o[:, cols[2]], ".", ms=0.6)
        _percentile_box(ax, o[:, list(cols)])
        ax.set_title(f"({label}1, {label}2, {label}3), omega = {omega}")
    fig.tight_layout()
    fig.savefig(OUT / name, dpi=110)


def plot3() -> None:
    """Plot 3: (c1, c2, c3) of K_Phi0 at 300 random points of [0, 1]^6 lie on a line."""
    f = kahan_map("clebsch")
    rng = random.Random(1)
    pts = [[round(rng.random(), 6) for _ in range(6)] for _ in range(300)]
    c = kernel_cloud(f, parse_basis(f.ring, "p1**2, p2**2, p3**2, 1"),
                     {"eps": 0.1, "w1": 0.1, "w2": 0.2, "w3": 0.3}, pts)
    fig = plt.figure(figsize=(6, 5))
    ax = fig.add_subplot(projection="3d")
    ax.scatter(c[:, 0], c[:, 1], c[:, 2], s=4)
    _percentile_box(ax, c[:, :3])
    ax.set_xlabel("c1")
    ax.set_ylabel("c2")
    ax.set_zlabel("c3")
    ax.set_title("plot 3: K_Phi0 at 300 random points (eps = 0.1, omega = 0.1, 0.2, 0.3)")
    fig.tight_layout()
    fig.savefig(OUT / "paper_plot3.png", dpi=110)


def plot4() -> None:
    """Plot 4: (d7, d8, d9) of K_Psi on the 729-point grid around (1, ..., 1), seen from two sides."""
    f = kahan_map("clebsch")
    grid = [list(p) for p in itertools.product((0.99, 1.0, 1.01), repeat=6)]
    k = kernel_cloud(f, parse_basis(f.ring, "p1**2, p2**2, p3**2, m1*p1, m2*p2, m3*p3"),
                     {"eps": 0.1, "w1": 0.1, "w2": 0.2, "w3": 0.3}, grid)
    d = k[:, 3:6] / -k[:, [0]]          # the paper's normalization d1 = d2 = d3 = -1
    fig = plt.figure(figsize=(10, 4.5))
    a = fig.add_subplot(1, 2, 1, projection="3d")
    a.scatter(d[:, 0], d[:, 1], d[:, 2], s=3)
    a.set_title("plot 4 (a): (d7, d8, d9), 729 grid points")
    a.set_xlabel("d7")
    a.set_ylabel("d8")
    a.set_zlabel("d9")
    # side view: distance from the best plane through the points against the main direction within it
    centered = d - d.mean(axis=0)
    _, _, vt = np.linalg.svd(centered, full_matrices=False)
    b = fig.add_subplot(1, 2, 2)
    b.plot(centered @ vt[0], centered @ vt[2], ".", ms=3)
    b.set_xlabel("main direction within the plane")
    b.set_ylabel("distance from the plane")
    b.set_title(f"plot 4 (b): side view, normal ~ {np.round(vt[2] / vt[2][0] * -0.1, 3)}")
    fig.tight_layout()
    fig.savefig(OUT / "paper_plot4.png", dpi=110)


def _percentile_box(ax, xyz: np.ndarray, q: float = 2.0) -> None:
    """Axis limits from the q-th to the (100-q)-th percentile: orbits passing near Delta = 0 jump far away."""
    lo, hi = np.nanpercentile(xyz, q, axis=0), np.nanpercentile(xyz, 100 - q, axis=0)
    pad = 0.1 * (hi - lo)
    ax.set_xlim(lo[0] - pad[0], hi[0] + pad[0])
    ax.set_ylim(lo[1] - pad[1], hi[1] + pad[1])
    ax.set_zlim(lo[2] - pad[2], hi[2] + pad[2])


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    jobs = {"lv": fig_lv, "det": fig_det,
            "plot1": lambda: plot_clebsch_orbit("paper_plot1.png", (1, 0.2, 30), 20000),
            "plot2": lambda: plot_clebsch_orbit("paper_plot2.png", (0.1, 0.2, 0.3), 20000),
            "plot3": plot3, "plot4": plot4}
    for name in sys.argv[1:] or jobs:
        jobs[name]()
        print(f"wrote {name}")


if __name__ == "__main__":
    main()
