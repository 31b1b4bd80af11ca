"""Certify section 5 of the paper: the Hirota-Kimura Euler top, its HK-bases and integrals."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["euler-top"]))
