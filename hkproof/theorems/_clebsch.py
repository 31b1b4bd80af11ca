"""Shared data of section 6: the Clebsch integrals (eqs. "Clebsch H1" ... "Clebsch I") and the cyclic symmetry."""
from __future__ import annotations

from functools import lru_cache
from typing import Mapping

import flint

from hkproof.algebra.formula import cycled as formula_cycled
from hkproof.algebra.formula import parse_rational, rename
from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring
from hkproof.dynamics.catalogue import CLEBSCH_VARS
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.symmetries import SignedPermutation
from hkproof.hk.translation import ParameterTranslation
from hkproof.proof.certificate import Certificate

SYSTEM = "clebsch"
X = CLEBSCH_VARS
H = {
    "H1": "m1**2 + m2**2 + m3**2 + w1*p1**2 + w2*p2**2 + w3*p3**2",
    "H2": "w1*m1**2 + w2*m2**2 + w3*m3**2 - w2*w3*p1**2 - w3*w1*p2**2 - w1*w2*p3**2",
    "H3": "p1**2 + p2**2 + p3**2",
    "H4": "m1*p1 + m2*p2 + m3*p3",
}
I = {
    "I1": "p1**2 + m2**2/(w1 - w3) + m3**2/(w1 - w2)",
    "I2": "p2**2 + m1**2/(w2 - w3) + m3**2/(w2 - w1)",
    "I3": "p3**2 + m1**2/(w3 - w2) + m2**2/(w3 - w1)",
}
# p x (Omega + c Id) p = p x Omega p: the flow, f and the integrals' span depend on w only through w_i - w_j
# (each proof that uses this checks the invariance of what it needs).
TRANSLATION = ParameterTranslation(("w1", "w2", "w3"), "w3")
PHI_MAX = ("p1**2", "p2**2", "p3**2", "m1**2", "m2**2", "m3**2", "m1*p1", "m2*p2", "m3*p3", "1")

_CYCLE = {"m1": "m2", "m2": "m3", "m3": "m1", "p1": "p2", "p2": "p3", "p3": "p1", "w1": "w2", "w2": "w3",
          "w3": "w1", "d7": "d8", "d8": "d9", "d9": "d7", "g1": "g2", "g2": "g3", "g3": "g1"}


CYCLIC_SHIFT = SignedPermutation(tuple((f"{x}{k}", f"{x}{k % 3 + 1}", 1) for x in "mp" for k in (1, 2, 3)),
                                 tuple((f"w{k}", f"w{k % 3 + 1}") for k in (1, 2, 3)))
"""The index shift 1 -> 2 -> 3 -> 1 on m, p and w, as a signed permutation (`hk.symmetries`): its `commutes` checks
that it is a symmetry of a Kahan map exactly (tau(f_v) = f_(tau v) for every component)."""


def cycled(text: str, times: int = 1) -> str:
    """The formula with every index shifted cyclically 1 -> 2 -> 3 -> 1, `times` times.

    >>> cycled("w1*p2**2 - d7", 2)
    'w3*p1**2 - d9'
    """
    return formula_cycled(text, _CYCLE, times % 3)


def shift(ring: Ring, p: flint.fmpz_mpoly) -> flint.fmpz_mpoly:
    """p with every index shifted cyclically (the renaming of `cycled`, done by one compose)."""
    return ring.substitute(p, {n: ring.gen(_CYCLE[n]) for n in ring.names if n in _CYCLE})


def record(cert: Certificate, name: str, value: Frac) -> None:
    """cert.formula(name, value): the certificate keeps the exact value, so that later proofs need not re-parse it."""
    cert.formula(name, value)


def recall(cert: Certificate, name: str, ring: Ring) -> Frac:
    """A formula of an earlier certificate as an exact element of `ring`: the value the certificate keeps, or its
    text read again (another ring, or a certificate that kept no value)."""
    kept = cert.values.get(name)
    return kept if kept is not None and kept.ring == ring else Frac.parse(ring, cert.formulas[name])


def shift_frac(h: Frac) -> Frac:
    """The rational function with every index shifted cyclically."""
    return Frac(h.ring, shift(h.ring, h.num), shift(h.ring, h.den))


def number(text: str) -> flint.fmpq:
    """A claimed count or degree, read exactly (so that '(6) + 1/7' is a different number, not an error)."""
    return parse_rational(text)


def substitute(text: str, values: dict[str, str]) -> str:
    """Replace whole-word names in a formula by parenthesized formulas (H1 -> (m1**2 + ...))."""
    return rename(text, {k: f"({v})" for k, v in values.items()})


def named(kmap: KahanMap, text: str, values: Mapping[str, str | Frac] | None = None) -> Frac:
    """A formula in the map's ring, with H1..H4, I1..I3 (and `values`) as known functions, read exactly."""
    ring = kmap.ring
    known = {**_integrals(ring), **{k: (v if isinstance(v, Frac) else Frac.parse(ring, v))
                                    for k, v in (values or {}).items()}}
    return Frac.parse(ring, text, known)


@lru_cache(maxsize=None)
def _integrals(ring: Ring) -> dict[str, Frac]:
    """H1..H4 and I1..I3 as elements of Q(ring), parsed once."""
    return {k: Frac.parse(ring, v) for k, v in {**H, **I}.items()}
