"""asmcheck: a model checker and state-space explorer for AsmetaL Abstract State Machines.

The public API (docs/api.md)::

    import asmcheck
    model = asmcheck.load("specs/sb_async_master.asm")
    run = model.explore()
    run.verdict, run.states, run.verdicts, run.violations[0].trace.text()
"""

import sys as _sys

if _sys.argv[:1] == ["-m"] or _sys.argv[:1] and _sys.argv[0].rsplit("/", 1)[-1] == "asmcheck":
    # the command line is starting (python -m asmcheck, or the asmcheck script): a Ctrl-C before
    # its main function takes over ends the program with a message and exit code 3, not with a
    # traceback of the imports (asmcheck.cli.main puts Python's own handler back).  Only modules
    # already loaded are used here, so the window before the handler is as short as can be.
    import _signal
    import os as _os

    def _interrupted_while_loading(signum, frame):     # pragma: no cover - ends the process
        try:
            _os.write(2, b"asmcheck: interrupted before any result\n")
        finally:
            _os._exit(3)
    _interrupted_while_loading.asmcheck_startup = True
    try:
        # (started with Ctrl-C ignored, as `nohup` and a script's `&` start programs: it stays so)
        if _signal.getsignal(_signal.SIGINT) is not _signal.SIG_IGN:
            _signal.signal(_signal.SIGINT, _interrupted_while_loading)
    except (ValueError, OSError):                       # pragma: no cover - not the main thread
        pass

from .version import __version__  # noqa: E402
from .api import (AsmError, BmcResult, Exploration, Gate, Model, Simulation, Trace, UsageError,  # noqa: E402
                  Violation, check, find_specs, load, parse, scenario)

__all__ = ["__version__", "load", "parse", "check", "scenario", "find_specs", "Model", "Exploration", "Simulation",
           "BmcResult", "Gate", "Trace", "Violation", "AsmError", "UsageError"]
