"""The command line's start-up: a Ctrl-C (SIGINT) at any moment before the command's own handling
of interrupts begins, or after its report, ends the program with one line and exit code 3 (what an
interrupted run gives), never with a traceback.  asmcheck/__init__.py sets the first such handler
(started as the program) before it imports anything; :func:`asmcheck.cli.main` puts Python's own
handler back while the command runs, and this one again after it."""
from __future__ import annotations

import os
import _signal

EXIT_INCOMPLETE = 3


def _interrupted(signum, frame):      # pragma: no cover - runs in a process being interrupted
    try:
        os.write(2, b"asmcheck: interrupted before any result\n" if not _after[0] else b"asmcheck: interrupted\n")
    finally:
        os._exit(EXIT_INCOMPLETE)


_interrupted.asmcheck_startup = True
_after = [False]


def quiet_interrupts(after: bool = False) -> None:
    """SIGINT ends the program at once, with the message (``after``: the command's report is out)."""
    _after[0] = after
    try:
        _signal.signal(_signal.SIGINT, _interrupted)
    except (ValueError, OSError):  # pragma: no cover - not the main thread
        pass


def python_interrupts() -> bool:
    """SIGINT raises KeyboardInterrupt again, as Python's own handler does (a search stopped by
    Ctrl-C reports what it covered), where the start-up had set its handler: whether it had."""
    try:
        if getattr(_signal.getsignal(_signal.SIGINT), "asmcheck_startup", False):
            _signal.signal(_signal.SIGINT, _signal.default_int_handler)
            return True
    except (ValueError, OSError):  # pragma: no cover - not the main thread
        pass
    return False
