"""The ``asmcheck`` command: the only module that prints results and chooses exit codes.

Exit codes (every subcommand):
  0  success (parsed / conforms / every property holds)
  1  a property is violated, a scenario check failed, a transcript does not conform
  2  usage error, unreadable file, syntax or type error in a spec
  3  incomplete: a limit (states, depth, time) stopped the exploration first
"""
from __future__ import annotations

import argparse
import json
import os
import sys

from . import __version__
from .errors import AsmError, UsageError

EXIT_OK, EXIT_VIOLATED, EXIT_ERROR, EXIT_INCOMPLETE = 0, 1, 2, 3


def _error_json(err: AsmError) -> dict:
    sp = err.span
    return {
        "path": sp.path if sp else None,
        "line": sp.line if sp and sp.line else None,
        "column": sp.col if sp and sp.line else None,
        "message": err.message,
    }


def cmd_parse(args) -> int:
    from .semantics.resolve import check_file

    results = []
    for path in args.files:
        try:
            check_file(path)
            results.append((path, None))
        except AsmError as err:
            results.append((path, err))
    if args.format == "json":
        out = {"files": [{"path": p, "ok": e is None, "error": None if e is None else _error_json(e)}
                         for p, e in results]}
        print(json.dumps(out, indent=2))
    else:
        for p, e in results:
            if e is None:
                print(f"{p}: OK")
            else:
                print(e.render())
    return EXIT_OK if all(e is None for _, e in results) else EXIT_ERROR


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="asmcheck",
        description="Model checker and state-space explorer for AsmetaL (.asm) Abstract State Machines.",
        epilog="Exit codes: 0 ok / all properties hold; 1 property violated (or scenario check failed, "
               "transcript does not conform); 2 usage, syntax or type error; 3 incomplete (a limit was hit).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--version", action="version", version=f"asmcheck {__version__}")
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    sp = sub.add_parser("parse", help="parse and type-check AsmetaL files",
                        description="Parse and type-check each FILE (with its imports); print OK or the error.")
    sp.add_argument("files", nargs="+", metavar="FILE")
    sp.add_argument("--format", choices=["text", "json"], default="text")
    sp.set_defaults(func=cmd_parse)

    from . import commands  # the other subcommands live beside this module
    commands.register(sub)
    imp_help = ("a folder searched for imports not found beside the importing file (repeatable; "
                "searched before the folders of the ASMCHECK_PATH environment variable)")
    p.add_argument("-I", "--import-path", action="append", default=[], metavar="DIR", help=imp_help)
    for sp in sub.choices.values():
        sp.add_argument("-I", "--import-path", action="append", default=argparse.SUPPRESS, metavar="DIR",
                        help=imp_help)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code) if isinstance(exc.code, int) else EXIT_ERROR
    if not getattr(args, "command", None):
        parser.print_help()
        return EXIT_ERROR
    from .semantics.resolve import set_import_path
    for d in args.import_path:
        if not os.path.isdir(d):
            print(f"asmcheck: error: --import-path {d}: no such folder", file=sys.stderr)
            return EXIT_ERROR
    set_import_path(os.path.abspath(d) for d in args.import_path)
    try:
        code = args.func(args)
    except UsageError as exc:
        print(f"asmcheck: error: {exc}", file=sys.stderr)
        code = EXIT_ERROR
    except AsmError as exc:
        print(exc.render(), file=sys.stderr if getattr(args, "format", "text") == "json" else sys.stdout)
        code = EXIT_ERROR
    except KeyboardInterrupt:
        print("asmcheck: interrupted", file=sys.stderr)
        code = 130
    except BrokenPipeError:
        code = EXIT_OK
    except RecursionError:
        print("asmcheck: error: the spec nests too deeply (recursion limit reached)", file=sys.stderr)
        code = EXIT_ERROR
    except MemoryError:
        print("asmcheck: error: out of memory (bound the search with --max-states)", file=sys.stderr)
        code = EXIT_ERROR
    except Exception as exc:  # an internal error: say so plainly (ASMCHECK_DEBUG=1 shows the traceback)
        if os.environ.get("ASMCHECK_DEBUG"):
            raise
        print(f"asmcheck: internal error ({type(exc).__name__}: {exc}); please report it with the input "
              f"that caused it (set ASMCHECK_DEBUG=1 to see where it happened)", file=sys.stderr)
        code = EXIT_ERROR
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    return code


def entry() -> None:  # pragma: no cover - console script wrapper
    sys.exit(main())


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
