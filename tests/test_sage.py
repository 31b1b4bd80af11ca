"""Sage interop (the `sage` extra, passagemath): a round trip of a system and of exact results; skipped cleanly where
passagemath is not installed."""
from __future__ import annotations

import pytest

import hkproof as hk
from hkproof.errors import MissingDependencyError

try:
    import sage.all__sagemath_singular as sage
except ImportError:
    sage = None

needs_sage = pytest.mark.skipif(sage is None, reason="passagemath is not installed (pip install 'hkproof[sage]')")


@needs_sage
def test_a_system_from_sage_polynomials_and_its_integral_back_in_sage():
    R = sage.PolynomialRing(sage.QQ, ["x", "y", "z", "a", "b", "c", "eps"])
    x, y, z, a, b, c, eps = R.gens()
    field = hk.sage.from_sage([a * y * z, b * z * x, c * x * y], name="sage-top")
    assert field.variables == ("x", "y", "z") and field.parameters == ("a", "b", "c")
    assert hk.sage.to_sage(field, R) == [a * y * z, b * z * x, c * x * y]
    report = hk.discover(field, 2, seconds=60)
    found = hk.sage.to_sage(report, R.fraction_field())
    assert found["I1"] == (c * y**2 - b * z**2) / (b * x**2 - a * y**2)
    assert found["I1"].parent() is R.fraction_field()
    assert found["I2"] == b * (a * c * eps**2 * y**2 - 1) / (b * x**2 - a * y**2)


@needs_sage
def test_certificates_and_orbits_in_sage():
    [cert] = hk.prove("lv-explicit-map")
    values = hk.sage.to_sage(cert)
    x, y, eps = sage.PolynomialRing(sage.QQ, ["x", "y", "eps"]).gens()
    assert values["Delta"] == 1 - eps * x + eps * y + eps**2 * (x + y - 1)
    orbit = hk.orbit("lotka-volterra", "1, 2", steps=1, values={"eps": "1/4"})
    assert hk.sage.to_sage(orbit)[0] == (sage.QQ(1), sage.QQ(2))
    univariate = sage.PolynomialRing(sage.QQ, "t")
    t = univariate.gen()
    assert hk.sage.to_sage(hk.sage.from_sage([t**2 - 3 / sage.QQ(2)]), univariate) == [t**2 - 3 / sage.QQ(2)]


def test_without_sage_the_interop_says_what_to_install(monkeypatch):
    import builtins

    real = builtins.__import__

    def no_sage(name, *args, **kwargs):
        if name.startswith("sage"):
            raise ImportError(name)
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_sage)
    with pytest.raises(MissingDependencyError, match=r"hkproof\[sage\]"):
        hk.sage.sage_ring(["x"])
