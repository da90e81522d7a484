"""The ``asmcheck`` command: the only package that prints results and chooses exit codes.

One module per command (parse, simulate, conform, explore, check, bmc, scenario); each has
``register(subparsers)`` and a ``run(args) -> int``, and calls the public API
(:mod:`asmcheck.api`) for the work.  :mod:`.common` holds the options and the output
helpers they share (colours, the progress bar, a stdout that may be closed early).

Exit codes (every subcommand):
  0  success (parsed / conforms / every property holds)
  1  a property is violated, a scenario check failed, a transcript does not conform
  2  usage error, unreadable file, syntax or type error in a spec
  3  incomplete: a limit (states, depth, time, memory) or Ctrl-C stopped the work first
"""
from __future__ import annotations

import argparse
import contextlib
import os
import signal
import sys
import threading

from ..version import __version__
from ..api import WATCHDOG_RETRY, unsafe_to_raise
from ..errors import AsmError, Terminated, UsageError
from .startup import python_interrupts, quiet_interrupts
from . import advise, bmc, check, common, conform, explore, lsp, parse, scenario, simulate, testgen
from .common import EXIT_ERROR, EXIT_INCOMPLETE

COMMANDS = (parse, simulate, conform, scenario, explore, bmc, check, advise, testgen, lsp)


class Parser(argparse.ArgumentParser):
    """argparse's parser whose usage errors are one line, with where to read the options
    (argparse printed the whole usage first, a dozen lines for explore)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}; see {self.prog} --help\n")

    def parse_args(self, args=None, namespace=None):
        # (arguments a command does not take are its error, not the program's)
        ns, extras = self.parse_known_args(args, namespace)
        if extras:
            command = getattr(ns, "command", None)
            prog = f"{self.prog} {command}" if command else self.prog
            self.exit(2, f"{prog}: error: unrecognized arguments: {' '.join(extras)}; see {prog} --help\n")
        return ns


def build_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="asmcheck",
        description="Model checker and state-space explorer for AsmetaL (.asm) Abstract State Machines.",
        epilog="Exit codes: 0 ok / all properties hold; 1 property violated (or scenario check failed, "
               "transcript does not conform); 2 usage, syntax or type error; 3 incomplete (a limit was hit).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--version", action="version", version=f"asmcheck {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")
    for cmd in COMMANDS:
        cmd.register(sub)
    imp_help = ("a folder searched for imports not found beside the importing file (repeatable; "
                "searched before the folders of the ASMCHECK_PATH environment variable)")
    p.add_argument("-I", "--import-path", action="append", default=[], metavar="DIR", help=imp_help)
    for sp in sub.choices.values():
        sp.add_argument("-I", "--import-path", action="append", default=argparse.SUPPRESS, metavar="DIR",
                        help=imp_help)
    return p


@contextlib.contextmanager
def _sigterm_as_interrupt():
    """SIGTERM (``timeout``, a CI runner's cancel) ends a command as Ctrl-C does: with the partial
    report and the report files, exit 3 (or 1 after a violation)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    on = [True]

    def again():
        if on[0]:
            os.kill(os.getpid(), signal.SIGTERM)

    def stop(signum, frame):
        if not on[0]:
            return
        if unsafe_to_raise(frame):
            # (a generator being closed, a __del__: Python would drop the exception) the signal
            # again in a moment, at a safe point
            t = threading.Timer(WATCHDOG_RETRY, again)
            t.daemon = True
            t.start()
            return
        raise Terminated()
    try:
        old = signal.signal(signal.SIGTERM, stop)
    except (ValueError, OSError):     # pragma: no cover - no signals here
        yield
        return
    try:
        yield
    finally:
        on[0] = False
        signal.signal(signal.SIGTERM, old)


def main(argv: list[str] | None = None) -> int:
    started = False
    try:
        try:
            # started as the program (asmcheck/cli/startup.py): Python's handler of Ctrl-C again
            started = python_interrupts()
            return _main(argv)
        finally:
            if started:
                # (the report is out: a Ctrl-C from here on ends the program quietly)
                quiet_interrupts(after=True)
    except KeyboardInterrupt:
        # before the command took over its interrupts (the arguments, the parser)
        common.error("asmcheck: interrupted before any result")
        return EXIT_INCOMPLETE


def _main(argv: list[str] | None = None) -> int:
    argv = common.join_range_arguments(list(sys.argv[1:] if argv is None else argv))
    parser = build_parser()
    with common.guarded_stdout():
        try:
            args = parser.parse_args(argv)
        except SystemExit as exc:
            return int(exc.code) if isinstance(exc.code, int) else EXIT_ERROR
        if not getattr(args, "command", None):
            parser.print_help()
            return EXIT_ERROR
        args.started = common.now()
        try:
            with _sigterm_as_interrupt():
                code = args.func(args)
        except UsageError as exc:
            common.error(f"asmcheck: error: {exc}")
            code = EXIT_ERROR
        except AsmError as exc:
            common.input_error(args, exc)
            code = EXIT_ERROR
        except KeyboardInterrupt:
            common.error("asmcheck: interrupted before any result")
            code = EXIT_INCOMPLETE
        except RecursionError as exc:
            from ..errors import located_recursion_error
            common.input_error(args, located_recursion_error(exc))
            code = EXIT_ERROR
        except MemoryError:
            common.error("asmcheck: out of memory before any result (bound the search with --max-states or "
                         "--max-memory)")
            code = EXIT_INCOMPLETE
        except common.TimeUp:
            common.error("asmcheck: the time limit was reached before any result")
            code = EXIT_INCOMPLETE
        except Exception as exc:  # an internal error: say so plainly (ASMCHECK_DEBUG=1 shows the traceback)
            if os.environ.get("ASMCHECK_DEBUG"):
                raise
            common.error(f"asmcheck: internal error ({type(exc).__name__}: {exc}); please report it with the "
                         f"input that caused it (set ASMCHECK_DEBUG=1 to see where it happened)")
            code = EXIT_ERROR
    return code


def entry() -> None:  # pragma: no cover - console script wrapper
    sys.exit(main())
