"""``asmcheck testgen FILE --criterion rule|branch|update [--out DIR]``: Avalla scenarios, each a
shortest path from the initial state, covering every coverable target (see
:mod:`asmcheck.review.testgen` and docs/review.md)."""
from __future__ import annotations


def register(sub) -> None:
    from ..review.testgen import add_testgen_options
    p = sub.add_parser("testgen", help="generate Avalla scenarios covering rules, branches or updates",
                       description=__doc__)
    add_testgen_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..review.testgen import run_testgen
    return run_testgen(args)
