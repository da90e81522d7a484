"""Swarm simulation (``simulate --swarm N --depth D``): many random walks, spread over workers.

Walk ``i`` starts from a random initial state and takes up to ``D`` random steps; its random
choices come from its own generator seeded with (seed, i), so what a walk does depends on
neither the number of workers nor on the other walks.  At every state a walk reaches, every
successor the step function enumerates is *met*: invariants are checked on it and step
properties on the step to it, and the rules that made the step's updates are counted as covered.
Per property the shortest violation over all walks is kept (ties: the lower walk number) and
replayed through the step function, as every trace is.

LTL properties are checked on each walk's own graph (the states it visited and the steps it took,
up to its last return to a state it had visited before): every infinite path of that graph is a
run of the spec, so a violation found there is real, though "not found" proves nothing.  CTL
properties need the whole graph and are named as not checked.
"""
from __future__ import annotations

import random
from dataclasses import dataclass, field

from ..errors import AsmError


@dataclass
class Found:
    prop_kind: str          # state step deadlock error
    prop_index: int
    length: int             # steps from the initial state to the violating state
    walk: int
    picks: list             # [initial picks, step picks...] up to the violating state
    message: str = ""


@dataclass
class SwarmResult:
    walks: int
    depth: int
    seed: int
    states_met: int = 0
    steps_taken: int = 0
    covered: set = field(default_factory=set)
    found: dict = field(default_factory=dict)     # property name -> Found
    errors: int = 0


def _better(a: Found | None, b: Found) -> bool:
    return a is None or (b.length, b.walk) < (a.length, a.walk)


def run_walks(machine, state_props, step_props, walk_ids, depth: int, seed: int, deadlock=False,
              temporal=(), fair=(), keep=None) -> SwarmResult:
    """Run the walks ``walk_ids`` (in this process).  ``temporal``: the LTL properties (and the
    fairness constraints) to check on each walk's graph; ``keep``: a dict that receives, per
    walk, its graph explorer and temporal results (to print a lasso)."""
    from .expand import PythonExpander
    x = PythonExpander(machine, state_props, step_props, deadlock)
    ex = x.ex
    m = machine
    out = SwarmResult(len(walk_ids), depth, seed)
    found = out.found
    inits = [(dict(k), p) for k, p in x.initial()]
    init_fail = [x.check_state(st) for st, _ in inits]

    def note(name, f):
        if _better(found.get(name), f):
            found[name] = f

    for w in walk_ids:
        rng = random.Random(f"asmcheck-swarm:{seed}:{w}")
        if not inits:
            break
        i0 = rng.randrange(len(inits))
        st, p0 = inits[i0]
        path = [p0]
        walk_states = [st]
        out.states_met += 1
        for i, msg, _ in init_fail[i0]:
            note(state_props[i].name, Found("state", i, 0, w, list(path), msg))
        for d in range(depth):
            try:
                succ = ex.admitted_successors(st)
            except AsmError as e:
                note("error", Found("error", -1, d, w, list(path), e.message))
                out.errors += 1
                break
            options = []
            for picks, ups, nxt, canon, mon in succ:
                for u in ups.locs.values():
                    if u.rule is not None:
                        out.covered.add(u.rule)
                out.states_met += 1
                for i, prop in enumerate(step_props):
                    try:
                        ok = prop.check_step(m, st, ups, nxt, mon)
                        msg = ""
                    except AsmError as e:
                        ok, msg = False, f"cannot be evaluated: {e.message}"
                    if not ok:
                        note(prop.name, Found("step", i, d + 1, w, path + [picks], msg))
                for i, msg, _ in x.check_state(canon):
                    note(state_props[i].name, Found("state", i, d + 1, w, path + [picks], msg))
                options.append((picks, canon))
            if deadlock and all(x.ex.layout.freeze(c) == x.ex.layout.freeze(st) for _, c in options):
                note("deadlock", Found("deadlock", -1, d, w, list(path),
                                       "no successor" if not options else "the only successor is the state itself"))
            if not options:
                break
            picks, st = options[rng.randrange(len(options))]
            path.append(picks)
            walk_states.append(st)
            out.steps_taken += 1
        if temporal:
            _walk_temporal(machine, state_props, step_props, temporal, fair, w, path, walk_states, note, keep)
    return out


def _walk_temporal(machine, state_props, step_props, temporal, fair, w, path, walk_states, note, keep):
    """Check the LTL properties on the graph of one walk, cut after its last return."""
    from ..explore.bfs import Explorer
    from ..temporal import check_temporal
    ex = Explorer(machine, state_props=state_props, step_props=step_props, keep_graph=True)
    first = {}
    fzs = [ex.layout.freeze(st) for st in walk_states]
    last = -1
    for i, fz in enumerate(fzs):
        if fz in first:
            last = i
        else:
            first[fz] = i
    if last < 0:
        return
    ltl = [p for p in temporal if p.kind == "ltl"]
    if not ltl:
        return
    prev = None
    for i in range(last + 1):
        sid, _ = ex._add(walk_states[i], -1 if i == 0 else prev, path[i], i)
        if prev is not None:
            ex.edges.append((prev, sid, path[i]))
        prev = sid
    props = ltl + [p for p in temporal if p.kind in ("justice", "compassion")]
    results = check_temporal(ex, props, fair=fair)
    if keep is not None:
        keep[w] = (ex, results)
    for k, r in enumerate(results):
        if not r.holds and getattr(r, "verdict", None) != "error" and not getattr(r, "message", ""):
            # its length: the lasso's states (steps to the loop and around it once)
            note(r.name, Found("ltl", k, len(r.nodes) or last, w, path[:last + 1]))


def merge(parts: list, walks: int, depth: int, seed: int) -> SwarmResult:
    out = SwarmResult(walks, depth, seed)
    for p in parts:
        out.states_met += p.states_met
        out.steps_taken += p.steps_taken
        out.errors += p.errors
        out.covered |= p.covered
        for name, f in p.found.items():
            if _better(out.found.get(name), f):
                out.found[name] = f
    return out


def _walker(conn, machine, state_props, step_props, ids, depth, seed, deadlock, temporal, fair):
    try:
        conn.send(("ok", run_walks(machine, state_props, step_props, ids, depth, seed, deadlock, temporal, fair)))
    except BaseException as e:  # pragma: no cover - reported to the caller
        conn.send(("err", f"{type(e).__name__}: {e}"))


def _ray_walks(recipe, ids, depth, seed, deadlock, fair):
    machine, state_props, step_props, temporal = recipe.load_all()
    return run_walks(machine, state_props, step_props, ids, depth, seed, deadlock, temporal, fair)


def swarm(machine, state_props, step_props, walks: int, depth: int, seed: int = 0, workers: int = 1,
          deadlock=False, temporal=(), fair=(), cluster=None, recipe=None) -> SwarmResult:
    """``walks`` random walks of up to ``depth`` steps, on ``workers`` forked processes, or as
    ``workers`` Ray tasks on ``cluster`` (each rebuilding the machine from ``recipe``)."""
    ids = list(range(walks))
    temporal = list(temporal)
    if cluster:
        from .cluster import connect, shutdown
        from .search import WorkerLost
        ray, started = connect(cluster, workers)
        try:
            task = ray.remote(num_cpus=1, max_retries=0)(_ray_walks)
            refs = [task.remote(recipe, ids[w::workers], depth, seed, deadlock, list(fair)) for w in range(workers)]
            try:
                parts = ray.get(refs)
            except ray.exceptions.RayError as e:
                raise WorkerLost(f"a swarm task failed ({type(e).__name__}); no result") from None
        finally:
            if started:
                shutdown(ray)
        return merge(parts, walks, depth, seed)
    if workers <= 1 or walks <= 1:
        return merge([run_walks(machine, state_props, step_props, ids, depth, seed, deadlock, temporal, fair)],
                     walks, depth, seed)
    import multiprocessing
    from .search import WorkerLost
    ctx = multiprocessing.get_context("fork")
    procs, conns = [], []
    try:
        for w in range(workers):
            a, b = ctx.Pipe()
            p = ctx.Process(target=_walker, args=(b, machine, state_props, step_props, ids[w::workers], depth,
                                                  seed, deadlock, temporal, fair), daemon=True)
            p.start()
            b.close()
            procs.append(p)
            conns.append(a)
        parts = []
        for w, c in enumerate(conns):
            try:
                status, res = c.recv()
            except (EOFError, OSError):
                procs[w].join(1.0)
                raise WorkerLost(f"swarm worker {w + 1} died (exit code {procs[w].exitcode}); no result") from None
            if status != "ok":
                raise RuntimeError(res)
            parts.append(res)
    finally:
        for p in procs:
            p.join(timeout=2.0)
            if p.is_alive():
                p.kill()
                p.join()
    return merge(parts, walks, depth, seed)


def swarm_traces(machine, state_props, step_props, res: SwarmResult, deadlock=False):
    """The violations found, each as (Violation, Trace) replayed through the step function, in
    the order of the properties (state properties, step properties, deadlock, error)."""
    from ..explore.bfs import DEADLOCK, Explorer, PseudoProperty, Violation
    from ..report.trace import build_trace
    from ..semantics.machine import ScriptChooser
    out = []
    names = [p.name for p in state_props] + [p.name for p in step_props] + ["deadlock", "error"]
    for name in names:
        f = res.found.get(name)
        if f is None:
            continue
        ex = Explorer(machine, state_props=state_props, step_props=step_props, deadlock=deadlock)
        # the walk's states, rebuilt from its choices: the trace is the walk itself
        st = ex._norm(machine.initial_state(ScriptChooser(f.picks[0])))
        sid, _ = ex._add(st, -1, f.picks[0], 0)
        steps = f.picks[1:]
        last = steps[-1] if f.prop_kind == "step" else None
        if last is not None:
            steps = steps[:-1]
        for k, picks in enumerate(steps):
            ups, raw, ctx = machine.step(st, ScriptChooser(picks))
            st = ex._norm(raw)
            sid = _append(ex, st, sid, picks, k + 1)
        if f.prop_kind == "step":
            prop = step_props[f.prop_index]
            ups, raw, ctx = machine.step(st, ScriptChooser(last))
            tid = _append(ex, ex._norm(raw), sid, last, len(steps) + 1)
            v = Violation(prop, tid, sid, last, message=f.message)
        elif f.prop_kind == "state":
            v = Violation(state_props[f.prop_index], sid, message=f.message)
        elif f.prop_kind == "deadlock":
            v = Violation(DEADLOCK, sid, message=f.message)
        else:
            # the walk's last step fails: found again (where, with which inputs and choices) as explore shows it
            try:
                ex.admitted_successors(st)
            except AsmError as e:
                v = Violation(PseudoProperty("error", "error", e.span), sid, message=e.message, error=e)
            else:
                v = Violation(PseudoProperty("error", "error"), sid, message=f.message)
        out.append((v, build_trace(ex, v)))
    return out


def _append(ex, st, parent, picks, depth) -> int:
    """Add a walk's state to the trace explorer even when the walk came back to it (a trace
    may pass a state twice)."""
    fz = ex.layout.freeze(st)
    sid = len(ex.frozen)
    ex.index.setdefault(fz, sid)
    ex.frozen.append(fz)
    ex.parent.append(parent)
    ex.depth_of.append(depth)
    ex.via.append(picks)
    return sid
