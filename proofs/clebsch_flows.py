"""Certify the end of section 6: the general Clebsch flow, the second-flow theorem and the Phi0 claim for all flows."""
import sys

from hkproof.proof.runner import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-flows"]))
