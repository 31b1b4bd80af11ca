"""Group lotka-volterra (sec. 2): the explicit Kahan map and its Poisson bracket, certified by the group script."""
from __future__ import annotations

from tests.conftest import assert_group_certified


def test_the_script_certifies_the_group(monkeypatch, capsys):
    assert_group_certified("lotka-volterra", monkeypatch, capsys)
