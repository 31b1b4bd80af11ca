"""hkproof orbit: exact orbits, periods, pictures, and bad points refused with exit 2."""
from __future__ import annotations

import json
from pathlib import Path

import flint
import pytest

from hkproof.cli import main
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.orbits import exact_orbit
from hkproof.errors import SingularPointError

OSC = str(Path(__file__).resolve().parent.parent / "docs" / "examples" / "oscillator.toml")


def run(capsys, *args: str) -> tuple[int, dict]:
    code = main([*args, "--json"])
    return code, json.loads(capsys.readouterr().out)


def test_cayley_rotation_by_a_quarter_turn_has_period_4(capsys):
    # x' = y, y' = -x with eps = 1: the Kahan map is the Cayley transform, a rotation by 2 arctan(eps) = pi/2
    code, out = run(capsys, "orbit", OSC, "1, 0", "--eps", "1", "--param", "k=1", "--steps", "10")
    assert code == 0 and out["period"] == 4 and out["closes"]
    assert out["orbit"] == [["1", "0"], ["0", "-1"], ["-1", "0"], ["0", "1"]]


def test_a_perturbed_eps_is_not_periodic(capsys):
    code, out = run(capsys, "orbit", OSC, "1, 0", "--eps", "99/100", "--param", "k=1", "--steps", "10")
    assert code == 0 and out["period"] is None and len(out["orbit"]) == 11


def test_orbit_agrees_with_the_map_and_the_equilibrium_is_fixed():
    f = kahan_map("euler-top")
    values = {"eps": flint.fmpq(1, 10), "a1": flint.fmpq(1), "a2": flint.fmpq(-2), "a3": flint.fmpq(1)}
    orbit = exact_orbit(f, {"x1": flint.fmpq(1, 2), "x2": flint.fmpq(3), "x3": flint.fmpq(-1)}, values, 3)
    x1 = [c.evaluate({**values, **orbit.points[0]}) for c in f.components()]
    assert x1 == [orbit.points[1][v] for v in f.variables]
    fixed = exact_orbit(kahan_map("lotka-volterra"), {"x": flint.fmpq(1), "y": flint.fmpq(1)},
                        {"eps": flint.fmpq(1, 2)}, 5)
    assert fixed.period == 1


def test_plot_writes_a_png(capsys, tmp_path):
    png = tmp_path / "orbit.png"
    code, out = run(capsys, "orbit", "clebsch", "1,1,1,1,1,1", "--steps", "1", "--eps", "1/10",
                    "--plot", str(png), "--plot-steps", "200")
    assert code == 0 and png.read_bytes()[:4] == b"\x89PNG" and out["plot"]["points"] == 201


def test_singular_point_is_a_clear_error():
    # det M = (1/2 + y/2)(3/2 - x/2) + x y / 4 vanishes at (3, 0) for eps = 1/2
    with pytest.raises(SingularPointError, match="singular"):
        exact_orbit(kahan_map("lotka-volterra"), {"x": flint.fmpq(3), "y": flint.fmpq(0)}, {"eps": flint.fmpq(1, 2)}, 3)


@pytest.mark.parametrize("args", [("lotka-volterra", "3, 0", "--eps", "1/2"), ("lotka-volterra", "1, 2, 3"),
                                  ("lotka-volterra", "1, x"), ("lotka-volterra", "1, 2", "--plot", "o.pdf"),
                                  ("lotka-volterra", "1, 2", "--param", "k=1"), ("no-such-system", "1")])
def test_bad_input_exit_2(capsys, args):
    assert main(["orbit", *args]) == 2
    assert "error" in capsys.readouterr().err
