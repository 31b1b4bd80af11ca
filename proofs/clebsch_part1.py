"""Certify section 6, part I: the discrete Clebsch map, Table "f2", Th. "dC basis 1", "dC basis 2", "dC Theta".

The kernel profiles of Th. "dClebsch max basis" / "dClebsch 1dim bases" and the dependence of g1, g2, g3 on J, d7, d8
are open claims: they promise exact evidence only, and are reported as such.
"""
import sys

from hkproof.orchestration.runner import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-map", "clebsch-bases", "clebsch-kernels", "clebsch-f2"]))
