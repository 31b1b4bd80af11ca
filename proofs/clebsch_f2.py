"""Certify Table "f2" of section 6.2: the monomial counts of f o f, plain and with the common factor cancelled
(slow)."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-f2"]))
