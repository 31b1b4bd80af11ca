"""Certify the end of section 6: the general Clebsch flow, the second-flow theorem, the Phi0 claim for all flows.

The group also holds two open claims: the conjecture for the general flow (exact evidence) and Theta for every
flow with w fixed (verified(specialized), slow); they succeed when they reach that promised status.
"""
import sys

from hkproof.orchestration.runner import run_script

if __name__ == "__main__":
    sys.exit(run_script(groups=["clebsch-flows"]))
