"""Scans through the default process pool, the progress bar, and the scaling weights used by recipe (E)."""
from __future__ import annotations

import io

from hkproof.dynamics import kahan_map
from hkproof.experiments import scan
from hkproof.experiments.progress import bar, message_bar
from hkproof.experiments.weights import scaling_weights


def test_a_long_scan_runs_in_the_default_process_pool():
    result = scan("clebsch", "p1**2, p2**2, p3**2, 1", points=16, arithmetic="modular", with_kernel=False)
    assert len(result.profiles) == 16 and result.dimension == 1


def test_progress_bar_counts_points():
    """tqdm on the given stream when enabled; nothing off a terminal (a StringIO is none) or when disabled."""
    out = io.StringIO()
    with bar(4, "points", enabled=True, stream=out) as shown:
        shown.update(3)
        shown.update(1)
        shown.refresh()
    assert "4/4" in out.getvalue() and "points" in out.getvalue()
    for enabled in (None, False):
        silent = io.StringIO()
        with bar(4, "points", enabled=enabled, stream=silent) as shown:
            shown.update(4)
        assert silent.getvalue() == ""


def test_message_bar_shows_pipeline_lines():
    out = io.StringIO()
    with bar(None, "events", enabled=True, stream=out) as shown:
        message_bar(shown)("discover: screening (0.1 s)")
        shown.refresh()
    assert "discover: screening" in out.getvalue()


def test_scaling_weights_of_the_clebsch_flows():
    """m -> l^a m, p -> l^b p, omega -> l^(2a-2b) omega, eps -> l^-a eps: eps and w1 can be set to 1."""
    for system in ("clebsch", "clebsch-flow2"):
        weights = scaling_weights(kahan_map(system))
        assert weights.normalized == ("eps", "w1") and len(weights.basis) == 2
    fixed = scaling_weights(kahan_map("clebsch"), fixed=["eps"])
    assert "eps" not in fixed.normalized
