"""asmcheck: a model checker and state-space explorer for AsmetaL Abstract State Machines.

The public API (docs/api.md)::

    import asmcheck
    model = asmcheck.load("specs/sb_async_master.asm")
    run = model.explore()
    run.verdict, run.states, run.verdicts, run.violations[0].trace.text()
"""

from .version import __version__  # noqa: E402
from .api import (AsmError, BmcResult, Exploration, Gate, Model, Simulation, Trace, UsageError,  # noqa: E402
                  Violation, check, find_specs, load, parse, scenario)

__all__ = ["__version__", "load", "parse", "check", "scenario", "find_specs", "Model", "Exploration", "Simulation",
           "BmcResult", "Gate", "Trace", "Violation", "AsmError", "UsageError"]
