"""``asmcheck simulate``: run a spec step by step."""
from __future__ import annotations

import json

from .. import api
from .common import EXIT_OK, EXIT_VIOLATED, add_domain_options, color_on, error, load_options, out


def run(args) -> int:
    from .scaling import DEFAULT_DEPTH, check_simulate_options
    check_simulate_options(args)
    opts = load_options(args)
    if getattr(args, "swarm", None) is not None:
        model = api.load(args.file, **opts)
        rep = model.swarm(walks=args.swarm, depth=DEFAULT_DEPTH if args.depth is None else args.depth,
                          seed=args.seed, workers=args.swarm_workers or "auto",
                          cluster=getattr(args, "cluster", None),
                          deadlock=getattr(args, "deadlock", False), fair=getattr(args, "fair", None) or [],
                          color=args.format != "json" and color_on())
        if args.format == "json":
            out(json.dumps(rep.json(), indent=2))
        else:
            out("\n".join(rep.lines))
        return EXIT_VIOLATED if rep.violated else EXIT_OK
    model = api.load(args.file, default_properties=False, **opts)
    sim = model.simulate(10 if args.steps is None else args.steps, seed=args.seed, random=args.random,
                         inputs=args.input)
    if args.format == "json":
        out(json.dumps(sim.json(), indent=2))
    elif args.format == "asmeta":
        out(sim.asmeta().rstrip("\n"))
        if sim.interrupted:
            error(f"asmcheck: {sim.stopped_note()}")
    else:
        out(sim.text().rstrip("\n"))
    return sim.exit_code


def register(sub) -> None:
    p = sub.add_parser("simulate", help="run a spec step by step",
                       description="Run FILE for N steps and print what changed per step. choose takes the "
                                   "first candidate and monitored functions their first value, unless --random "
                                   "(or --seed) picks at random or --input gives the values.")
    p.add_argument("file", metavar="FILE")
    p.add_argument("-n", "--steps", type=int, default=None, metavar="N", help="number of steps (default 10)")
    p.add_argument("--seed", type=int, help="random choices, from this seed (reproducible)")
    p.add_argument("--random", action="store_true", help="random choices (seed 0 unless --seed)")
    p.add_argument("--input", metavar="FILE", help="monitored values: 'location = value' lines, '---' between steps")
    p.add_argument("--format", choices=["text", "asmeta", "json"], default="text",
                   help="text: changes per step; asmeta: ASMETA's <State n (controlled)> blocks; json")
    add_domain_options(p)
    from .scaling import add_simulate_options
    add_simulate_options(p)
    p.set_defaults(func=run)
