"""The command-line side of the scaling modes: options, refusals, and the swarm command.

``explore`` gains ``--workers N|auto``, ``--cluster ADDRESS|auto|local``, ``--worker-memory MB``
and ``--bitstate BITS``; ``simulate`` gains ``--swarm [N]`` and ``--depth D``.  The command
modules call :func:`add_explore_options`/:func:`explore` and :func:`add_simulate_options`/
:func:`cmd_swarm`; everything else lives here.
"""
from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

from ..errors import UsageError
from . import Recipe, explore_partitioned, parse_workers
from .search import WorkerLost

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
    g.add_argument("--depth", type=int, default=DEFAULT_DEPTH, metavar="D",
                   help=f"steps per walk of --swarm (default {DEFAULT_DEPTH})")
    g.add_argument("--swarm-workers", metavar="N|auto", default="auto",
                   help="worker processes (or Ray tasks) for --swarm (default: one per core)")
    g.add_argument("--cluster", metavar="ADDRESS|auto|local", default=None,
                   help="run the --swarm walks as Ray tasks on this cluster (needs pip install 'asmcheck[cluster]')")


def options(args) -> dict:
    """The scaling options of :meth:`asmcheck.Model.explore` given on the command line."""
    return {"workers": parse_workers(getattr(args, "workers", None)), "cluster": getattr(args, "cluster", None),
            "bitstate": getattr(args, "bitstate", None), "worker_memory": getattr(args, "worker_memory", None)}


def wanted(workers=1, cluster=None, bitstate=None, worker_memory=None) -> bool:
    """Whether an exploration runs in one of the scaling modes."""
    return (workers or 1) > 1 or bool(cluster) or bitstate is not None


def memory_share(worker_memory, max_memory, workers: int):
    """Bytes of resident memory each worker may use: ``worker_memory`` (MB), else an equal share of
    ``max_memory`` (bytes), else of nine tenths of the memory available now."""
    if worker_memory is not None:
        if worker_memory <= 0:
            raise UsageError("--worker-memory expects a positive number of megabytes")
        return int(worker_memory * 1024 * 1024)
    if max_memory:
        return max_memory // workers
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024 * 9 // 10 // workers
    except OSError:  # pragma: no cover - not Linux
        pass
    return None


def explore_model(model, state_props, step_props, *, workers=1, cluster=None, bitstate=None, worker_memory=None,
                  max_states=None, max_depth=None, max_seconds=None, max_memory=None, deadlock=False,
                  engine="auto", keep_graph=False, progress=None):
    """Explore a loaded :class:`asmcheck.api.Model` in the scaling mode asked for (more workers, a
    Ray cluster, bitstate).  Returns (explorer, result) as the sequential search does."""
    workers = parse_workers(workers)
    if engine == "native":
        raise UsageError("--workers, --cluster and --bitstate run the Python step function; the native engine "
                         "does not offer its successor function to them (drop --engine native)")
    machine = model.machine
    if bitstate is not None:
        if workers > 1 or cluster:
            raise UsageError("--bitstate runs on one worker (drop --workers/--cluster)")
        if keep_graph:
            raise UsageError("--bitstate keeps no state graph, so it cannot check LTL/CTL properties or write "
                             "--graph: drop them (--no-default-properties, --properties FILE) or drop --bitstate")
        if not 10 <= bitstate <= 40:
            raise UsageError("--bitstate expects BITS from 10 to 40 (a table of 2**BITS bits)")
        from .bitstate import BitstateExplorer
        ex = BitstateExplorer(machine, bitstate, max_states=max_states, max_depth=max_depth,
                              max_seconds=max_seconds, deadlock=deadlock, progress=progress,
                              state_props=state_props, step_props=step_props)
        result = ex.run()
        result.engine = "python"
        result.notes = [ex.note()]
        result.bitstate = ex.report()
        return ex, result
    backend = "processes"
    if cluster:
        from .cluster import import_ray
        import_ray()
        backend = "ray"
    from ..semantics.resolve import import_path
    recipe = Recipe(str(Path(model.path).resolve()), dict(model.options), model.prop_files,
                    model.default_properties, list(import_path()), deadlock,
                    [p.name for p in state_props], [p.name for p in step_props])
    try:
        return explore_partitioned(machine, workers=workers, backend=backend, cluster=cluster,
                                   state_props=state_props, step_props=step_props, deadlock=deadlock,
                                   max_states=max_states, max_depth=max_depth, max_seconds=max_seconds,
                                   keep_graph=keep_graph, progress=progress,
                                   memory_share=memory_share(worker_memory, max_memory, workers), recipe=recipe)
    except WorkerLost as e:
        raise UsageError(str(e)) from None


def report_lines(result) -> list:
    """What a scaling mode adds to the text report (the bitstate miss probability)."""
    return list(getattr(result, "notes", ()))


def report_json(result) -> dict:
    return {"bitstate": result.bitstate} if getattr(result, "bitstate", None) else {}


# ----------------------------------------------------------------- swarm
def cmd_swarm(args, model) -> int:
    """``simulate --swarm``: print the report; returns the exit code (1: a violation found)."""
    spec, machine = model.spec, model.machine
    state_props, step_props, temporal = list(model.state_props), list(model.step_props), list(model.temporal)
    from ..report.trace import temporal_json, temporal_text, trace_json, trace_text
    from .swarm import run_walks, swarm, swarm_traces
    if args.swarm < 1 or args.depth < 1:
        raise UsageError("--swarm and --depth expect positive numbers")
    workers = parse_workers(getattr(args, "swarm_workers", "auto"))
    seed = args.seed if args.seed is not None else 0
    fair = getattr(args, "fair", None) or []
    t0 = time.perf_counter()
    cluster = getattr(args, "cluster", None)
    recipe = None
    if cluster:
        from ..semantics.resolve import import_path
        from .cluster import import_ray
        import_ray()
        recipe = Recipe(str(Path(model.path).resolve()), dict(model.options), model.prop_files,
                        model.default_properties, list(import_path()))
    try:
        res = swarm(machine, state_props, step_props, args.swarm, args.depth, seed=seed, workers=workers,
                    deadlock=getattr(args, "deadlock", False), temporal=temporal, fair=fair, cluster=cluster,
                    recipe=recipe)
    except WorkerLost as e:
        raise UsageError(str(e)) from None
    secs = time.perf_counter() - t0
    traces = swarm_traces(machine, state_props, step_props, res, getattr(args, "deadlock", False))
    lassos = []
    for name, f in sorted(res.found.items(), key=lambda kv: (kv[1].length, kv[1].walk)):
        if f.prop_kind == "ltl":
            keep = {}
            run_walks(machine, state_props, step_props, [f.walk], args.depth, seed, False, temporal, fair, keep)
            ex, results = keep[f.walk]
            lassos.extend(r for r in results if r.name == name and not r.holds)
    rules = sorted({r.name for r in machine.spec.rules if r.body is not None})
    covered = sorted(set(rules) & res.covered)
    missing = [r for r in rules if r not in res.covered]
    rows = []
    for p in state_props + step_props:
        rows.append((p.name, _row(res.found.get(p.name))))
    for p in temporal:
        if p.kind == "ltl":
            rows.append((p.name, _row(res.found.get(p.name), " (on each walk's own graph)")))
        elif p.kind == "ctl":
            rows.append((p.name, "not checked (CTL needs the whole state graph: use explore)"))
    for extra in ("deadlock", "error"):
        if extra in res.found:
            rows.append((extra, _row(res.found[extra])))
    violated = bool(res.found)
    if args.format == "json":
        doc = {"spec": spec.name, "walks": res.walks, "depth": res.depth, "seed": seed,
               "states_met": res.states_met, "steps": res.steps_taken, "seconds": round(secs, 3),
               "rule_coverage": {"covered": covered, "not_covered": missing, "rules": len(rules)},
               "properties": [{"property": n, "verdict": v} for n, v in rows],
               "violations": [{"property": v.prop.name, "kind": tr.kind, "message": v.message,
                               "walk": res.found[v.prop.name].walk, "trace": trace_json(machine, tr)}
                              for v, tr in traces]
                             + [temporal_json(t, machine) for t in lassos],
               "verdict": "violated" if violated else "no violation found"}
        print(json.dumps(doc, indent=2))
        return 1 if violated else 0
    color = sys.stdout.isatty() and not os.environ.get("NO_COLOR")
    print(f"{Path(args.file).name}: swarm of {res.walks} walks of up to {res.depth} steps (seed {seed}): "
          f"{res.states_met:,} states met, {res.steps_taken:,} steps taken, {secs:.2f} s")
    print(f"  rule coverage: {len(covered)} of {len(rules)} rules made an update"
          + (f" (not: {', '.join(missing)})" if missing else ""))
    for name, verdict in rows:
        print(f"  {name:<40} {verdict}")
    for v, tr in traces:
        print()
        where = f" ({v.prop.span.short()})" if getattr(v.prop, "span", None) is not None and v.prop.span.line else ""
        what = "deadlock" if v.prop.name == "deadlock" else f"{v.prop.name}{where} is violated"
        steps = len(tr.steps) - 1
        print(f"{what}" + (f": {v.message}" if v.message else "") +
              f" -- shortest trace found (walk {res.found[v.prop.name].walk}), {steps} step{'s' if steps != 1 else ''}"
              + (" (the last step breaks it)" if tr.kind == "step" else "") + ":")
        for line in trace_text(machine, tr, color):
            print("  " + line)
    for t in lassos:
        print()
        for line in temporal_text(t, machine, color):
            print(line)
    print("verdict: " + ("violated" if violated else
                         "no violation found (random walks prove nothing: explore does)"))
    return 1 if violated else 0


def _row(f, note="") -> str:
    if f is None:
        return "no violation found" + note
    if f.prop_kind == "ltl":
        return f"violated (shortest lasso found: {f.length} states, walk {f.walk})"
    return f"violated (shortest found: {f.length} step{'s' if f.length != 1 else ''}, walk {f.walk})"
