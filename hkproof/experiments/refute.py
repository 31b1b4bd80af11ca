"""A cheap exact refutation of h o f = h: one evaluation mod a large prime at a random point (before any symbolic work).

If h o f - h were the zero rational function, its numerator would vanish mod p at every point where det M(x, eps),
the denominators of h at x and at f(x) are units mod p. So a non-zero value there is a proof that h is not an
integral, with the point and the prime as the witness; a zero value proves nothing (the symbolic check decides).
"""
from __future__ import annotations

import random
from dataclasses import dataclass

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.kahan import KahanMap
from hkproof.errors import SingularPointError
from hkproof.experiments.profiles_mod_p import ModP, random_prime
from hkproof.algebra.sampling import random_rationals
from hkproof.experiments.points import random_values
from hkproof.experiments.scene import make_scene, point_values

__all__ = ["modular_witness", "Witness"]


@dataclass(frozen=True)
class Witness:
    """A point, eps and parameter values, and a prime p with h(f(x)) != h(x) mod p."""

    point: dict[str, str]
    values: dict[str, str]
    prime: int
    h_at_x: int
    h_at_fx: int

    def text(self) -> str:
        at = ", ".join(f"{k} = {v}" for k, v in {**self.point, **self.values}.items())
        return (f"h(f(x)) = {self.h_at_fx} but h(x) = {self.h_at_x} mod p = {self.prime} at {at} "
                "(an exact refutation: h o f - h is not the zero function)")

    def to_dict(self) -> dict:
        return {"point": self.point, "values": self.values, "prime": self.prime, "h_at_x_mod_p": self.h_at_x,
                "h_at_fx_mod_p": self.h_at_fx}


def modular_witness(kmap: KahanMap, h: Frac, seed: int = 0, tries: int = 4) -> Witness | None:
    """A point where h(f(x)) != h(x) mod a random 62-bit prime, or None if `tries` random points show no difference."""
    rng = random.Random(seed)
    for _ in range(tries):
        values = random_values(kmap, rng)
        scene = make_scene(kmap, values)
        arithmetic = ModP(random_prime(rng))
        prep = arithmetic.prepare(scene, [scene.compile(h)])
        point = random_rationals(rng, len(kmap.variables))
        try:
            x = [arithmetic.number(v) for v in point_values(scene, point)]
            (at_x,), (at_fx,) = arithmetic.basis_row(prep, x), arithmetic.basis_row(prep, arithmetic.step(prep, x))
        except SingularPointError:  # det M(x) or a denominator of h vanishes mod p here: another point
            continue
        if at_x != at_fx:
            return Witness(dict(zip(kmap.variables, map(str, point), strict=True)),
                           {k: str(v) for k, v in values.items()}, arithmetic.p, at_x, at_fx)
    return None
