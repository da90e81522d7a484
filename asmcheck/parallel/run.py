"""Running the scaling modes for the API: the partitioned, cluster and bitstate searches of
:meth:`asmcheck.Model.explore`, and the swarm simulation of :meth:`asmcheck.Model.swarm`
(a report as JSON and as text lines; the command line prints them)."""
from __future__ import annotations

import time
from pathlib import Path

from ..errors import UsageError
from . import Recipe, explore_partitioned, parse_workers
from .cluster import PER_NODE
from .search import WorkerLost

DEFAULT_WALKS = 32
DEFAULT_DEPTH = 100


def wanted(workers=1, cluster=None, bitstate=None, worker_memory=None) -> bool:
    """Whether an exploration runs in one of the scaling modes."""
    return (workers or 1) > 1 or bool(cluster) or bitstate is not None


def check_options(workers=1, cluster=None, bitstate=None, worker_memory=None) -> None:
    """The scaling options that do not go together, refused before the search: a worker's memory
    share (``--worker-memory``) without workers to share it (one process is bounded by
    ``--max-memory``; a bitstate search runs on one)."""
    if worker_memory is None:
        return
    if isinstance(worker_memory, bool) or not isinstance(worker_memory, (int, float)) or not worker_memory > 0 \
            or worker_memory == float("inf"):
        raise UsageError("--worker-memory expects a positive number of megabytes")
    if not cluster and (bitstate is not None or (str(workers).strip().lower() != "auto" and
                                                 parse_workers(workers or 1) <= 1)):
        raise UsageError("--worker-memory bounds each worker of --workers N or --cluster; a search in one "
                         "process is bounded by --max-memory")


def native_threads(workers=1, cluster=None, bitstate=None, worker_memory=None) -> bool:
    """Whether more workers run as threads of the native search (no cluster, no bitstate)."""
    return parse_workers(workers or 1) > 1 and not cluster and bitstate is None


def native_memory(max_memory, workers=1, cluster=None, bitstate=None, worker_memory=None):
    """The bound, in bytes, on the native search's tables: ``--worker-memory`` (MB) times the
    workers (the threads share one table), else ``max_memory``."""
    if worker_memory is not None and native_threads(workers, cluster, bitstate):
        if worker_memory <= 0:
            raise UsageError("--worker-memory expects a positive number of megabytes")
        return int(worker_memory * 1024 * 1024) * parse_workers(workers)
    return max_memory


def memory_share(worker_memory, max_memory, workers: int, cluster=None):
    """Bytes of resident memory each worker may use: ``worker_memory`` (MB); else an equal share of
    ``max_memory`` (bytes) given by the user; else the default bound (three quarters of the
    physical memory, ``max_memory`` None or that default) shared by the workers on one machine:
    on this machine an equal share, on a Ray cluster :data:`PER_NODE` (each actor's share is
    worked out on its node: the node's default bound divided among the actors placed there)."""
    from ..explore.store import default_max_memory
    if worker_memory is not None:
        if worker_memory <= 0:
            raise UsageError("--worker-memory expects a positive number of megabytes")
        return int(worker_memory * 1024 * 1024)
    default = default_max_memory()
    if cluster and (max_memory is None or max_memory == default):
        return PER_NODE
    if max_memory:
        return max_memory // workers
    if default:
        return default // workers
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
    machine = model.machine
    if bitstate is not None:
        if engine == "native":
            raise UsageError("--bitstate runs the Python step function (drop --engine native)")
        if workers > 1 or cluster:
            raise UsageError("--bitstate runs on one worker (drop --workers/--cluster)")
        if keep_graph:
            # (the spec's own LTL/CTL properties cannot be dropped from the command line)
            own = [p.name for p in getattr(model, "temporal", ()) or ()
                   if p.kind in ("ltl", "ctl") and getattr(p, "source", "spec") == "spec"]
            if own:
                raise UsageError(f"--bitstate keeps no state graph, so it cannot check LTL/CTL properties, and the "
                                 f"spec declares its own ({', '.join(own)}): drop --bitstate")
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
    # the partitions expand states with the native engine's compiled step function where it takes
    # the spec ('auto', 'native'), else with the Python step function
    expander = {"native": "native", "python": "python"}.get(engine, "auto")
    from .native_expand import Refused
    try:
        return explore_partitioned(machine, workers=workers, backend=backend, cluster=cluster,
                                   state_props=state_props, step_props=step_props, deadlock=deadlock,
                                   max_states=max_states, max_depth=max_depth, max_seconds=max_seconds,
                                   keep_graph=keep_graph, progress=progress,
                                   memory_share=memory_share(worker_memory, max_memory, workers, cluster), recipe=recipe,
                                   expander=expander)
    except WorkerLost as e:
        raise UsageError(str(e)) from None
    except Refused as e:
        raise UsageError(f"the native explorer cannot run {Path(model.path).name}: {e}") from None


# ----------------------------------------------------------------- swarm
def swarm_report(model, *, walks: int = DEFAULT_WALKS, depth: int = DEFAULT_DEPTH, seed=None, workers="auto",
                 cluster=None, deadlock: bool = False, fair=(), color: bool = False) -> "SwarmReport":
    """Random walks from the initial states, every property checked on every state met (see
    :func:`asmcheck.parallel.swarm.swarm`): the report as JSON and as text lines."""
    spec, machine = model.spec, model.machine
    state_props, step_props, temporal = list(model.state_props), list(model.step_props), list(model.temporal)
    from ..report.trace import failing_json, temporal_json, temporal_text, trace_json
    from ..report.place import found_violation_lines, property_place
    from .swarm import run_walks, swarm, swarm_traces
    if walks < 1 or depth < 1:
        raise UsageError("--swarm and --depth expect positive numbers")
    workers = parse_workers(workers)
    seed = seed if seed is not None else 0
    fair = list(fair or [])
    t0 = time.perf_counter()
    recipe = None
    if cluster:
        from ..semantics.resolve import import_path
        from .cluster import import_ray
        import_ray()
        recipe = Recipe(str(Path(model.path).resolve()), dict(model.options), model.prop_files,
                        model.default_properties, list(import_path()))
    try:
        res = swarm(machine, state_props, step_props, walks, depth, seed=seed, workers=workers,
                    deadlock=deadlock, temporal=temporal, fair=fair, cluster=cluster,
                    recipe=recipe)
    except WorkerLost as e:
        raise UsageError(str(e)) from None
    secs = time.perf_counter() - t0
    traces = swarm_traces(machine, state_props, step_props, res, deadlock)
    lassos = []
    for name, f in sorted(res.found.items(), key=lambda kv: (kv[1].length, kv[1].walk)):
        if f.prop_kind == "ltl":
            keep = {}
            run_walks(machine, state_props, step_props, [f.walk], depth, seed, False, temporal, fair, keep)
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
    doc = {"spec": spec.name, "walks": res.walks, "depth": res.depth, "seed": seed,
           "states_met": res.states_met, "steps": res.steps_taken, "seconds": round(secs, 3),
           "rule_coverage": {"covered": covered, "not_covered": missing, "rules": len(rules)},
           "properties": [{"property": n, "verdict": v} for n, v in rows],
           "violations": [{"property": v.prop.name, "kind": tr.kind, "message": v.message, **property_place(v.prop),
                           "walk": res.found[v.prop.name].walk, "trace": trace_json(machine, tr),
                           **({"failing_step": failing_json(tr)} if tr.failing is not None else {})}
                          for v, tr in traces]
                         + [{**temporal_json(t, machine), **property_place(t.prop)} for t in lassos],
           "verdict": "violated" if violated else "no violation found"}
    out: list[str] = []
    say = out.append        # the text report, line by line
    say(f"{Path(model.path).name}: swarm of {res.walks} walks of up to {res.depth} steps (seed {seed}): "
          f"{res.states_met:,} states met, {res.steps_taken:,} steps taken, {secs:.2f} s")
    say(f"  rule coverage: {len(covered)} of {len(rules)} rules made an update"
          + (f" (not: {', '.join(missing)})" if missing else ""))
    for name, verdict in rows:
        say(f"  {name:<40} {verdict}")
    for v, tr in traces:
        say("")
        # as explore shows a violation; the trace is the shortest found, by the walk named
        for line in found_violation_lines(machine, v.prop, tr, v.message, color,
                                          f"counterexample found (walk {res.found[v.prop.name].walk})"):
            say(line)
    for t in lassos:
        say("")
        for line in temporal_text(t, machine, color):
            say(line)
    say("verdict: " + ("violated" if violated else
                         "no violation found (random walks prove nothing: explore does)"))
    return SwarmReport(doc, out, violated)


class SwarmReport:
    """What :func:`swarm_report` found: ``json()`` (a dict), ``lines`` (the text report) and
    ``violated``."""

    def __init__(self, doc: dict, lines: list, violated: bool):
        self.doc = doc
        self.lines = lines
        self.violated = violated

    def json(self) -> dict:
        return self.doc


def _row(f, note="") -> str:
    if f is None:
        return "no violation found" + note
    if f.prop_kind == "ltl":
        return f"violated (shortest lasso found: {f.length} states, walk {f.walk})"
    return f"violated (shortest found: {f.length} step{'s' if f.length != 1 else ''}, walk {f.walk})"
