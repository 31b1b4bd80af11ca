"""Certify sections 6.4-6.6: Th. "dC basis 1" (J), Th. "dC basis 2" (d7, d8, d9) and Th. "dC Theta" (g_k)."""
import sys

from hkproof.commands.theorems import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-bases"]))
