"""hk/transport.Substitution: names replaced by rational functions (one compose), as the sec. 6 proofs use it."""
from __future__ import annotations

import pytest

from hkproof.algebra import Frac
from hkproof.algebra.ring import get_ring
from hkproof.errors import HKProofError
from hkproof.hk.transport import Substitution

R = get_ring(("x", "y"))
BIG = R.extend(["A", "L"])


def test_names_replaced_by_fractions_agree_with_the_direct_formula():
    sigma = Substitution(BIG, R, {"A": Frac.parse(R, "x/(y + 1)"), "L": Frac.parse(R, "1/x")})
    q = Frac.parse(BIG, "A**2*L - x/(A + L)")
    direct = Frac.parse(R, "(x/(y + 1))**2/x - x/(x/(y + 1) + 1/x)")
    assert sigma.apply(q) == direct
    assert direct.is_ratio(*sigma.apply_terms(q))
    assert sigma.apply(q) != Frac.parse(R, "(x/(y + 1))**2/x + x/(x/(y + 1) + 1/x)")


def test_a_kept_name_missing_from_the_target_is_refused():
    with pytest.raises(HKProofError):
        Substitution(BIG, R, {"A": Frac.parse(R, "x")})
