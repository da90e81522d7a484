"""``asmcheck advise FILE [--format json] [--mp 1,2,..]``: AsmetaMA's model-advisor checks, computed
exactly over the explored configurations (see :mod:`asmcheck.review.advise` and docs/review.md)."""
from __future__ import annotations


def register(sub) -> None:
    from ..review.advise import add_advise_options
    p = sub.add_parser("advise", help="the model advisor's checks (AsmetaMA's meta-properties), exactly",
                       description=__doc__)
    add_advise_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ..review.advise import run_advise
    return run_advise(args)
