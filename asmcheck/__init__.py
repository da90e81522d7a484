"""asmcheck: a model checker and state-space explorer for AsmetaL Abstract State Machines."""

__version__ = "0.1.0"
