"""The scaling options of the command line: ``explore --workers/--cluster/--worker-memory/--bitstate``
and ``simulate --swarm/--depth/--swarm-workers/--cluster``."""
from __future__ import annotations

from .. import api

DEFAULT_WALKS = 32
DEFAULT_DEPTH = 100


def add_explore_options(p) -> None:
    g = p.add_argument_group("scaling")
    g.add_argument("--workers", metavar="N|auto", default=None,
                   help="partition the states among N worker processes (auto: one per core); the result is "
                        "the same as with one worker, state numbers and traces included")
    g.add_argument("--cluster", metavar="ADDRESS|auto|local", default=None,
                   help="run the partitioned search on a Ray cluster (local: start one on this machine); "
                        "needs pip install 'asmcheck[cluster]'")
    g.add_argument("--worker-memory", type=float, metavar="MB", default=None,
                   help="resident memory each worker may use; a worker over it ends the run with a partial "
                        "report (exit 3)")
    g.add_argument("--bitstate", type=int, metavar="BITS", default=None,
                   help="bitstate search: remember visited states as 3 bits in a table of 2**BITS bits; the "
                        "report gives the probability that a state was missed")


def add_simulate_options(p) -> None:
    g = p.add_argument_group("swarm simulation")
    g.add_argument("--swarm", type=int, nargs="?", const=DEFAULT_WALKS, default=None, metavar="N",
                   help=f"run N random walks (default {DEFAULT_WALKS}) checking every property on every state "
                        "met; prints rule coverage and the shortest violation found, replayed")
    # (--depth and --swarm-workers default to None: given without --swarm they are usage errors)
    g.add_argument("--depth", type=int, default=None, metavar="D",
                   help=f"steps per walk of --swarm (default {DEFAULT_DEPTH})")
    g.add_argument("--swarm-workers", metavar="N|auto", default=None,
                   help="worker processes (or Ray tasks) for --swarm (default: one per core)")
    g.add_argument("--cluster", metavar="ADDRESS|auto|local", default=None,
                   help="run the --swarm walks as Ray tasks on this cluster (needs pip install 'asmcheck[cluster]')")


def check_simulate_options(args) -> None:
    """The options of one simulation and those of a swarm are not mixed: a usage error names the
    one the other ignores (--steps, --input or --format asmeta with --swarm; --depth,
    --swarm-workers or --cluster without it)."""
    if getattr(args, "swarm", None) is not None:
        for given, flag, why in ((getattr(args, "steps", None) is not None, "--steps", "use --depth for the steps "
                                  "of each walk"),
                                 (getattr(args, "input", None) is not None, "--input", "the walks choose the "
                                  "monitored values at random"),
                                 (getattr(args, "format", None) == "asmeta", "--format asmeta", "a swarm's report "
                                  "is text or json")):
            if given:
                raise api.UsageError(f"{flag} is an option of one simulation, not of --swarm ({why})")
        if args.swarm_workers is not None:
            try:
                api.parse_workers(args.swarm_workers)
            except api.UsageError as e:
                raise api.UsageError(str(e).replace("--workers", "--swarm-workers", 1)) from None
        return
    for value, flag in ((getattr(args, "depth", None), "--depth"), (getattr(args, "swarm_workers", None),
                                                                    "--swarm-workers"),
                        (getattr(args, "cluster", None), "--cluster")):
        if value is not None:
            raise api.UsageError(f"{flag} is an option of --swarm (the random walks); one simulation runs "
                                 f"-n/--steps steps")


def options(args) -> dict:
    """The scaling options of :meth:`asmcheck.Model.explore` given on the command line."""
    return {"workers": api.parse_workers(getattr(args, "workers", None)), "cluster": getattr(args, "cluster", None),
            "bitstate": getattr(args, "bitstate", None), "worker_memory": getattr(args, "worker_memory", None)}
