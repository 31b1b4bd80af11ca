"""Certify the end of section 6: the general Clebsch flow, the second-flow theorem, the Phi0 and Theta claims for
all flows, the second flow's bases Phi1, Phi2, Phi3, and the paper's closing conjecture for every flow."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-flows"]))
