"""The paper's theorems, one module per section; importing a module registers its claims."""
