"""One trace style everywhere, continued: ``asmcheck bmc`` and ``asmcheck simulate --swarm``
show a violation as ``asmcheck explore`` does (the head, the summary, the ``formula:`` line, a
step that fails with its inputs); ``--graph`` labels each edge as a trace names its step and
marks the counterexample; the JSON violations of explore, bmc and swarm carry the property's
formula and location, as ``check --json`` rows do."""
from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from asmcheck.cli import main

# --graph, bmc and the swarm run the Python machine; explore's JSON is pinned on it too
pytestmark = pytest.mark.engines("python")

ROOT = Path(__file__).resolve().parent.parent

GRAPH = """asm Graph
import StandardLibrary
signature:
	enum domain Light = {RED | GREEN}
	monitored go: Boolean
	controlled light: Light
	controlled c: Integer
definitions:
	invariant inv_c over c: c < 3
	main rule r_main = if go then par light := GREEN c := (c + 1) mod 4 endpar
		else choose $l in Light with true do light := $l endif
default init s0:
	function light = RED
	function c = 0
"""

SMALL = """asm Small
import StandardLibrary
signature:
	enum domain Light = {RED | GREEN}
	monitored go: Boolean
	controlled light: Light
definitions:
	invariant inv_red over light: light = RED
	main rule r_main = if go then choose $l in Light with true do light := $l endif
default init s0:
	function light = RED
"""

CLASH = """asm Clash
import StandardLibrary
signature:
	monitored go: Boolean
	controlled c: Integer
definitions:
	main rule r_main = if go then par c := 1 c := 2 endpar else c := 0 endif
default init s0:
	function c = 0
"""

# the trace of inv_c, as explore, bmc and the swarm all show it
INV_C = [
    "  formula: c < 3",
    "  state 0 (initial)",
    "      c = 0",
    "      light = RED",
    "  step 1: r_main; reads go = true",
    "      c = 1",
    "      light = GREEN",
    "  step 2: r_main; reads go = true",
    "      c = 2",
    "  step 3: r_main; reads go = true  <- violates the property",
    "      c = 3",
]

# the step that fails, as explore, bmc and the swarm all show it
CLASH_TRACE = [
    "  state 0 (initial)",
    "      c = 0",
    "  step 1: r_main; reads go = true  <- fails (the step cannot be made)",
]


@pytest.fixture
def specs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for name, text in (("Graph", GRAPH), ("Small", SMALL), ("Clash", CLASH)):
        (tmp_path / f"{name}.asm").write_text(text)
    return tmp_path


def run(capsys, *argv):
    code = main(list(argv))
    return code, capsys.readouterr().out


def violation_block(out: str) -> list[str]:
    """The lines from the first violation's head to the verdict."""
    lines = out.splitlines()
    start = lines.index("") + 1
    return lines[start:-1]


# ----------------------------------------------------------------- bmc
def test_bmc_shows_a_violation_as_explore_does(specs, capsys):
    code, ex = run(capsys, "explore", "Graph.asm")
    assert code == 1
    code, out = run(capsys, "bmc", "Graph.asm", "-k", "4", "--int-range", "0..4")
    assert code == 1
    lines = out.splitlines()
    assert re.fullmatch(r"Graph\.asm: bounded model checking to depth 4 \(z3\), \d+\.\d\d s", lines[0])
    assert lines[1:] == [
        "  inv_c                                    violated at depth 3",
        "  error                                    holds-to-depth",
        "",
        "inv_c (Graph.asm:9:2) is violated -- shortest counterexample, 3 steps:",
        *INV_C,
        "verdict: violated",
    ]
    assert violation_block(out) == violation_block(ex)
    assert "shortest trace" not in out and "replayed" not in out


def test_bmc_shows_a_step_that_fails_as_explore_does(specs, capsys):
    code, ex = run(capsys, "explore", "Clash.asm")
    assert code == 1
    code, out = run(capsys, "bmc", "Clash.asm", "-k", "3", "--int-range", "0..3")
    assert code == 1
    head = ("a step fails (Clash.asm:7:43): inconsistent update of c: 1 and 2 -- shortest counterexample, "
            "0 steps, then step 1 fails:")
    assert out.splitlines()[1:] == [
        "  error                                    violated at depth 0",
        "",
        head,
        *CLASH_TRACE,
        "verdict: violated",
    ]
    assert violation_block(out) == violation_block(ex) == [head, *CLASH_TRACE]


def test_bmc_json_carries_formula_location_and_the_failing_step(specs, capsys):
    code, out = run(capsys, "bmc", "Graph.asm", "-k", "4", "--int-range", "0..4", "--format", "json")
    assert code == 1
    (v,) = json.loads(out)["violations"]
    assert {k: v[k] for k in ("property", "kind", "message", "formula", "location", "depth")} == {
        "property": "inv_c", "kind": "state", "message": "", "formula": "c < 3",
        "location": {"path": "Graph.asm", "line": 9, "column": 2, "end_column": 17}, "depth": 3}
    code, out = run(capsys, "bmc", "Clash.asm", "-k", "3", "--int-range", "0..3", "--format", "json")
    (v,) = json.loads(out)["violations"]
    assert v["formula"] == "" and v["location"] == {"path": "Clash.asm", "line": 7, "column": 43}
    assert v["failing_step"] == {"step": 1, "choices": [{"kind": "monitored", "at": "go", "value": True}]}


# ----------------------------------------------------------------- simulate --swarm
def test_swarm_shows_a_violation_as_explore_does(specs, capsys):
    code, out = run(capsys, "simulate", "Graph.asm", "--swarm", "4", "--depth", "6", "--swarm-workers", "1")
    assert code == 1
    lines = out.splitlines()
    assert lines[1:] == [
        "  rule coverage: 1 of 1 rules made an update",
        "  inv_c                                    violated (shortest found: 3 steps, walk 3)",
        "",
        "inv_c (Graph.asm:9:2) is violated -- shortest counterexample found (walk 3), 3 steps:",
        *INV_C,
        "verdict: violated",
    ]
    code, out = run(capsys, "simulate", "Clash.asm", "--swarm", "2", "--depth", "3", "--swarm-workers", "1")
    assert code == 1
    assert violation_block(out) == [
        "a step fails (Clash.asm:7:43): inconsistent update of c: 1 and 2 -- shortest counterexample found "
        "(walk 0), 0 steps, then step 1 fails:", *CLASH_TRACE]


def test_swarm_json_carries_formula_and_location(specs, capsys):
    code, out = run(capsys, "simulate", "Graph.asm", "--swarm", "4", "--depth", "6", "--swarm-workers", "1",
                    "--format", "json")
    assert code == 1
    (v,) = json.loads(out)["violations"]
    assert (v["property"], v["walk"], v["formula"], v["location"]) == (
        "inv_c", 3, "c < 3", {"path": "Graph.asm", "line": 9, "column": 2, "end_column": 17})
    code, out = run(capsys, "simulate", "Clash.asm", "--swarm", "2", "--depth", "3", "--swarm-workers", "1",
                    "--format", "json")
    (v,) = json.loads(out)["violations"]
    assert (v["formula"], v["location"]) == ("", {"path": "Clash.asm", "line": 7, "column": 43})
    assert v["failing_step"] == {"step": 1, "choices": [{"kind": "monitored", "at": "go", "value": True}]}


# ----------------------------------------------------------------- explore --format json
def test_explore_json_violations_carry_formula_and_location(specs, capsys):
    import jsonschema
    schema = json.loads((ROOT / "docs" / "trace.schema.json").read_text())
    tv = jsonschema.validators.validator_for(schema)(schema)
    code, out = run(capsys, "explore", "Graph.asm", "--format", "json")
    assert code == 1
    (v,) = json.loads(out)["violations"]
    assert list(v)[:5] == ["property", "kind", "message", "formula", "location"]
    assert (v["formula"], v["location"]) == ("c < 3", {"path": "Graph.asm", "line": 9, "column": 2, "end_column": 17})
    tv.validate(v)
    code, out = run(capsys, "explore", "Clash.asm", "--format", "json")
    (v,) = json.loads(out)["violations"]
    assert (v["formula"], v["location"]) == ("", {"path": "Clash.asm", "line": 7, "column": 43})
    tv.validate(v)
    with pytest.raises(jsonschema.ValidationError):
        tv.validate({**v, "location": {"path": "Clash.asm", "line": 0, "column": 43}})


def test_explore_json_temporal_violations_carry_formula_and_location(specs, capsys):
    import jsonschema
    schema = json.loads((ROOT / "docs" / "trace.schema.json").read_text())
    tv = jsonschema.validators.validator_for(schema)(schema)
    text = SMALL.replace("\tmain rule", "\tLTLSPEC ltlSpec_red: g(light = RED)\n\tmain rule")
    (specs / "Ltl.asm").write_text(text.replace("asm Small", "asm Ltl").replace("StandardLibrary", "StandardLibrary\nimport LTLLibrary"))
    code, out = run(capsys, "explore", "Ltl.asm", "--format", "json")
    assert code == 1
    ltl = next(v for v in json.loads(out)["violations"] if v["property"] == "ltlSpec_red")
    assert (ltl["formula"], ltl["location"]) == ("g(light = RED)", {"path": "Ltl.asm", "line": 10, "column": 2,
                                                                    "end_column": 21})
    tv.validate(ltl)


def test_swarm_json_temporal_violations_carry_formula_and_location(specs, capsys):
    text = SMALL.replace("\tmain rule", "\tLTLSPEC ltlSpec_red: g(light = RED)\n\tmain rule")
    (specs / "Ltl.asm").write_text(text.replace("asm Small", "asm Ltl").replace("StandardLibrary", "StandardLibrary\nimport LTLLibrary"))
    code, out = run(capsys, "simulate", "Ltl.asm", "--swarm", "2", "--depth", "4", "--swarm-workers", "1",
                    "--format", "json")
    assert code == 1
    got = [(v["property"], v["kind"], v["formula"], v["location"], v["loop_start"] if "loop_start" in v else "-")
           for v in json.loads(out)["violations"]]
    assert got == [
        ("inv_red", "state", "light = RED", {"path": "Ltl.asm", "line": 9, "column": 2, "end_column": 19}, "-"),
        ("ltlSpec_red", "ltl", "g(light = RED)", {"path": "Ltl.asm", "line": 10, "column": 2, "end_column": 21}, 2),
    ]


# ----------------------------------------------------------------- --graph
SMALL_DOT = r"""digraph states {
  node [shape=box, fontname=monospace];
  s0 [label="light = RED\l", penwidth=2, color=red, fontcolor=red];
  s1 [label="light = GREEN\l", color=red, fontcolor=red];
  s0 -> s0 [label="r_main chooses $l = RED; reads go = true"];
  s0 -> s0 [label="r_main; reads go = false"];
  s0 -> s1 [label="r_main chooses $l = GREEN; reads go = true", color=red, fontcolor=red, penwidth=2];
  s1 -> s0 [label="r_main chooses $l = RED; reads go = true"];
  s1 -> s1 [label="r_main chooses $l = GREEN; reads go = true"];
  s1 -> s1 [label="r_main; reads go = false"];
}
"""


def _edge(i, src, dst, text, cx):
    return (f'    <edge id="e{i}" source="s{src}" target="s{dst}">\n'
            f'      <data key="e_choices">{text}</data>\n'
            f'      <data key="e_counterexample_edge">{"true" if cx else "false"}</data>\n'
            f'    </edge>\n')


SMALL_GRAPHML = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<graphml xmlns="http://graphml.graphdrawing.org/xmlns">\n'
    '  <key id="n_label" for="node" attr.name="label" attr.type="string" />\n'
    '  <key id="n_depth" for="node" attr.name="depth" attr.type="int" />\n'
    '  <key id="n_initial" for="node" attr.name="initial" attr.type="boolean" />\n'
    '  <key id="n_counterexample" for="node" attr.name="counterexample" attr.type="boolean" />\n'
    '  <key id="e_choices" for="edge" attr.name="choices" attr.type="string" />\n'
    '  <key id="e_counterexample_edge" for="edge" attr.name="counterexample" attr.type="boolean" />\n'
    '  <graph id="states" edgedefault="directed">\n'
    '    <node id="s0">\n'
    '      <data key="n_label">light = RED</data>\n'
    '      <data key="n_depth">0</data>\n'
    '      <data key="n_initial">true</data>\n'
    '      <data key="n_counterexample">true</data>\n'
    '    </node>\n'
    '    <node id="s1">\n'
    '      <data key="n_label">light = GREEN</data>\n'
    '      <data key="n_depth">1</data>\n'
    '      <data key="n_initial">false</data>\n'
    '      <data key="n_counterexample">true</data>\n'
    '    </node>\n'
    + _edge(0, 0, 0, "r_main; reads go = false", False)
    + _edge(1, 0, 0, "r_main chooses $l = RED; reads go = true", False)
    + _edge(2, 0, 1, "r_main chooses $l = GREEN; reads go = true", True)
    + _edge(3, 1, 1, "r_main; reads go = false", False)
    + _edge(4, 1, 0, "r_main chooses $l = RED; reads go = true", False)
    + _edge(5, 1, 1, "r_main chooses $l = GREEN; reads go = true", False)
    + '  </graph>\n'
    '</graphml>\n')


def test_graph_dot_text_of_a_small_spec(specs, capsys):
    code, out = run(capsys, "explore", "Small.asm", "--graph", "s.dot")
    assert code == 1
    assert (specs / "s.dot").read_text() == SMALL_DOT
    # the edge labels are the step lines of the trace, without the step number
    assert "  step 1: r_main chooses $l = GREEN; reads go = true  <- violates the property" in out.splitlines()
    assert "choose at" not in SMALL_DOT


def test_graph_graphml_text_of_a_small_spec(specs, capsys):
    import networkx as nx
    code, _ = run(capsys, "explore", "Small.asm", "--graph", "s.graphml")
    assert code == 1
    text = (specs / "s.graphml").read_text()
    assert text == SMALL_GRAPHML
    g = nx.read_graphml(specs / "s.graphml")
    assert g.nodes["s1"]["counterexample"] is True and g.nodes["s1"]["initial"] is False
    assert [d["choices"] for _, _, d in g.edges(data=True) if d["counterexample"]] == [
        "r_main chooses $l = GREEN; reads go = true"]


def test_graph_of_the_running_example_names_rules_and_reads(specs, capsys):
    code, _ = run(capsys, "explore", "Graph.asm", "--graph", "g.dot")
    assert code == 1
    lines = (specs / "g.dot").read_text().splitlines()
    edges = [ln for ln in lines if " -> " in ln]
    assert len(edges) == 24
    assert [ln for ln in edges if "color=red" in ln] == [
        '  s0 -> s2 [label="r_main; reads go = true", color=red, fontcolor=red, penwidth=2];',
        '  s2 -> s4 [label="r_main; reads go = true", color=red, fontcolor=red, penwidth=2];',
        '  s4 -> s6 [label="r_main; reads go = true", color=red, fontcolor=red, penwidth=2];',
    ]
    assert edges[:3] == [
        '  s0 -> s0 [label="r_main chooses $l = RED; reads go = false"];',
        '  s0 -> s1 [label="r_main chooses $l = GREEN; reads go = false"];',
        '  s0 -> s2 [label="r_main; reads go = true", color=red, fontcolor=red, penwidth=2];',
    ]


def test_graph_label_of_a_step_that_fails(specs, capsys):
    """A step that fails has no edge; an edge's label never shows a choice index."""
    from asmcheck import api
    from asmcheck.report.graph import edge_label
    from asmcheck.semantics.choice import ScriptChooser
    m = api.load("Clash.asm").machine
    state = m.initial_state(ScriptChooser([]))
    # go = true (index 1 of false/true) makes the step fail: its label still names the input read
    assert edge_label(m, state, [1]) == "r_main; reads go = true"
    assert edge_label(m, state, [0]) == "r_main; reads go = false"


COUNTER = """asm Counter
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	main rule r_main = x := (x + 1) mod {n}
default init s0:
	function x = 0
"""


@pytest.mark.parametrize("n, warned", [(500, False), (501, True)])
def test_a_graph_over_500_states_is_written_with_a_warning(specs, capsys, n, warned):
    (specs / "Counter.asm").write_text(COUNTER.format(n=n))
    code = main(["explore", "Counter.asm", "--graph", "c.dot"])
    err = capsys.readouterr().err
    assert code == 0
    assert (specs / "c.dot").read_text().count(" -> ") == n
    warning = (f"asmcheck: warning: the graph in c.dot has {n:,} states; over 500 a drawing of it is hard to read "
               f"(bound the search with --max-depth, or give fewer monitored values)\n")
    assert err == (warning if warned else "")
