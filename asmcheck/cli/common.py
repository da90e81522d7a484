"""What the commands share: options, colours, the progress bar, a stdout that may close early."""
from __future__ import annotations

import json
import os
import re
import sys
import time
from contextlib import contextmanager
from pathlib import Path

from ..api import TimeUp, UsageError, default_max_memory, max_states_error, parse_int_range, parse_range  # noqa: F401

EXIT_OK, EXIT_VIOLATED, EXIT_ERROR, EXIT_INCOMPLETE = 0, 1, 2, 3

now = time.perf_counter


# ----------------------------------------------------------------- stdout
class _GuardedStream:
    """stdout that survives its reader going away (``asmcheck explore spec | head -3``): the
    rest of the output is dropped and the command still ends with its verdict's exit code."""

    def __init__(self, stream):
        self._s = stream
        self.closed_early = False

    def _drop(self):
        self.closed_early = True
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, self._s.fileno())
            os.close(devnull)
        except (OSError, ValueError, AttributeError):
            pass

    def write(self, text):
        if self.closed_early:
            return len(text)
        try:
            return self._s.write(text)
        except BrokenPipeError:
            self._drop()
            return len(text)

    def flush(self):
        if self.closed_early:
            return
        try:
            self._s.flush()
        except BrokenPipeError:
            self._drop()

    def __getattr__(self, name):
        return getattr(self._s, name)


@contextmanager
def guarded_stdout():
    old = sys.stdout
    guard = _GuardedStream(old)
    sys.stdout = guard
    try:
        yield guard
    finally:
        guard.flush()
        sys.stdout = old


def out(text: str = "") -> None:
    print(text)


def error(text: str) -> None:
    try:
        print(text, file=sys.stderr)
    except (BrokenPipeError, OSError):
        pass


def color_on(stream=None) -> bool:
    stream = stream or sys.stdout
    try:
        return stream.isatty() and not os.environ.get("NO_COLOR")
    except (AttributeError, ValueError):
        return False


def error_json(err) -> dict:
    """An input error as the JSON outputs carry it."""
    sp = getattr(err, "span", None)
    located = sp is not None and bool(sp.line)
    return {"file": sp.path if located else None, "line": sp.line if located else None,
            "col": sp.col if located else None, "message": getattr(err, "message", str(err))}


def input_error(args, err) -> None:
    """A located error in a spec: rendered on stderr; with ``--format json`` also as
    ``{"error": {...}}`` on stdout, so a tool reading stdout always gets JSON."""
    error(err.render())
    if getattr(args, "format", "text") == "json":
        out(json.dumps({"error": error_json(err)}, indent=2))


# ----------------------------------------------------------------- arguments
RANGE_OPTIONS = ("--int-range", "--monitored")


def join_range_arguments(argv: list[str]) -> list[str]:
    """``--int-range -3..3`` as ``--int-range=-3..3``: argparse would take a value that starts
    with '-' for an option."""
    out = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in RANGE_OPTIONS and i + 1 < len(argv) and re.match(r"-[0-9]", argv[i + 1]):
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def parse_size(text: str) -> int:
    """``2G``, ``512M``, ``100000K`` or a number of bytes; 0 means no limit."""
    m = re.fullmatch(r"\s*([0-9]+(?:\.[0-9]+)?)\s*([KkMmGgTt]?)(?:i?[Bb])?\s*", text)
    if not m:
        raise UsageError(f"--max-memory {text!r}: expected a size such as 2G, 512M or a number of bytes")
    n = float(m.group(1)) * {"": 1, "k": 2**10, "m": 2**20, "g": 2**30, "t": 2**40}[m.group(2).lower()]
    return int(n)


#: the files asmcheck reads, which a report never overwrites (a spec given as the report's name
#: by mistake was replaced by the report)
INPUT_SUFFIXES = {".asm": "a spec", ".prop": "a property file"}


def check_output_path(path: str, what: str, folder_ok: bool = False) -> None:
    """An output path must be writable before the work starts: not a folder (unless
    ``folder_ok``), not a special file, not read-only.  A missing parent folder is created
    now, and asmcheck says so on stderr."""
    if path == "-":
        raise UsageError(f"{what} -: only --json and --format print a report on standard output; give a file "
                         f"name")
    target = os.path.abspath(path)
    real = os.path.realpath(target)
    if real.startswith(("/proc/", "/sys/", "/dev/")) or real in ("/proc", "/sys", "/dev"):
        raise UsageError(f"{what} {path}: is a file of the system, not one asmcheck writes reports to")
    if os.path.isfile(real) and Path(real).suffix.lower() in INPUT_SUFFIXES:
        raise UsageError(f"{what} {path}: is {INPUT_SUFFIXES[Path(real).suffix.lower()]}; asmcheck does not write "
                         f"a report over it (give another file name)")
    if os.path.isdir(target):
        if not folder_ok:
            raise UsageError(f"{what} {path}: is a folder; give a file name")
        if not os.access(target, os.W_OK | os.X_OK):
            raise UsageError(f"{what} {path}: cannot write into the folder (permission denied)")
        return
    if os.path.lexists(target):
        import stat
        mode = os.stat(target).st_mode if os.path.exists(target) else 0
        if not stat.S_ISREG(mode):
            raise UsageError(f"{what} {path}: is not a regular file")
        if not os.access(target, os.W_OK):
            raise UsageError(f"{what} {path}: the file cannot be written (permission denied)")
        return
    parent = os.path.dirname(target)
    if not os.path.isdir(parent):
        up = parent
        while not os.path.exists(up):
            up = os.path.dirname(up)
        if not os.path.isdir(up):
            raise UsageError(f"{what} {path}: {up} is not a folder")
        if not os.access(up, os.W_OK | os.X_OK):
            raise UsageError(f"{what} {path}: the folder {parent} does not exist and cannot be created in {up} "
                             f"(permission denied)")
        os.makedirs(parent, exist_ok=True)
        error(f"asmcheck: created the folder {parent} for {what}")
    elif not os.access(parent, os.W_OK | os.X_OK):
        raise UsageError(f"{what} {path}: cannot write into {parent} (permission denied)")


def check_output_folder(path: str, what: str) -> None:
    """An output folder (the command makes it, or writes into it) must be one before the work
    starts: not an existing file, and within a folder that can be written (see
    :func:`check_output_path`)."""
    if path == "-":
        raise UsageError(f"{what} -: only --json and --format print a report on standard output; give a folder "
                         f"name")
    if os.path.lexists(path) and not os.path.isdir(path):
        raise UsageError(f"{what} {path}: is a file, not a folder; give a folder name")
    check_output_path(path, what, folder_ok=True)


@contextmanager
def writing(what: str, path: str):
    """Writing a report: an OSError (disk full, a file that changed since it was checked) is a
    plain error, not an internal one."""
    try:
        yield
    except OSError as e:
        raise UsageError(f"{what} {path}: cannot write it: {e.strerror or e}") from None


def non_negative_int(text: str) -> int:
    try:
        v = int(text)
    except ValueError:
        raise UsageError(f"{text!r} is not an integer") from None
    if v < 0:
        raise UsageError(f"{v}: expected 0 or more")
    return v


def positive_int(text: str) -> int:
    """An argparse type: a whole number of 1 or more."""
    import argparse
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"{v}: expected 1 or more")
    return v


def add_domain_options(p) -> None:
    p.add_argument("--int-range", metavar="LO..HI",
                   help="bound the Integer and Natural domains (for monitored functions and quantifiers over them)")
    p.add_argument("--monitored", action="append", metavar="NAME=LO..HI",
                   help="the values a monitored function ranges over (repeatable); also NAME=v1,v2,...")
    p.add_argument("--max-loop", type=positive_int, metavar="N",
                   help="the most iterations of one while/iterate within a step (default 10000)")


def monitored_option(args) -> dict:
    """``--monitored NAME=VALUES`` (repeated) as {name: values}; names are checked against the
    spec by the API."""
    mons: dict = {}
    for item in getattr(args, "monitored", None) or []:
        if "=" not in item:
            raise UsageError(f"--monitored expects NAME=LO..HI or NAME=v1,v2,..., not {item!r}")
        name, rng = item.split("=", 1)
        name = name.strip()
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
            raise UsageError(f"--monitored {item!r}: {name!r} is not a function name")
        if name in mons:
            raise UsageError(f"--monitored {name} is given twice")
        mons[name] = parse_range(rng, f"--monitored {name}")
    return mons


def load_options(args) -> dict:
    """The options of :func:`asmcheck.load` given on the command line."""
    opts = {"import_path": list(getattr(args, "import_path", None) or []),
            "monitored": monitored_option(args),
            "int_range": parse_int_range(args.int_range) if getattr(args, "int_range", None) else None}
    if getattr(args, "max_loop", None) is not None:
        opts["max_loop"] = args.max_loop
    if hasattr(args, "properties"):
        opts["properties"] = args.properties
        opts["default_properties"] = not getattr(args, "no_default_properties", False)
    return opts


def add_explore_options(p) -> None:
    p.add_argument("--max-states", type=int, metavar="N", help="stop once N (1 or more) distinct states are found (verdict incomplete); the state being "
                   "expanded is finished first, so the report may count a few more")
    p.add_argument("--max-depth", type=int, metavar="N", help="do not go deeper than N steps (verdict incomplete)")
    p.add_argument("--max-seconds", type=float, metavar="S",
                   help="stop after S seconds of wall-clock time for the whole command, LTL/CTL and the "
                        "native engine's compile included (verdict incomplete; a compile is not cut short: it "
                        "is cached for the next run)")
    p.add_argument("--max-memory", metavar="SIZE",
                   help="stop when the process holds more than SIZE of memory (2G, 512M; verdict incomplete); "
                        "default: three quarters of the physical memory; 0: no limit")
    p.add_argument("--deadlock", action="store_true",
                   help="report a state whose only successor is itself, or that has none")
    p.add_argument("--properties", action="append", metavar="FILE",
                   help="a property file to check (repeatable; it must apply to the spec); by default the files "
                        "in properties/ that apply")
    p.add_argument("--no-default-properties", action="store_true",
                   help="check only the spec's own properties (and --properties files)")
    p.add_argument("--engine", choices=["auto", "python", "native"], default="auto",
                   help="native: the spec compiled to C (needs a C compiler; refused, with the reason, for the "
                        "few constructs it does not cover); python: the step function itself; auto (default): "
                        "native when it can, else python, and the report says why")
    p.add_argument("--fair", action="append", default=[], metavar="DOMAIN|all",
                   help="weak fairness for LTL/CTL: every agent of DOMAIN (or, with 'all', every alternative "
                        "of every choose rule) that is continuously enabled eventually moves; monitored inputs "
                        "are not constrained (declare JUSTICE constraints in the spec for them)")
    add_domain_options(p)
    from .scaling import add_explore_options as add_scaling_options
    add_scaling_options(p)


def check_limits(args) -> None:
    """The limits every command takes (--max-states, --max-depth, --max-seconds, --loop-bound), checked
    alike: a usage error for a state limit below 1 (the initial states are always found: a limit of 0
    would stop before them, and --max-depth 0 is the way to check them alone), a negative depth, a
    loop bound below 1, or a time that is not a number of seconds, 0 or more (nan, inf)."""
    states = getattr(args, "max_states", None)
    if states is not None and states < 1:
        raise UsageError(max_states_error("--max-states", states, "--max-depth 0"))
    depth = getattr(args, "max_depth", None)
    if depth is not None and depth < 0:
        raise UsageError("--max-depth must be 0 or more")
    secs = getattr(args, "max_seconds", None)
    if secs is not None and not (secs >= 0 and secs < float("inf")):
        raise UsageError("--max-seconds must be a number of seconds, 0 or more")
    bound = getattr(args, "loop_bound", None)
    if bound is not None and bound < 1:
        raise UsageError("--loop-bound must be 1 or more")


def explore_options(args) -> dict:
    """The options of :meth:`asmcheck.Model.explore` given on the command line; the time limit
    counts from the start of the command."""
    check_limits(args)
    secs = getattr(args, "max_seconds", None)
    mem = getattr(args, "max_memory", None)
    opts = {"engine": getattr(args, "engine", "auto"), "max_states": getattr(args, "max_states", None),
            "max_depth": getattr(args, "max_depth", None), "max_seconds": secs,
            "max_memory": parse_size(mem) if mem is not None else None,
            "deadlock": getattr(args, "deadlock", False), "fair": list(getattr(args, "fair", []) or [])}
    from .scaling import options as scaling_options
    opts.update(scaling_options(args))
    if secs is not None:
        opts["started"] = getattr(args, "started", None)
    return opts


# ----------------------------------------------------------------- progress
class Progress:
    """A live line on a terminal's stderr: states, transitions, depth, states/s, memory and
    elapsed time (rich); nothing when stderr is not a terminal."""

    def __init__(self):
        self.live = None
        try:
            on = sys.stderr.isatty()
        except (AttributeError, ValueError):
            on = False
        if not on:
            return
        from rich.console import Console
        from rich.live import Live
        self.console = Console(stderr=True)
        self.live = Live(console=self.console, transient=True, refresh_per_second=4)

    def __enter__(self):
        if self.live is not None:
            self.live.start()
        return self if self.live is not None else None

    def __call__(self, states, depth, transitions, secs):
        from rich.text import Text
        from ..api import memory_in_use
        rate = states / secs if secs > 0 else 0
        mem = memory_in_use() / 2**20
        line = Text.assemble(("exploring ", "bold"), f"{states:,} states, {transitions:,} transitions, depth {depth}, ",
                             (f"{rate:,.0f} states/s", "cyan"), f", {mem:,.0f} MB, {secs:,.1f} s")
        self.live.update(line)

    def __exit__(self, *exc):
        if self.live is not None:
            self.live.stop()
        return False


VERDICT_STYLE = {"holds": "green", "violated": "bold red", "incomplete": "yellow", "cannot be checked": "bold red",
                 "proved": "green", "holds-to-depth": "green", "unknown": "yellow"}


def verdict_rows(rows, width: int = 40) -> None:
    """The property table: plain aligned text, or coloured by verdict on a terminal."""
    if not color_on():
        for r in rows:
            out(f"  {r[0]:<{width}} {r[1]}")
        return
    from rich.console import Console
    from rich.text import Text
    con = Console(file=sys.stdout, highlight=False, soft_wrap=True)
    for name, verdict in rows:
        word = verdict.split(" ", 1)[0] if verdict.split(" ", 1)[0] in VERDICT_STYLE else verdict
        style = VERDICT_STYLE.get(word, VERDICT_STYLE.get(verdict, ""))
        con.print(Text.assemble(f"  {name:<{width}} ", (verdict, style)))
