"""``asmcheck advise FILE [--format json] [--mp 1,2,..]``: AsmetaMA's model-advisor checks, computed
exactly over the explored configurations (see docs/review.md)."""
from __future__ import annotations


def register(sub) -> None:
    from ..review.advise import add_advise_options
    p = sub.add_parser(
        "advise", help="the model advisor's checks (AsmetaMA's meta-properties), computed exactly",
        description="Explore every configuration of FILE (a reachable state with the monitored values and choices "
                    "of its step) and report AsmetaMA's meta-properties: inconsistent updates, incomplete "
                    "conditionals, empty choose/forall, trivial updates, unused domain elements and values, "
                    "removable, never updated or static locations, unreached rules.",
        epilog="Exit codes: 0 every check satisfied; 1 a check violated; 2 usage, syntax or type error; "
               "3 incomplete (a limit stopped the exploration first).")
    add_advise_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..review.advise import run_advise
    from .common import check_limits
    check_limits(args)
    return run_advise(args)
