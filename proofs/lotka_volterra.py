"""Certify section 2 of the paper: Kahan's Lotka-Volterra map and its Poisson property."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["lotka-volterra"]))
