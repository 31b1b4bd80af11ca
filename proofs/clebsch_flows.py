"""Certify the end of section 6: the general Clebsch flow, the second-flow theorem and the Phi0 claim for all flows.

The conjecture for the general flow is printed afterwards as exact evidence (it is not a theorem, so it is not in the
registry and does not change the exit status).
"""
import sys

from hkproof.proof.runner import run_script
from hkproof.theorems.s6c_clebsch_flows import conjecture_evidence

if __name__ == "__main__":
    code = run_script(groups=["clebsch-flows"])
    if "--json" not in sys.argv:
        print(conjecture_evidence().render())
    sys.exit(code)
