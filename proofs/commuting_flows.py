"""Certify the remark of section 7: the Kahan maps of the two Clebsch flows do not commute, and what they share."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["commuting-flows"]))
