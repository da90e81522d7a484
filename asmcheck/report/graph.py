"""The explored state graph for people: DOT or GraphML.

Each edge is labelled as a trace names its step (the rule that chooses what, the
monitored values read: ``r_main chooses $l = GREEN; reads go = false``), found by running the step again with its
recorded choices; the states and steps of counterexamples are highlighted.  GraphML is
written by hand so that it is valid: ``boolean`` values are ``true``/``false`` and every
edge has its own id.
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from ..errors import UsageError
from ..semantics.choice import ScriptChooser
from ..semantics.printer import state_lines
from .describe import Choice, ChooseIndex, StepRecord, choose_records, flat_choices, read_records
from .trace import step_header

# a graph over this many states is written, with a warning that few people can read it
READABLE_STATES = 500


def edge_label(machine, state: dict, picks, chooses=None) -> str:
    """The step from ``state`` taken with ``picks`` as a trace's step line names it, without its
    number: ``r_main chooses $l = GREEN; reads go = false``."""
    from ..semantics.values import show
    if chooses is None:
        chooses = ChooseIndex(machine.spec)
    ch = ScriptChooser(picks)
    try:
        mon = dict(machine.step(state, ch)[2].mon)
    except Exception:        # a step that fails: its choices are those made before it failed
        reads = [Choice("monitored", f"{c.label} = {show(c.value)}") for c in flat_choices(ch.log)
                 if c.kind == "monitored"]
        rec = StepRecord(1, chooses.main, choose_records(ch.log, chooses) + reads, {}, {})
        return step_header(rec)[len("step 1: "):]
    return step_label(machine, ch.log, mon, chooses)


def step_label(machine, log, mon: dict, chooses) -> str:
    """:func:`edge_label` of a step already made: its choices ``log`` and the monitored values
    ``mon`` it read."""
    rec = StepRecord(1, chooses.main, choose_records(log, chooses) + read_records(machine, mon), {}, {})
    return step_header(rec)[len("step 1: "):]


def state_graph(explorer, highlight=None):
    """A networkx MultiDiGraph of the explored states: nodes carry ``label`` (the state),
    ``depth``, ``initial`` and ``counterexample``; edges ``choices`` (text), ``id`` and
    ``counterexample``.  ``highlight``: (state ids, (source, target) pairs) to mark."""
    import networkx as nx

    states, steps = highlight or (set(), set())
    g = nx.MultiDiGraph()
    m = explorer.m
    chooses = ChooseIndex(m.spec)
    depth_of, parent = explorer.depth_of, explorer.parent
    for sid in range(explorer.n_states):
        st = explorer.state(sid)
        g.add_node(sid, label="\n".join(state_lines(m, st, sorted(st, key=_function_order))), depth=int(depth_of[sid]),
                   initial=parent[sid] == -1, counterexample=sid in states)
    # an engine whose edge arrays hold each pair of states once gives every step apart
    every = getattr(explorer, "graph_edges", None)
    # the steps as the enumeration made them (choices log, monitored values): not run again
    made = getattr(explorer, "graph_made", None) if every is not None else None
    made = made() if made is not None else None
    labels: dict = {}
    for i, (src, dst, picks) in enumerate(every() if every is not None else explorer.edges):
        if made is not None:
            text = labels.get(id(made[i]))
            if text is None:
                text = labels[id(made[i])] = step_label(m, made[i][0], made[i][1], chooses)
        else:
            text = edge_label(m, explorer.state(src), picks, chooses)
        g.add_edge(src, dst, key=f"e{i}", choices=text, counterexample=(src, dst) in steps)
    return g


def _function_order(key) -> int:
    """The number of a location's function: two functions of one name (from two modules) print
    their locations in this order, whatever the order of the state's entries."""
    if type(key) is int:
        return key
    return key[0] if type(key[0]) is int else -1


def highlight_of(explorer, violations) -> tuple[set, set]:
    """The states and steps on the shortest paths to the given violations."""
    states, steps = set(), set()
    for v in violations:
        end = v.source if v.source >= 0 else v.state
        path = explorer.path_to(end)
        if v.source >= 0:
            path = path + [v.state]
        states.update(path)
        steps.update(zip(path, path[1:]))
    return states, steps


def _dot_text(s: str) -> str:
    return s.replace("\\", "\\\\").replace('"', '\\"')


def write_graph(explorer, path: str, highlight=None) -> int:
    """Write the graph (``.dot``/``.gv`` or ``.graphml``); returns the number of states."""
    suffix = Path(path).suffix.lower()
    if suffix not in (".graphml", ".dot", ".gv"):
        raise UsageError(f"--graph: write a .dot or .graphml file, not {path!r}")
    g = state_graph(explorer, highlight)
    if suffix == ".graphml":
        Path(path).write_text(graphml(g), encoding="utf-8")
        return g.number_of_nodes()
    lines = ["digraph states {", "  node [shape=box, fontname=monospace];"]
    for n, data in sorted(g.nodes(data=True)):
        label = _dot_text(data["label"]).replace("\n", "\\l") + "\\l"
        extra = ", penwidth=2" if data.get("initial") else ""
        if data.get("counterexample"):
            extra += ", color=red, fontcolor=red"
        lines.append(f'  s{n} [label="{label}"{extra}];')
    edges = sorted(g.edges(data=True), key=lambda e: (e[0], e[1], e[2]["choices"]))
    for u, v, data in edges:
        extra = ", color=red, fontcolor=red, penwidth=2" if data.get("counterexample") else ""
        lines.append(f'  s{u} -> s{v} [label="{_dot_text(data["choices"])}"{extra}];')
    lines.append("}")
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
    return g.number_of_nodes()


def graphml(g) -> str:
    """GraphML 1.0 of the state graph (valid against the schema)."""
    ns = "http://graphml.graphdrawing.org/xmlns"
    root = ET.Element("graphml", {"xmlns": ns})
    keys = [("label", "node", "string"), ("depth", "node", "int"), ("initial", "node", "boolean"),
            ("counterexample", "node", "boolean"), ("choices", "edge", "string"),
            ("counterexample_edge", "edge", "boolean")]
    for name, where, typ in keys:
        attr = "counterexample" if name == "counterexample_edge" else name
        ET.SubElement(root, "key", {"id": f"{where[0]}_{name}", "for": where, "attr.name": attr, "attr.type": typ})
    graph = ET.SubElement(root, "graph", {"id": "states", "edgedefault": "directed"})

    def data(parent, key, value):
        el = ET.SubElement(parent, "data", {"key": key})
        el.text = ("true" if value else "false") if isinstance(value, bool) else str(value)

    for n, d in sorted(g.nodes(data=True)):
        node = ET.SubElement(graph, "node", {"id": f"s{n}"})
        data(node, "n_label", d["label"])
        data(node, "n_depth", d["depth"])
        data(node, "n_initial", bool(d["initial"]))
        data(node, "n_counterexample", bool(d["counterexample"]))
    for u, v, k, d in sorted(g.edges(keys=True, data=True), key=lambda e: int(e[2][1:])):
        edge = ET.SubElement(graph, "edge", {"id": k, "source": f"s{u}", "target": f"s{v}"})
        data(edge, "e_choices", d["choices"])
        data(edge, "e_counterexample_edge", bool(d["counterexample"]))
    ET.indent(root, space="  ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
