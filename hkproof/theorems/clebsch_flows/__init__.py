"""Group `clebsch-flows` (paper, sec. 6, the general flow eq. "gcl" and the closing conjecture): the general flow's
map and its reduction to the first and second flows (general), the second flow's bases Phi1, Phi2, Phi3 with w
symbolic (second_flow_bases), the conjecture for every flow (conjecture); the (w, y, z) family is in data.
Script: proofs/clebsch_flows.py. The submodules are imported in the order their claims are listed."""
from hkproof.theorems.clebsch_flows import general  # noqa: I001  (registration order: general first)
from hkproof.theorems.clebsch_flows import second_flow_bases
from hkproof.theorems.clebsch_flows import conjecture

__all__ = ["conjecture", "general", "second_flow_bases"]
