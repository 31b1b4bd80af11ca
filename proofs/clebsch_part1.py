"""Certify section 6, part I: the discrete Clebsch map, Table "f2", Th. "dC basis 1", "dC basis 2", "dC Theta".

Afterwards (not in the registry, so they do not change the exit status): the kernel profiles of Th. "dClebsch max
basis" and "dClebsch 1dim bases", and (unless --no-slow) the functional dependence of g1, g2, g3 on J, d7, d8, as
exact evidence.
"""
import sys

from hkproof.proof.runner import run_script
from hkproof.theorems.s6a_clebsch_bases import theta_dependence_evidence
from hkproof.theorems.s6a_clebsch_kernels import kernel_evidence

if __name__ == "__main__":
    code = run_script(groups=["clebsch-map", "clebsch-bases", "clebsch-kernels", "clebsch-f2"])
    if "--json" not in sys.argv:
        print(kernel_evidence().render())
        if "--no-slow" not in sys.argv:  # it needs the (slow) Theta solution
            print(theta_dependence_evidence().render())
    sys.exit(code)
