"""Minimal HK-bases at each degree that adds new kernel dimensions, their candidate ratios, and their confirmation
by algorithm (N) (two primes and once over Q)."""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field


from hkproof import budget
from hkproof.algebra.sampling import random_rational
from hkproof.algebra.fraction import Frac
from hkproof.algebra.modular import rank_mod_p
from hkproof.algebra.monomials import Exponents, exponents_upto, text
from hkproof.errors import BudgetExhausted, ResourceLimitError
from hkproof.experiments.arithmetics import ExactQ
from hkproof.experiments.profiles_mod_p import Modular
from hkproof.experiments.profiles import HK_BASIS, ProfileProblem
from hkproof.experiments.scene import Scene
from hkproof.pipelines.discover.candidates import Candidate, normalizations, ratio_candidates
from hkproof.pipelines.discover.circuits import MAX_CIRCUIT_TRIALS, circuits, support_vector
from hkproof.pipelines.discover.context import SearchContext
from hkproof.pipelines.discover.screen import Probe, complement_of_trivial, trivial_products
from hkproof.proof.status import Status

__all__ = ["FULL_CIRCUITS", "MinimalBases", "confirm_basis", "minimal_bases"]

FULL_CIRCUITS = 5000        # above this many trials, circuits are sought in a complement of the trivial part


@dataclass
class MinimalBases:
    """The minimal HK-bases found (as report entries), the trivial parts split off, coverage notes, and the
    candidate ratios of their kernel coordinates, simplest first."""

    bases: list[dict] = field(default_factory=list)
    trivial: list[dict] = field(default_factory=list)
    covered: list[str] = field(default_factory=list)
    candidates: list[Candidate] = field(default_factory=list)


def minimal_bases(ctx: SearchContext, probe: Probe, degrees: list[int]) -> MinimalBases:
    """Circuits of the new part of the kernel at each degree in `degrees`, with their candidate ratios."""
    n = len(ctx.kmap.variables)
    variables = ctx.kmap.variables
    out = MinimalBases()
    for d in degrees:
        monos = exponents_upto(n, d)
        lower = trivial_products(probe.kernels.get(d - 1, []), exponents_upto(n, d - 1) if d > 1 else [], monos, n)
        kernel = probe.kernels[d]
        width = sum(1 for j in range(len(monos)) if any(v[j] for v in kernel))
        triv_rank = rank_mod_p(lower, probe.p)
        if triv_rank and math.comb(width, len(kernel) - 1) > FULL_CIRCUITS:
            new_part, eliminated = complement_of_trivial(kernel, lower, monos, probe.p)
        else:
            new_part, eliminated = kernel, []
        supports, complete = circuits(new_part, probe.p)
        if triv_rank and not eliminated:          # circuits of the whole kernel: drop the trivial ones
            supports = [sp for sp in supports
                        if rank_mod_p(lower + [support_vector(kernel, sp, probe.p)], probe.p) > triv_rank]
        if eliminated:
            out.trivial.append({"degree": d, "dimension": len(probe.kernels[d]) - len(new_part),
                                "eliminated": [text(variables, monos[j]) for j in eliminated],
                                "reason": "products of lower-degree kernel elements with monomials; bases avoid "
                                          "the listed monomials"})
        if not complete:
            out.covered.append(f"degree {d}: circuit enumeration stopped after {MAX_CIRCUIT_TRIALS} trials")
        for s in supports:
            budget.check("choosing the normalizations of the minimal HK-bases")
            basis: list[Exponents] = [monos[j] for j in s]
            for j, sizes in normalizations(ctx.kmap, basis, ctx.weights, ctx.free, ctx.rng, len(ctx.free) + n):
                for cand in ratio_candidates(probe.orbit, basis, j):
                    cand.estimate = sizes[cand.k]
                    out.candidates.append(cand)
            out.bases.append({"basis": [text(variables, e) for e in basis], "degree": d})
    out.candidates.sort(key=lambda c: c.estimate)      # the simplest integrals first (stable: small bases first)
    return out


def confirm_basis(scene: Scene, basis: list[Frac]) -> dict:
    """Algorithm (N) on a minimal basis: mod two primes at two points, and exactly over Q at a third; when the heights
    of the exact orbit grow exponentially (a non-integrable map), mod p at the third point too.

    Along an orbit that reduces well mod p (no denominator of the map or of the basis vanishes mod p, which the
    modular map checks), each X_[0,s-1] mod p is the reduction of the rational matrix, so its rank mod p is at most
    the rank over Q: the kernel dimension d mod p bounds the one over Q from above. That the two are equal (so that
    the basis is an HK-basis over Q) fails only at primes dividing the non-zero minors: evidence, the same at two
    random primes per point and at three points."""
    problem = ProfileProblem(scene, basis)
    rng = random.Random(len(basis))
    pts = [[random_rational(rng, 60) for _ in scene.variables] for _ in range(3)]
    modular = [problem.profile(pt, Modular(seed=i), with_kernel=False) for i, pt in enumerate(pts[:2])]
    try:
        third, limit = problem.profile(pts[2], ExactQ(), with_kernel=False), ""
    except BudgetExhausted:
        raise
    except ResourceLimitError as exc:     # heights that explode: a third point mod p instead
        third, limit = problem.profile(pts[2], Modular(seed=2), with_kernel=False), str(exc)
    profiles = modular + [third]
    dims = {pr.dimension for pr in profiles if pr.verdict == HK_BASIS}
    ok = len(dims) == 1 and third.verdict == HK_BASIS
    check = "algorithm (N): 2 points mod p, 1 point over Q"
    if limit:
        check = (f"algorithm (N) mod p only: an HK-basis at {sum(pr.verdict == HK_BASIS for pr in profiles)} of 3 "
                 "points, 2 agreeing random primes each; the dimension mod p bounds the one over Q from above (ranks "
                 "mod p <= ranks over Q on an orbit that reduces well), equality (an HK-basis over Q) is evidence; "
                 f"not over Q: {limit}")
    return {"dimension": dims.pop() if ok else None,
            "status": Status.EVIDENCE_EXACT.label if ok else Status.UNKNOWN.label,
            "check": check}
