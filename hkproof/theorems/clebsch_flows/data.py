"""The general flow of the Clebsch system (eq. "gcl") and its reparametrization b_k = s + y w_k - z w_i w_j."""
from __future__ import annotations

from functools import lru_cache
from typing import Mapping, Sequence

import flint

from hkproof.algebra.fraction import Frac
from hkproof.algebra.ring import Ring, get_ring
from hkproof.dynamics.catalogue import CLEBSCH_VARS, get_system, kahan_map
from hkproof.dynamics.field import EPS, QuadraticField
from hkproof.errors import HKProofError
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.transport import Substitution

__all__ = ["B_OF_YZ", "C_OF_YZ", "CYCLIC", "e_names", "GENERAL", "field_under", "PHI0", "REDUCTION",
           "REDUCTION_Z0", "substitution", "yz_map", "yz_map_at_z0"]

GENERAL = "clebsch-general"
# b = s (1,1,1) + y w + z (-w2 w3, -w3 w1, -w1 w2): c_k = y + z w_k by eq. "c thru b"; s drops out (p x p = 0)
B_OF_YZ = {"b1": "s + y*w1 - z*w2*w3", "b2": "s + y*w2 - z*w3*w1", "b3": "s + y*w3 - z*w1*w2"}
C_OF_YZ = ("(y + z*w1)", "(y + z*w2)", "(y + z*w3)")
CYCLIC = ((0, 1, 2), (1, 2, 0), (2, 0, 1))


@lru_cache(maxsize=None)
def yz_map() -> KahanMap:
    """Kahan map of the general flow in the parameters (w, y, z): the catalogue field with b = B_OF_YZ at s = 0."""
    general = get_system(GENERAL)
    target = get_ring(CLEBSCH_VARS + (EPS, "w1", "w2", "w3", "y", "z"))
    rhs = tuple(str(f) for f in _under(general.ring, general.rhs, {**B_OF_YZ, "s": "0"}, target))
    return kahan_map(QuadraticField("clebsch-general-yz", CLEBSCH_VARS, ("w1", "w2", "w3", "y", "z"), rhs,
                                    "general Clebsch flow with b_k = y w_k - z w_i w_j (c_k = y + z w_k)"))


def _under(source: Ring, functions: Sequence[Frac], images: Mapping[str, str], target: Ring) -> list[Frac]:
    """The functions with parameters replaced by polynomials (text in `target`'s names and `s`), in lowest terms."""
    work = target.extend(["s"])
    polys = {}
    for n, text in images.items():
        img = Frac.parse(work, text)
        if not img.is_polynomial() or not img.den.is_one():
            raise HKProofError(f"{n} -> {text} is not a polynomial with integer coefficients")
        polys[n] = img.num
    zero_s = {n: p for n, p in polys.items() if n != "s"}
    images_of: dict[int, flint.fmpz_mpoly] = {}     # a polynomial that several functions share (their
    out = []                                          # denominator) is substituted once

    def image(p: flint.fmpz_mpoly) -> flint.fmpz_mpoly:
        if id(p) not in images_of:
            images_of[id(p)] = source.substitute(p, zero_s, work)
        return images_of[id(p)]

    for f in functions:
        g = Frac(work, image(f.num), image(f.den))
        out.append(g.specialize({"s": 0}, target) if "s" in polys else g.to_ring(target))
    return out


def field_under(kmap: KahanMap, images: Mapping[str, str], target: Ring) -> list[Frac]:
    """The right-hand sides of `kmap`'s vector field with parameters replaced by polynomials, in lowest terms. Equal
    to a target map's field, they make the Kahan equations equal (polarization commutes with the substitution), so
    the explicit maps N / Delta too wherever the target's Delta is non-zero (Cramer's rule commutes with it)."""
    return _under(kmap.field.ring, list(kmap.field.rhs), images, target)


def e_names() -> tuple[str, ...]:
    """Kernel coordinates of Phi0 = (p1^2, p2^2, p3^2, m1^2, m2^2, m3^2, 1), normalized by e7 = -1."""
    return tuple(f"e{k}" for k in range(1, 7))


PHI0 = ("p1**2", "p2**2", "p3**2", "m1**2", "m2**2", "m3**2")


# The flow reduction (claim flow-reduction): F_(y,z)(x; w) = z F_2(x; w + y/z), and Kahan's map of lambda F with step
# eps is the map of F with step lambda eps; at z = 0, F_(y,0) = y F_1.
REDUCTION = {"w1": "w1 + y/z", "w2": "w2 + y/z", "w3": "w3 + y/z", "eps": "z*eps"}
REDUCTION_Z0 = {"eps": "y*eps"}


@lru_cache(maxsize=None)
def yz_map_at_z0() -> KahanMap:
    """The (y, z) family on the hyperplane z = 0 (c_k = y, b_k = y w_k)."""
    return kahan_map(yz_map().field.specialize({"z": 0}))


def substitution(source: KahanMap, target: KahanMap, images: Mapping[str, str]) -> Substitution:
    """sigma: Q(source's ring) -> Q(target's ring), name -> image (claimed text, read by Frac.parse)."""
    return Substitution(source.ring, target.ring, {n: Frac.parse(target.ring, t) for n, t in images.items()})
