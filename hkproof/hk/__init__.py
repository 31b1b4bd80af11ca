"""The paper's method: integrals, reduced HK systems and Prop. "prop: even", functional independence."""
