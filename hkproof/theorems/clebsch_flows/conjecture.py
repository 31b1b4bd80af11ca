"""Section 6, the conjecture after eq. "dC2 map", for every flow: the second flow's null-vectors of Phi0..Phi3
(z != 0) and the first flow's (z = 0), carried to the (y, z) family by the substitutions of flow-reduction, each
transported statement checked on the new map."""
from __future__ import annotations

from typing import Mapping, Sequence

from hkproof.algebra.fraction import Frac
from hkproof.dynamics.catalogue import kahan_map
from hkproof.dynamics.field import EPS
from hkproof.dynamics.kahan import KahanMap
from hkproof.hk.balance import orbit_matrix
from hkproof.hk.reduced import linear_combination_equals
from hkproof.hk.transport import Substitution, require_transport
from hkproof.orchestration.registry import claim, require_proven
from hkproof.proof.certificate import Certificate
from hkproof.theorems._clebsch import recall
from hkproof.theorems.clebsch_bases_345.data import UNKNOWNS
from hkproof.theorems.clebsch_bases_345.steps import kernel_vectors
from hkproof.theorems.clebsch_flows.second_flow_bases import embedded_vectors, max_basis_facts
from hkproof.theorems.clebsch_flows.general import FIRST, FLOW2, GROUP, PHI_MAX_TEXT, RANK_POINT, reduction_substitutions
from hkproof.theorems.clebsch_flows.data import yz_map, yz_map_at_z0

__all__ = ["prove_conjecture", "STATEMENT"]

STATEMENT = ("For every flow of the Clebsch system (b_k = s + y w_k - z w_i w_j, i.e. b and w arbitrary; w, y, z, eps "
             "symbolic): Phi0 = (p^2, m^2, 1) and Phi_k = (p^2, m^2, m_k p_k) are HK-bases with one-dimensional "
             "null-spaces, whose vectors, placed in R^10, span K_Phi for the ten monomials (dim K_Phi = `dim`); their "
             "components are even in eps and integrals, four of them functionally independent. z != 0: the second "
             "flow's vectors (flow-second-theorem, flow-second-bases-345) carried by sigma; z = 0: the first flow's "
             "(Th. \"dC bases 345\") by sigma0. Excluded: w_i = w_j, y = z = 0 (the zero field), and the proper "
             "algebraic subsets where a denominator or a maximal minor vanishes.")


@claim("flow-conjecture", GROUP, "The conjecture for every Clebsch flow: dim K_Phi = 4, the sum of the four "
       "one-dimensional null-spaces of Phi0..Phi3; four independent integrals",
       "sec. 6, conjecture after eq. \"dC2 map\" (with Th. \"dClebsch max basis\", \"dClebsch 1dim bases\")",
       STATEMENT, claimed={"dim": "4"}, slow=True,
       uses=["flow-reduction", "flow-second-theorem", "flow-second-bases-345", "dc-basis1-relations", "dc345-alpha",
             "dc345-step5"])
def prove_conjecture(cert: Certificate, claimed: Mapping[str, str]) -> None:
    with cert.step("the claimed dim K_Phi against rank X_[0,5] at a rational point of both target maps (a fast "
                   "refutation; the full check follows)", "exact rank (fmpq_mat)", yz_map().ring) as s:
        for target in (yz_map(), yz_map_at_z0()):
            point = {k: v for k, v in RANK_POINT.items() if k in target.ring.names}
            monomials = [Frac.parse(target.ring, m) for m in PHI_MAX_TEXT.split(", ")]
            found = 10 - orbit_matrix(target, monomials, point, 6).rank()
            s.require(str(found) == claimed["dim"].strip(), f"dim ker X_[0,5] = {found}, claimed {claimed['dim']}")
    sigma, sigma0 = reduction_substitutions(require_proven(cert, "flow-reduction").formulas)
    flow2, first = kahan_map(FLOW2), kahan_map(FIRST)
    theorem, bases2 = require_proven(cert, "flow-second-theorem"), require_proven(cert, "flow-second-bases-345")
    e = [Frac.parse(flow2.ring, theorem.formulas[f"e{k}"]) for k in range(1, 7)]
    blocks = [[recall(bases2, u, flow2.ring) for u in UNKNOWNS[6 * b:6 * b + 6]] for b in range(3)]
    second = embedded_vectors(e, blocks)
    big_l = Frac.parse(flow2.ring, theorem.formulas["L"])
    _carried(cert, "z != 0: ", sigma, yz_map(), second, [big_l, blocks[0][0], blocks[1][0], blocks[2][0]],
             "L, a1, b1, c1", claimed)
    first_vectors = list(kernel_vectors(cert, first.ring).values())
    _carried(cert, "z = 0: ", sigma0, yz_map_at_z0(), first_vectors,
             [first_vectors[0][0], *(first_vectors[k][0] for k in (1, 2, 3))], "c1 (a function of J), a1, b1, c1",
             claimed)


def _carried(cert: Certificate, case: str, sigma: Substitution, target: KahanMap,
             vectors: Sequence[Sequence[Frac]], integrals: Sequence[Frac], names: str,
             claimed: Mapping[str, str]) -> None:
    """What the conjecture says of the vectors and integrals carried by sigma onto `target`, read on the source:
    sigma is an injective homomorphism fixing x (flow-reduction) and commuting with eps -> -eps, so parity and every
    identity carry over, and the ranks are taken at the pulled-back point. The images are never formed."""
    source = sigma.source
    monomials = [Frac.parse(source, m) for m in PHI_MAX_TEXT.split(", ")]
    with cert.step(f"{case}the null-vectors carried by {sigma}: components even in eps, rows i = 0",
                   "transport: sigma fixes x and commutes with eps -> -eps (the image of eps odd in eps, the other "
                   "images even), so the images of even components are even and the images of identities are "
                   "identities; exact parity and row i = 0 (substitution) on the source vectors", source) as s:
        require_transport(s, sigma, target)
        s.require(all(h.ring == source for vec in vectors for h in (*vec, *integrals)),
                  "a vector or an integral is not a function on sigma's source")
        for k, vec in enumerate(vectors):
            s.require(all(h.is_even_in(EPS) for h in vec), f"a component of the Phi{k} vector is not even in eps")
            s.require(linear_combination_equals(vec, monomials, Frac(source, 0)), f"the Phi{k} vector misses row i = 0")
        s.note(f"sizes on the source up to {max(len(h.num) for vec in vectors for h in vec)} terms over "
               f"{max(len(h.den) for vec in vectors for h in vec)}; sigma maps the source map to this one "
               "(flow-reduction) and is an injective homomorphism of fields fixing x, so the source's identities "
               "h o f = h carry over: the images are integrals and annihilate every row")
    max_basis_facts(cert, target, vectors, integrals, names, case, claimed["dim"], sigma)
