"""Certify sections 6.1-6.2: the Clebsch integrals and the discrete Clebsch map (eqs. "dC", "dC map"): its
symmetries, reversibility and size."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-map"]))
