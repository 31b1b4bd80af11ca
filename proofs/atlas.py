"""Certify the atlas beyond the paper: integrals of Kahan maps found by `hkproof discover` (docs/atlas.md)."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["atlas"]))
