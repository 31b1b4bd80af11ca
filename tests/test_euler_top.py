"""Group euler-top (sec. 5): the Euler top map, its HK-bases and integrals, certified by the group script."""
from __future__ import annotations

from tests.conftest import assert_group_certified


def test_the_script_certifies_the_group(monkeypatch, capsys):
    assert_group_certified("euler-top", monkeypatch, capsys)
