"""Certify section 6.3: Th. "dClebsch max basis" (the proven bounds) and the kernel profiles at points (evidence)."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-kernels"]))
