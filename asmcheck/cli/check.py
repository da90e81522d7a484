"""``asmcheck check``: the property gate for CI.

``asmcheck check [PATHS...]`` explores every spec under PATHS (``*.asm`` files; folders are
walked, modules skipped; default ``specs/``) with the properties that apply to it, prints
one row per spec and property, and exits

* 0 when every property holds (or is violated as the spec declares it expects),
* 1 when a property is violated unexpectedly, or an expected violation does not happen,
* 2 on an input error (a spec or property file that does not parse or type-check, a path
  that does not exist, an expected violation of a property that is not checked),
* 3 when a limit (states, depth, time, memory) or Ctrl-C stopped an exploration first.

When several apply, the first in the order 2, 1, 3 wins.  See report/gate.py for how an
expected violation (``// asmcheck: expect violated NAME``) is judged.
"""
from __future__ import annotations

import argparse
import os
import sys

from .. import api
from .common import (add_explore_options, check_output_folder, check_output_path, color_on, explore_options,
                     load_options, writing)


def run(args) -> int:
    paths = args.paths or ["specs"]
    for opt in ("junit", "sarif", "html"):
        if getattr(args, opt, None):
            check_output_path(getattr(args, opt), f"--{opt}")
    if args.json and args.json != "-":
        check_output_path(args.json, "--json")
    if args.avalla:
        check_output_folder(args.avalla, "--avalla")
        os.makedirs(args.avalla, exist_ok=True)
    opts = load_options(args)
    gate = api.check(paths, strict_expect=args.strict_expect, avalla_dir=args.avalla, **opts,
                     **explore_options(args), **({"symmetry": True} if args.symmetry else {}))
    code = gate.exit_code
    with writing("a report", ", ".join(p for p in (args.json, args.junit, args.sarif, args.html) if p and p != "-")):
        gate.write(json=args.json, junit=args.junit, sarif=args.sarif, html=args.html)
    if args.json == "-":
        sys.stdout.write(gate.json_text())
        return code
    if color_on():
        _rich_table(gate)
        sys.stdout.write(gate.text(True, traces=args.traces, table=False))
    else:
        sys.stdout.write(gate.text(False, traces=args.traces))
    for o in gate.outcomes:
        if getattr(o, "symmetry", ""):
            sys.stdout.write(f"symmetry: the states of {o.path} are counted up to {o.symmetry}\n")
        if getattr(o, "symmetry_hint", ""):
            sys.stdout.write(f"{o.path}: {o.symmetry_hint}\n")
    return code


def _rich_table(gate) -> None:
    """The verdict table in colour (on a terminal)."""
    from rich.console import Console
    from rich.table import Table
    from rich import box
    styles = {"pass": "green", "fail": "bold red", "error": "bold red", "incomplete": "yellow"}
    t = Table(box=box.SIMPLE_HEAD, show_edge=False, pad_edge=False)
    for col, just in (("SPEC", "left"), ("PROPERTY", "left"), ("VERDICT", "left"), ("STATES", "right"),
                      ("SECONDS", "right")):
        t.add_column(col, justify=just)
    for o in gate.outcomes:
        for p in o.properties:
            t.add_row(o.path, p.name, p.label, f"{o.states:,}" if o.verdict != "error" else "-", f"{o.seconds:.2f}",
                      style=styles.get(p.status, ""))
    Console(file=sys.stdout, highlight=False).print(t)


def register(sub) -> None:
    p = sub.add_parser(
        "check", help="check every spec under PATHS: the property gate for CI",
        description="Explore every spec under PATHS (.asm files; folders are walked; default specs/) with the "
                    "properties that apply to it (its own, and those of the property files in properties/), "
                    "print a table of spec, property, verdict, states and seconds, and the counterexample of "
                    "each failure. A spec may declare the properties it is built to break with a line "
                    "'// asmcheck: expect violated NAME': such a violation passes the gate ('violated "
                    "(expected)'), and fails it when it does not happen. Other violations in such a spec are "
                    "consequences of its bug: they are 'tolerated' (--strict-expect fails them).",
        epilog="Exit codes: 0 the gate passes; 1 a property is violated unexpectedly, or an expected violation "
               "does not happen; 2 input error (syntax, types, a missing path, an expected violation of an "
               "unknown property); 3 incomplete (a limit or Ctrl-C stopped an exploration first). When several "
               "apply, 2 wins over 1, and 1 over 3.",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("paths", nargs="*", metavar="PATH", help="spec files or folders (default: specs)")
    add_explore_options(p)
    from .explore import add_symmetry_option
    add_symmetry_option(p)
    p.add_argument("--junit", metavar="OUT.xml", help="write a JUnit XML report: one test case per spec and property")
    p.add_argument("--sarif", metavar="OUT.sarif",
                   help="write a SARIF 2.1.0 log: one result per violation, at the property's declaration")
    p.add_argument("--json", metavar="OUT.json", help="write the results as JSON ('-': print them instead of the "
                                                     "table); docs/check.schema.json")
    p.add_argument("--html", metavar="OUT.html", help="write a self-contained HTML report with every counterexample")
    p.add_argument("--avalla", metavar="DIR", help="write every counterexample as an Avalla scenario into DIR")
    p.add_argument("--strict-expect", action="store_true",
                   help="in a spec that declares expected violations, fail on any other violation too")
    p.add_argument("--traces", choices=["failing", "all", "none"], default="failing",
                   help="which counterexamples to print (default: those of failures)")
    p.set_defaults(func=run)
