"""``asmcheck testgen FILE --criterion rule|branch|update|mcdc [--out DIR]``: Avalla scenarios, each a
shortest path from the initial state, covering every coverable target (see docs/review.md)."""
from __future__ import annotations


def register(sub) -> None:
    from ..review.testgen import add_testgen_options
    p = sub.add_parser(
        "testgen", help="generate Avalla scenarios that cover rules, branches, updates or conditions",
        description="Explore FILE and write a small set of Avalla scenarios, each a shortest path from the initial "
                    "state, that together cover every coverable target of the criterion; the targets no "
                    "reachable configuration covers (dead code) are listed.",
        epilog="Exit codes: 0 done; 2 usage, syntax or type error; 3 incomplete (a limit stopped the exploration "
               "first: more targets may be coverable).")
    add_testgen_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..review.testgen import run_testgen
    from .common import check_limits, check_output_folder
    check_limits(args)
    if args.out is not None:
        check_output_folder(args.out, "--out")
    return run_testgen(args)
