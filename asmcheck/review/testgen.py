"""``asmcheck testgen``: Avalla scenarios that cover every coverable target of a criterion.

Each target (see :mod:`.coverage`) that some reachable configuration covers has a *shortest*
witness: the configuration found first by the breadth-first exploration, reached by the shortest
path from an initial state.  The generator takes the uncovered target with the longest witness,
makes its path a scenario, marks every target the path's steps cover (the path is replayed
through the step function with the rule hook on), and repeats until every coverable target is
covered.  Targets no reachable configuration covers are listed: dead code.

Criteria: ``rule`` (every rule occurrence fires), ``branch`` (every rule occurrence and every
``if`` branch, ``switch`` case), ``update`` (every update rule executes), ``mcdc`` (``branch``,
plus for each condition of a guard made of several -- its operands under ``and``, ``or``,
``implies``, ``not`` -- two activations of the ``if`` whose outcomes differ and whose condition
values differ in that condition only; a condition that reads a monitored location the step did
not read is a don't-care).  A condition that no such pair shows is listed as uncoverable.

Each scenario is written with AsmetaV's commands only (``set``, ``pick``, ``step``, ``check``):
the checks pin the run down state by state, so it passes exactly when the run is the path's.
"""
from __future__ import annotations

import os
from pathlib import Path

from ..semantics.choice import ScriptChooser
from .coverage import targets as all_targets

CRITERIA = ("rule", "branch", "update", "mcdc")


class TestPath:
    def __init__(self, sid, picks, tid, covers):
        self.sid = sid
        self.picks = picks
        self.tid = tid
        self.covers = covers


def _wanted(criterion: str):
    # mcdc adds its condition targets to branch's (see generate)
    if criterion == "rule":
        return {"rule"}
    if criterion == "update":
        return {"update"}
    return {"rule", "branch"}


def mcdc_targets(rv) -> tuple[list, dict]:
    """MC/DC targets [(criterion, key, node, label)] and their witnesses (key -> the key of the
    configuration seen first that shows it, in the observations)."""
    from ..semantics import ir
    from .space import conditions
    vectors: dict = {}
    for k in rv.obs.first:
        if k[0] == "vector":
            vectors.setdefault(k[1], []).append(k)
    depth = rv.space.depth
    out, alias = [], {}
    for n in rv.unf.nodes:
        if not isinstance(n, ir.If):
            continue
        conds = conditions(n.cond)
        if len(conds) < 2:
            continue
        vs = vectors.get(id(n), [])
        for i, c in enumerate(conds):
            best = None
            for a in vs:
                for b in vs:
                    va, vb = a[2], b[2]
                    if a[3] == b[3] or va[i] not in (True, False) or vb[i] not in (True, False) or va[i] == vb[i]:
                        continue
                    if va[i] is not True:
                        continue
                    if any(va[j] != vb[j] and "?" not in (va[j], vb[j]) for j in range(len(conds)) if j != i):
                        continue
                    da, db = depth(rv.obs.first[a][0]), depth(rv.obs.first[b][0])
                    cost = (max(da, db), da + db, str(va), str(vb))
                    if best is None or cost < best[0]:
                        best = (cost, a, b)
            text = f"condition {i + 1} of {len(conds)}"
            for side in (0, 1):
                key = ("mcdc", id(n), i, side)
                out.append(("mcdc", key, n, text + (" true" if side == 0 else " false")))
                if best is not None:
                    alias[key] = best[1 + side]
    return out, alias


def generate(rv, criterion: str = "branch", mcdc=None):
    """(paths, targets, uncoverable, failing_only): the chosen witnesses, every target of the criterion
    [(criterion, key, node, label)], those no configuration covers, those only failing steps cover."""
    wanted = _wanted(criterion)
    tg = [t for t in all_targets(rv.unf) if t[0] in wanted]
    first = dict(rv.obs.first)
    alias: dict = {}
    if criterion == "mcdc":
        extra, alias = mcdc_targets(rv)
        tg += extra
        for k, w in alias.items():
            first[k] = first[w]
    keys = [t[1] for t in tg]
    coverable = [k for k in keys if k in first]
    failing_only = [t for t in tg if t[1] not in first and t[1] in rv.obs.first_failing]
    uncoverable = [t for t in tg if t[1] not in first and t[1] not in rv.obs.first_failing]
    want = set(coverable)
    depth = rv.space.depth
    # longest witnesses first; ties by the order of the targets (deterministic)
    order = sorted(coverable, key=lambda k: (-depth(first[k][0]), keys.index(k)))
    covered: set = set()
    paths = []
    for k in order:
        if k in covered:
            continue
        sid, picks, tid = first[k]
        hits = path_targets(rv, sid, picks, tid)
        hits |= {a for a, w in alias.items() if w in hits}
        hits &= want
        hits.add(k)
        covered |= hits
        paths.append(TestPath(sid, picks, tid, hits))
    return paths, tg, uncoverable, failing_only


def path_targets(rv, sid, picks, tid) -> set:
    """The targets the steps of the path to (sid, then picks) cover, replayed with the rule hook on."""
    from .observe import Observations
    from .space import Configuration, run_step
    ex = rv.space.explorer
    path = ex.path_to(sid)
    steps = [(ex.via[path[i + 1]], path[i + 1]) for i in range(len(path) - 1)] + [(picks, tid)]
    obs = Observations()
    cur = ex.state(path[0])
    m, tracer = rv.space.machine, rv.space.tracer
    for pk, dst in steps:
        events, clashes, err, nxt, mon = run_step(m, tracer, cur, ScriptChooser(pk))
        obs(Configuration(0, pk, [], events, clashes, err, dst, mon))
        cur = ex.state(dst)
    return set(obs.first)


def trace_of(rv, p: TestPath):
    from ..report.trace import Trace, trace_steps
    ex = rv.space.explorer
    path = ex.path_to(p.sid)
    replayed = ex.replay(path, p.picks, p.tid)
    steps = trace_steps([(r[0], r[1], r[2], r[4] if len(r) > 5 else None, r[5] if len(r) > 5 else None)
                         for r in replayed])
    return Trace(None, steps, "step", "")


class _Goal:
    def __init__(self, name):
        self.name = name
        self.kind = "testgen"
        self.span = None
        self.source = "testgen"
        self.body = None


def scenario_text(rv, p: TestPath, number: int, spec_path: str, out_path: str | None, labels: dict) -> str:
    from .. import __version__
    from ..report.avalla_export import trace_scenario
    name = f"{rv.spec.name}_test{number}"
    tr = trace_of(rv, p)
    text = trace_scenario(rv.space.machine, tr, spec_path=spec_path, out_path=out_path, prop=_Goal(name), name=name)
    lines = text.split("\n")
    start = next(i for i, ln in enumerate(lines) if ln.startswith("scenario "))
    body = lines[start:]
    # drop the closing comment about a violation: a test ends after its last step's checks
    while body and (body[-1] == "" or body[-1].startswith("//")):
        body.pop()
    nsteps = len(tr.steps) - 1
    head = [f"// Generated by asmcheck {__version__} (testgen) for {rv.spec.name}: test {number}, "
            f"{nsteps} step{'s' if nsteps != 1 else ''}, a shortest path from the initial state.",
            "// set: the monitored values each step reads; pick: the choices of its choose rules;",
            "// check: the locations the step changed. Every check passes.",
            f"// It covers {len(p.covers)} target{'s' if len(p.covers) != 1 else ''}:"]
    for lab in sorted(labels[k] for k in p.covers if k in labels):
        head.append(f"//   {lab}")
    return "\n".join(head + body) + "\n"


def target_label(t) -> str:
    crit, key, node, label = t
    sp = node.span
    return f"{Path(sp.path).name}:{sp.line}:{sp.col} {crit} {label}"


def testgen(path: str, criterion: str, out_dir: str | None, *, options=None, max_states=None, max_seconds=None):
    """Explore, choose the paths, write the scenarios; the JSON-able summary."""
    from .advise import Review
    from .common import load_spec
    from .coverage import Sources
    spec = load_spec(path)
    rv = Review(spec, options, max_states=max_states, max_seconds=max_seconds, conditions=criterion == "mcdc")
    paths, tg, uncoverable, failing_only = generate(rv, criterion)
    first = dict(rv.obs.first)
    if criterion == "mcdc":
        _, alias = mcdc_targets(rv)
        first.update({k: first[w] for k, w in alias.items()})
    labels = {t[1]: target_label(t) for t in tg}
    src = Sources()
    written = []
    scen = []
    for i, p in enumerate(paths, start=1):
        out_path = os.path.join(out_dir, f"{rv.spec.name}_test{i}.avalla") if out_dir else None
        text = scenario_text(rv, p, i, path, out_path, labels)
        if out_path:
            os.makedirs(out_dir, exist_ok=True)
            Path(out_path).write_text(text, encoding="utf-8")
            written.append(out_path)
        steps = len(rv.space.explorer.path_to(p.sid))
        scen.append({"name": f"{rv.spec.name}_test{i}", "file": out_path, "steps": steps,
                     "covers": sorted(labels[k] for k in p.covers if k in labels), "text": text})
    per_target = sum(len(rv.space.explorer.path_to(first[k][0])) for k in {t[1] for t in tg} if k in first)
    coverable = sum(1 for t in tg if t[1] in first)
    return {"spec": rv.spec.name, "path": path, "criterion": criterion, "states": rv.space.states,
            "incomplete": rv.incomplete, "targets": len(tg), "coverable": coverable,
            "scenarios": scen, "total_steps": sum(s["steps"] for s in scen),
            "one_per_target": {"scenarios": coverable, "total_steps": per_target},
            "uncoverable": [dict(target=labels[t[1]], text=src.excerpt(t[2].span)) for t in uncoverable],
            "failing_only": [dict(target=labels[t[1]], text=src.excerpt(t[2].span)) for t in failing_only],
            "written": written}


def add_testgen_options(p) -> None:
    p.add_argument("file")
    p.add_argument("--criterion", choices=CRITERIA, default="branch")
    p.add_argument("--out", default=None, help="folder for the scenarios (default: print a summary only)")
    p.add_argument("--format", choices=["text", "json", "itf"], default="text")
    p.add_argument("--max-states", type=int, default=200_000)
    p.add_argument("--max-seconds", type=float, default=None)
    from .common import add_domain_options
    add_domain_options(p)


def run_testgen(args) -> int:
    import json
    import sys
    from ..errors import AsmError
    from .common import machine_options
    try:
        options = machine_options(args)
    except ValueError as e:
        sys.stderr.write(f"asmcheck testgen: {e}\n")
        return 2
    if getattr(args, "import_path", None):
        from .common import use_import_path
        use_import_path(args.import_path)
    try:
        doc = testgen(args.file, args.criterion, args.out, options=options, max_states=args.max_states,
                      max_seconds=args.max_seconds)
    except AsmError as e:
        sys.stderr.write(e.render() + "\n")
        return 2
    if args.format == "json":
        sys.stdout.write(json.dumps({k: v for k, v in doc.items()}, indent=1) + "\n")
    elif args.format == "itf":
        sys.stdout.write(json.dumps(testgen_itf(args.file, args.criterion, args.max_states, options), indent=1) + "\n")
    else:
        n = len(doc["scenarios"])
        lines = [f"testgen {doc['spec']} ({doc['criterion']}): {doc['coverable']} of {doc['targets']} targets "
                 f"coverable, covered by {n} scenario{'s' if n != 1 else ''} of {doc['total_steps']} steps in all "
                 f"(one scenario per target: {doc['one_per_target']['scenarios']} scenarios, "
                 f"{doc['one_per_target']['total_steps']} steps)"]
        if doc["incomplete"]:
            lines.append(f"exploration incomplete ({doc['incomplete']}): more targets may be coverable")
        for s in doc["scenarios"]:
            lines.append(f"  {s['file'] or s['name']}: {s['steps']} steps, {len(s['covers'])} targets")
        if doc["uncoverable"] and doc["incomplete"]:
            lines.append(f"not covered in the states explored (dead code, or beyond the limit): "
                         f"{len(doc['uncoverable'])}")
            for u in doc["uncoverable"]:
                lines.append(f"  {u['target']}: {u['text']}")
        elif doc["uncoverable"]:
            lines.append(f"uncoverable (dead code): {len(doc['uncoverable'])}")
            for u in doc["uncoverable"]:
                lines.append(f"  {u['target']}: {u['text']}")
        if doc["failing_only"]:
            lines.append(f"covered only by failing steps: {len(doc['failing_only'])}")
            for u in doc["failing_only"]:
                lines.append(f"  {u['target']}: {u['text']}")
        sys.stdout.write("\n".join(lines) + "\n")
    return 3 if doc["incomplete"] else 0


def testgen_itf(path: str, criterion: str = "branch", max_states=None, options=None) -> list[dict]:
    """The ITF of each path testgen chooses."""
    from ..report.gate import step_inputs
    from .advise import Review
    from .common import load_spec
    from .itf import trace_itf
    rv = Review(load_spec(path), options, max_states=max_states, conditions=criterion == "mcdc")
    paths, *_ = generate(rv, criterion)
    out = []
    for i, p in enumerate(paths, start=1):
        tr = trace_of(rv, p)
        out.append(trace_itf(rv.space.machine, tr, source=path, inputs=step_inputs(rv.space.machine, tr),
                             description=f"{rv.spec.name}_test{i}: test {i} of testgen ({criterion})"))
    return out
