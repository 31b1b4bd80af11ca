"""Certify the end of section 6: the general Clebsch flow, the second-flow theorem and the Phi0 claim for all flows.

Afterwards (not in the registry, so they do not change the exit status): the conjecture for the general flow as
exact evidence, and Theta = (p^2, m^2, H4) for every flow with w fixed (verified(specialized); skipped by --no-slow).
"""
import sys

from hkproof.proof.runner import run_script
from hkproof.theorems.s6c_clebsch_flows import conjecture_evidence, theta_all_flows

if __name__ == "__main__":
    code = run_script(groups=["clebsch-flows"])
    if "--json" not in sys.argv:
        print(conjecture_evidence().render())
        if "--no-slow" not in sys.argv:
            print(theta_all_flows().render())
    sys.exit(code)
