"""The notebook front end: docs/tutorial.ipynb executed by a real Jupyter kernel (nbclient), and the mime bundles
Jupyter gets from hkproof's result objects (Markdown with LaTeX, checked through IPython's own formatter)."""
from __future__ import annotations

from pathlib import Path

import nbclient
import nbformat
import pytest
from IPython.core.interactiveshell import InteractiveShell

import hkproof as hk

TUTORIAL = Path(__file__).resolve().parents[1] / "docs" / "tutorial.ipynb"


@pytest.fixture(scope="module")
def shell() -> InteractiveShell:
    return InteractiveShell.instance()


def markdown(shell: InteractiveShell, obj: object) -> str:
    data, _ = shell.display_formatter.format(obj)
    assert "text/markdown" in data, sorted(data)
    return data["text/markdown"]


def test_the_tutorial_runs_in_a_jupyter_kernel():
    """Every cell runs without error in the python3 kernel (ipykernel's own spec, the running interpreter), the
    results arrive as Markdown, the pictures as PNG."""
    nb = nbformat.read(TUTORIAL, as_version=4)
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(TUTORIAL.parent)}}).execute()
    outputs = [o for cell in nb.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    kinds = [kind for o in outputs for kind in o.get("data", {})]
    assert kinds.count("image/png") == 2 and kinds.count("text/markdown") >= 8
    shown = "\n".join(o["data"].get("text/markdown", "") for o in outputs if "data" in o)
    assert "| verified |" in shown and "| refuted |" in shown and "**[verified] et-explicit-map**" in shown


def test_results_render_as_markdown_with_latex(shell):
    top = hk.system(["x", "y", "z"], ["a*y*z", "b*z*x", "c*x*y"], parameters=["a", "b", "c"], name="top")
    cert = hk.check_integral(top, "(c*y**2 - b*z**2)/(b*x**2 - a*y**2)")
    text = markdown(shell, cert)
    assert text.startswith("**[verified] integral**") and r"\frac" in text and "exact substitution" in text
    assert r"\varepsilon" in markdown(shell, hk.kahan_map(top))
    orbit = hk.orbit(top, "1, 2, 3", steps=2, values={"eps": "1/10", "a": 1, "b": -2, "c": 1})
    assert "| x_1 | 65/37 | 10/37 | 125/37 |" in markdown(shell, orbit)
    assert "deg f^n | 3 | 9 | 19 |" in markdown(shell, hk.degrees(top, 3))
    assert "| verified |" in markdown(shell, hk.discover(top, 2, seconds=60))
    assert "cofactor K" in markdown(shell, hk.measure("lotka-volterra", 2))
    shown = markdown(shell, hk.poisson("lotka-volterra", 2, integrals_degree=0))
    assert r"Pi1 (verified, Poisson, rank 2" in shown and r"\{x, y\}" in shown and "| F1*F2 | $x y$ | 2 | verified |" in shown


def test_results_convert_to_sympy():
    import sympy

    report = hk.discover("lotka-volterra", 1, seconds=60)
    assert all(isinstance(e, sympy.Expr) for e in hk.to_sympy(report).values())
    assert hk.to_sympy(hk.measure("lotka-volterra", 2))["darboux"]
    [cert] = hk.prove("lv-explicit-map")
    assert sympy.simplify(hk.to_sympy(cert)["Delta"] - cert.values["Delta"].to_sympy()) == 0
    assert hk.to_sympy(hk.orbit("lotka-volterra", "1, 2", steps=1, values={"eps": "1/4"}))[0] == (1, 2)
    with pytest.raises(TypeError):
        hk.to_sympy(3)


def test_a_false_integral_is_refuted_in_its_certificate():
    cert = hk.check_integral("lotka-volterra", "x + y")
    assert cert.status.label == "refuted" and "terms" in cert.steps[0].detail
