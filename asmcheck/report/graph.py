"""The explored state graph as a networkx graph, written as DOT or GraphML."""
from __future__ import annotations

from pathlib import Path

from ..errors import UsageError


def state_graph(explorer):
    import networkx as nx
    from ..semantics.printer import state_lines

    g = nx.MultiDiGraph()
    m = explorer.m
    for sid in range(len(explorer.frozen)):
        st = explorer.state(sid)
        g.add_node(sid, label="\n".join(state_lines(m, st)), depth=int(explorer.depth_of[sid]),
                   initial=explorer.parent[sid] == -1)
    for src, dst, picks in explorer.edges:
        g.add_edge(src, dst, choices=",".join(map(str, picks)))
    return g


def write_graph(explorer, path: str) -> None:
    import networkx as nx

    g = state_graph(explorer)
    suffix = Path(path).suffix.lower()
    if suffix == ".graphml":
        nx.write_graphml(g, path)
    elif suffix in (".dot", ".gv"):
        lines = ["digraph states {", "  node [shape=box, fontname=monospace];"]
        for n, data in sorted(g.nodes(data=True)):
            label = data["label"].replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\l") + "\\l"
            extra = ", penwidth=2" if data.get("initial") else ""
            lines.append(f'  s{n} [label="{label}"{extra}];')
        for u, v, data in sorted(g.edges(data=True), key=lambda e: (e[0], e[1], e[2]["choices"])):
            lines.append(f'  s{u} -> s{v} [label="{data["choices"]}"];')
        lines.append("}")
        Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
    else:
        raise UsageError(f"--graph: write a .dot or .graphml file, not {path!r}")
