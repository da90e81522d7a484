"""Coverage of a spec's rules: over the whole explored state space (``explore --coverage``) or
over a set of Avalla scenarios (``scenario --coverage``).

Targets (each a source position):

* ``rule``: every rule occurrence of the rule tree unfolded from the main rule (a macro body is
  one occurrence for all its call sites) fired at least once;
* ``branch``: each ``if`` branch taken (``then``; ``else``, also when the ``if`` has no ``else``:
  the guard was false), each ``switch`` case taken (and its ``otherwise``), each ``choose`` with
  a candidate and without one;
* ``update``: each update rule executed (its location and value computed).

Over the explored state space a target that is not covered is *uncoverable*: no reachable
configuration reaches it (dead code, or a guard no reachable state satisfies).
"""
from __future__ import annotations

import html
from collections import defaultdict
from pathlib import Path

from ..semantics import ir
from .common import Sources, rule_kind

CRITERIA = ("rule", "branch", "update")


def targets(unf) -> list[tuple]:
    """Every target of the unfolded rule tree, in a fixed order: (criterion, key, node, label)."""
    out = []
    for n in unf.nodes:
        out.append(("rule", ("rule", id(n)), n, "fired"))
        if isinstance(n, ir.If):
            out.append(("branch", ("branch", id(n), "then"), n, "then"))
            out.append(("branch", ("branch", id(n), "else"), n, "else" if n.other is not None else
                        "else (guard false, no else)"))
        elif isinstance(n, ir.SwitchRule):
            for i, (c, _) in enumerate(n.cases):
                out.append(("branch", ("branch", id(n), i), n, f"case {i + 1}"))
            if n.other is not None:
                out.append(("branch", ("branch", id(n), "otherwise"), n, "otherwise"))
        elif isinstance(n, ir.Update):
            out.append(("update", ("update", id(n)), n, "executed"))
    return out


def _parent_map(unf) -> dict:
    """id(node) -> (the enclosing node, the branch label when it is an if/switch branch)."""
    parent: dict = {}

    def put(child, encl, label=None):
        if child is not None and id(child) not in parent:
            parent[id(child)] = (encl, label)

    progs = None
    for r in unf.nodes:
        if isinstance(r, ir.If):
            put(r.then, r, "then")
            put(r.other, r, "else")
        elif isinstance(r, ir.SwitchRule):
            for i, (_, b) in enumerate(r.cases):
                put(b, r, i)
            put(r.other, r, "otherwise")
        elif isinstance(r, ir.CallRule):
            put(r.rule.body, r)
        elif isinstance(r, ir.TermCall):
            if progs is None:
                progs = unf._rule_values()
            for rd in progs:
                put(rd.body, r)
        else:
            for v in vars(r).values():
                if isinstance(v, ir.Rule):
                    put(v, r)
                elif isinstance(v, (list, tuple)):
                    for x in v:
                        if isinstance(x, ir.Rule):
                            put(x, r)
    return parent


def coverage(unf, obs, sources: Sources | None = None, *, whole_space: bool = True, depth_of=None) -> dict:
    """The coverage document: per criterion the totals and every target with its status."""
    sources = sources or Sources()
    parents = _parent_map(unf)
    items = []
    totals = {c: [0, 0] for c in CRITERIA}
    for crit, key, node, label in targets(unf):
        hit = obs.first.get(key) or obs.first_failing.get(key)
        totals[crit][0] += 1
        if hit is not None:
            totals[crit][1] += 1
        sp = node.span
        it = {"criterion": crit, "rule": rule_kind(node), "target": label, "path": Path(sp.path).name,
              "file": sp.path, "line": sp.line, "column": sp.col, "text": sources.excerpt(sp),
              "covered": hit is not None}
        if hit is not None and depth_of is not None:
            it["depth"] = depth_of(hit[0]) + 1
        if hit is None:
            it["why"] = _why(node, key, obs, parents, sources, whole_space)
        items.append(it)
    items.sort(key=lambda i: (i["file"], i["line"], i["column"], CRITERIA.index(i["criterion"])))
    doc = {"criteria": {c: {"targets": t, "covered": k, "percent": round(100.0 * k / t, 1) if t else 100.0}
                        for c, (t, k) in totals.items()},
           "targets": items}
    reach = [i for i in items if i["criterion"] == "rule"]
    reachable = [i for i in reach if i["covered"]]
    doc["reachable_rules"] = len(reachable)
    return doc


def _why(node, key, obs, parents, sources, whole_space) -> str:
    acts = obs.node_configs.get(id(node), 0)
    # (whole_space "explored": a limit stopped the exploration, the configurations are those explored)
    run = "explored configuration" if whole_space == "explored" else "reachable configuration" if whole_space \
        else "scenario step"
    a_run = ("an " if run[0] in "aeiou" else "a ") + run
    if key[0] in ("rule", "update") and not acts:
        p = parents.get(id(node))
        seen = set()
        while p is not None and id(p[0]) not in seen:
            seen.add(id(p[0]))
            encl, label = p
            if label is not None and obs.node_configs.get(id(encl), 0):
                cond = encl.cond if isinstance(encl, ir.If) else getattr(encl, "subject", None)
                ctext = sources.excerpt(cond.span) if cond is not None else ""
                if isinstance(encl, ir.If):
                    want = "true" if label == "then" else "false"
                    return (f"the enclosing if (line {encl.span.line}) never has its guard {ctext} {want} "
                            f"in {a_run}")
                return f"the enclosing switch (line {encl.span.line}) never takes this case in {a_run}"
            if label is None and isinstance(encl, (ir.Choose, ir.Forall)) and obs.node_configs.get(id(encl), 0):
                return (f"the enclosing {rule_kind(encl)} (line {encl.span.line}) never finds an element "
                        f"satisfying its condition in {a_run}")
            p = parents.get(id(encl))
        return f"no {run} runs the rule that holds it"
    if key[0] == "update":
        return f"it runs, but its location or value cannot be computed (a step error) in every {run}"
    if not acts:
        return f"the {rule_kind(node)} itself is never reached"
    if isinstance(node, ir.If):
        ctext = sources.excerpt(node.cond.span)
        return (f"the guard {ctext} is " + ("false" if key[2] == "then" else "true") +
                f" in every {run} that reaches it")
    if isinstance(node, ir.SwitchRule):
        return f"the subject {sources.excerpt(node.subject.span)} never matches this case in {a_run}"
    return f"not taken in any {run}"


def coverage_text(doc: dict, title: str) -> list[str]:
    lines = [f"coverage of {title}:"]
    for c, t in doc["criteria"].items():
        lines.append(f"  {c}: {t['covered']} of {t['targets']} ({t['percent']} %)")
    miss = [i for i in doc["targets"] if not i["covered"]]
    if miss:
        lines.append(f"not covered ({len(miss)}):")
        for i in miss:
            lines.append(f"  {i['path']}:{i['line']}:{i['column']}  {i['criterion']} {i['rule']} {i['target']}: "
                         f"{i['text']}")
            lines.append(f"      {i['why']}")
    return lines


def coverage_html(doc: dict, title: str, sources: Sources | None = None) -> str:
    """The spec's source with each line coloured by the coverage of the targets that start on it."""
    sources = sources or Sources()
    per_file: dict = defaultdict(lambda: defaultdict(list))
    for i in doc["targets"]:
        per_file[i["file"]][i["line"]].append(i)
    out = ["<!DOCTYPE html>", "<html><head><meta charset='utf-8'>",
           f"<title>coverage of {html.escape(title)}</title>",
           "<style>body{font-family:sans-serif} pre{margin:0} .l{display:block;white-space:pre;"
           "font-family:monospace} .full{background:#d4f7d4} .part{background:#fbf3c0} .none{background:#f9d0d0}"
           " .n{color:#888;display:inline-block;width:4em;text-align:right;margin-right:1em}</style></head><body>",
           f"<h1>Coverage of {html.escape(title)}</h1><ul>"]
    for c, t in doc["criteria"].items():
        out.append(f"<li>{c}: {t['covered']} of {t['targets']} ({t['percent']} %)</li>")
    out.append("</ul><p><span class='full'>all targets on the line covered</span> "
               "<span class='part'>some covered</span> <span class='none'>none covered</span></p>")
    for f in sorted(per_file):
        out.append(f"<h2>{html.escape(Path(f).name)}</h2><pre>")
        for n, line in enumerate(sources.lines(f), start=1):
            ts = per_file[f].get(n)
            cls = ""
            tip = ""
            if ts:
                k = sum(1 for t in ts if t["covered"])
                cls = "full" if k == len(ts) else "none" if k == 0 else "part"
                tip = "; ".join(f"{t['criterion']} {t['target']}: " + ("covered" if t["covered"] else t["why"])
                                for t in ts)
            attr = f" class='l {cls}' title='{html.escape(tip, quote=True)}'" if cls else " class='l'"
            out.append(f"<span{attr}><span class='n'>{n}</span>{html.escape(line)}</span>")
        out.append("</pre>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"


def explore_coverage(path: str, options=None, *, max_states=None, max_seconds=None):
    """(review, coverage document) over the whole explored state space."""
    from .advise import Review
    from .common import load_spec
    rv = Review(load_spec(path), options, max_states=max_states, max_seconds=max_seconds)
    doc = coverage(rv.unf, rv.obs, rv.src, whole_space="explored" if rv.incomplete else True,
                   depth_of=rv.space.depth)
    doc.update({"spec": rv.spec.name, "path": path, "states": rv.space.states, "transitions": rv.space.transitions,
                "configurations": rv.obs.configs, "incomplete": rv.incomplete})
    return rv, doc


def _node_key(n):
    sp = n.span
    return (type(n).__name__, getattr(n, "kind", None), sp.path, sp.line, sp.col, sp.end_line, sp.end_col)


def scenario_coverage(paths: list[str], max_until: int = 1000) -> tuple[dict, list]:
    """Coverage of the spec by the scenarios ``paths`` (all loading the same spec): (document, outcomes)."""
    from ..avalla.runner import Scenario
    from .observe import Observations
    from .space import Configuration, review_machine
    from .static import Unfolding
    obs = Observations()
    outcomes = []
    spec = unf = None
    canon: dict = {}
    for p in paths:
        sc = Scenario(p, max_until)
        machine, tracer = review_machine(sc.spec, {}, lenient=False)
        sc.machine = machine
        tracer.reset()
        outcomes.append(sc.run())
        if unf is None:
            spec = sc.spec
            unf = Unfolding(machine)
            canon = {_node_key(n): n for n in unf.nodes}
        # each scenario loads the spec again: its rule occurrences are matched by position
        for ev in tracer.events:
            ev.node = canon.get(_node_key(ev.node), ev.node)
        obs(Configuration(0, (), [], tracer.events, [], None, None, {}))
    doc = coverage(unf, obs, whole_space=False) if unf is not None else {"criteria": {}, "targets": []}
    doc.update({"spec": spec.name if spec else None, "scenarios": paths})
    return doc, outcomes


def add_coverage_options(p) -> None:
    p.add_argument("--coverage", nargs="?", const="-", default=None, metavar="HTML",
                   help="report rule, branch and update coverage (with a file name: also the HTML view)")


def cli_coverage(path: str, target: str, options=None, *, fmt: str = "text", max_states=None, max_seconds=None):
    """For ``explore --coverage[=OUT.html]``: the coverage over the explored state space, as text
    lines (or the JSON document), and the HTML view written to ``target`` unless it is ``-``."""
    rv, doc = explore_coverage(path, options, max_states=max_states, max_seconds=max_seconds)
    title = f"{doc['spec']} over {doc['states']} states" + (
        f" (exploration incomplete: {doc['incomplete']})" if doc.get("incomplete") else "")
    if target and target != "-":
        from pathlib import Path
        Path(target).write_text(coverage_html(doc, title, rv.src), encoding="utf-8")
    return doc if fmt == "json" else coverage_text(doc, title)


def explore_coverage_for(args, fmt: str = "text"):
    """``explore --coverage``: :func:`cli_coverage` with the command's options (``--monitored``,
    ``--int-range``, ``-I``, the state and time limits)."""
    from .common import machine_options, use_import_path
    if getattr(args, "import_path", None):
        use_import_path(args.import_path)
    try:
        options = machine_options(args)
    except ValueError as e:
        from ..errors import UsageError
        raise UsageError(str(e)) from None
    return cli_coverage(args.file, args.coverage, options, fmt=fmt, max_states=getattr(args, "max_states", None),
                        max_seconds=getattr(args, "max_seconds", None))


def cli_scenario_coverage(paths: list[str], target: str, *, fmt: str = "text", max_until: int = 1000):
    """For ``scenario --coverage[=OUT.html]``: the coverage of the spec by the scenarios."""
    doc, _ = scenario_coverage(paths, max_until)
    title = f"{doc['spec']} by {len(paths)} scenario{'s' if len(paths) != 1 else ''}"
    if target and target != "-":
        from pathlib import Path
        Path(target).write_text(coverage_html(doc, title), encoding="utf-8")
    return doc if fmt == "json" else coverage_text(doc, title)
