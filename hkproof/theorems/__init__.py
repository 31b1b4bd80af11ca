"""The paper's theorems, one module (or package) per theorem group: its name is the group id (with '_' for '-'),
its script is proofs/<name>.py and its tests are tests/test_<name>.py. Modules whose names start with '_' hold data
and readers shared by several groups. GROUPS lists the groups in the paper's order (the order of `hkproof list`)."""

GROUPS = ("lotka_volterra", "euler_top", "clebsch_map", "clebsch_f2", "clebsch_bases", "clebsch_kernels",
          "clebsch_bases_345", "clebsch_flows", "commuting_flows", "atlas")

__all__ = ["GROUPS"]
