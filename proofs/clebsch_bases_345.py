"""Certify section 6.7: Th. "dC bases 345" (rel18, eq. "M2" with A, B, C, D, Steps 1-5) and Th. "dClebsch max basis"."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-bases-345"]))
