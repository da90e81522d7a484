"""Traces name the elements made by ``extend`` as a simulation of the same run does: an
element keeps its name for its whole life, a new one gets the next number of its domain
(while the explorer stores states under canonical names)."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

from asmcheck.cli import main
from asmcheck.props.load import load_machine
from asmcheck.explore.bfs import Explorer
from asmcheck.props import spec_properties
from asmcheck.props.files import properties_for
from asmcheck.report.avalla_export import trace_scenario
from asmcheck.report.gate import ChooseIndex, step_header, step_inputs, step_records
from asmcheck.report.trace import build_trace, display_names, trace_json, trace_text
from asmcheck.semantics.machine import ScriptChooser
from asmcheck.semantics.state import is_dom_key
from asmcheck.semantics.values import fresh_value
from asmcheck.simulate import simulate
import pytest

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parent.parent

# two elements, then swapped at every step; a counter ends the trace
REP = """asm Rep
import StandardLibrary
signature:
	dynamic abstract domain D
	dynamic controlled cur: D
	dynamic controlled other: D
	dynamic controlled mark: D -> Boolean
	dynamic controlled started: Boolean
	dynamic controlled n: Integer
definitions:
	main rule r_main =
		if not started then
			extend D with $a, $b do
				par
					cur := $a
					other := $b
					mark($a) := true
					mark($b) := false
					started := true
				endpar
		else
			par
				cur := other
				other := cur
				if n < 4 then n := n + 1 endif
			endpar
		endif
default init s0:
	function started = false
	function n = 0
"""
REP_PROPS = """applies to Rep
step stp_mark: started implies (let ($x = cur) in next(mark($x)) = mark($x) endlet)
invariant inv_n: n < 3
"""

# one element a step; only the one of step 2 is kept (D is not ranged over: the others are dropped)
DROP = """asm Drop
import StandardLibrary
signature:
	dynamic abstract domain D
	dynamic controlled cur: D
	dynamic controlled keep: D
	dynamic controlled t: Integer
definitions:
	main rule r_main =
		if t < 4 then
			extend D with $a do
				par
					cur := $a
					if t = 2 then keep := cur endif
					t := t + 1
				endpar
		endif
default init s0:
	function t = 0
"""
DROP_PROPS = "applies to Drop\ninvariant inv_t: t < 4\n"

# a choose over the made elements: the canonical order of its options is not the creation order
PICK = """asm Pick
import StandardLibrary
signature:
	dynamic abstract domain D
	dynamic controlled mark: D -> Boolean
	dynamic controlled last: D
	dynamic controlled started: Boolean
	dynamic controlled t: Integer
definitions:
	main rule r_main =
		if not started then
			extend D with $a, $b do
				par
					mark($a) := true
					mark($b) := false
					started := true
				endpar
		else
			choose $x in D with true do
				par
					forall $y in D do mark($y) := ($y != $x)
					last := $x
					if t < 3 then t := t + 1 endif
				endpar
		endif
default init s0:
	function started = false
	function t = 0
"""
PICK_PROPS = "applies to Pick\ninvariant inv_t: t < 3\n"

# a monitored function over the made elements
SENSE = """asm Sense
import StandardLibrary
signature:
	dynamic abstract domain D
	dynamic controlled cur: D
	dynamic controlled other: D
	dynamic controlled started: Boolean
	dynamic controlled hits: Integer
	dynamic monitored sense: D -> Boolean
definitions:
	main rule r_main =
		if not started then
			extend D with $a, $b do
				par
					cur := $a
					other := $b
					started := true
				endpar
		else
			par
				cur := other
				other := cur
				if sense(other) and hits < 3 then hits := hits + 1 endif
			endpar
		endif
default init s0:
	function started = false
	function hits = 0
"""
SENSE_PROPS = "applies to Sense\ninvariant inv_h: hits < 2\n"

# a new element at every step, the one before it kept: an LTL lasso
GEN = """asm Gen
import StandardLibrary
import LTLLibrary
signature:
	dynamic abstract domain D
	dynamic controlled cur: D
	dynamic controlled prev: D
	dynamic controlled k: Integer
definitions:
	LTLSPEC ltlSpec_two: g(k < 2)
	main rule r_main =
		extend D with $a do
			par
				prev := cur
				cur := $a
				if k < 2 then k := k + 1 endif
			endpar
default init s0:
	function k = 0
"""


def write_spec(tmp_path: Path, text: str, props: str | None = None) -> str:
    name = re.search(r"\basm\s+(\w+)", text).group(1)
    path = tmp_path / f"{name}.asm"
    path.write_text(text)
    if props is not None:
        (tmp_path / "properties").mkdir(exist_ok=True)
        (tmp_path / "properties" / f"{name}.prop").write_text(props)
    return str(path)


def explore_trace(path: str, name: str):
    """(machine, explorer, trace) of the shortest counterexample of the property ``name``."""
    spec, m = load_machine(path)
    state, step = spec_properties(m)
    extra_state, extra_step, _ = properties_for(spec, m, path)
    st = [p for p in state + extra_state if p.name == name]
    sp = [p for p in step + extra_step if p.name == name]
    ex = Explorer(m, state_props=st, step_props=sp)
    (v,) = ex.run().violations
    return m, ex, build_trace(ex, v)


def explore_text(path: str, capsys) -> list[str]:
    main(["explore", path])
    return capsys.readouterr().out.splitlines()


def trace_lines(out: list[str], name: str) -> list[str]:
    i = next(i for i, ln in enumerate(out) if ln.startswith(f"{name} ("))
    j = out.index("verdict: violated")
    return out[i:j]


def test_swapped_elements_keep_their_names_in_the_text_trace(tmp_path, capsys):
    path = write_spec(tmp_path, REP, REP_PROPS)
    out = explore_text(path, capsys)
    assert "  stp_mark                                 holds" in out
    assert trace_lines(out, "inv_n") == [
        "inv_n (Rep.prop:3:11) is violated -- shortest counterexample, 4 steps:",
        "  formula: n < 3",
        "  state 0 (initial)",
        "      n = 0",
        "      started = false",
        "  step 1: r_main",
        "      cur = D!1",
        "      mark(D!1) = true",
        "      mark(D!2) = false",
        "      other = D!2",
        "      started = true",
        "      D = {D!1, D!2}",
        "  step 2: r_main",
        "      cur = D!2",
        "      n = 1",
        "      other = D!1",
        "  step 3: r_main",
        "      cur = D!1",
        "      n = 2",
        "      other = D!2",
        "  step 4: r_main  <- violates the property",
        "      cur = D!2",
        "      n = 3",
        "      other = D!1",
    ]


def test_swapped_elements_keep_their_names_in_the_json_trace(tmp_path, capsys):
    path = write_spec(tmp_path, REP, REP_PROPS)
    main(["explore", path, "--format", "json"])
    doc = json.loads(capsys.readouterr().out)
    (v,) = doc["violations"]
    dom = {"tuple": ["D!1", "D!2"]}

    def state(cur, other, n):
        return {"cur": cur, "mark(D!1)": True, "mark(D!2)": False, "n": n, "other": other, "started": True,
                "D": dom}
    assert v["property"] == "inv_n"
    assert v["trace"] == [
        {"step": 0, "choices": [], "changed": {"n": 0, "started": False}, "state": {"n": 0, "started": False}},
        {"step": 1, "rule": "r_main", "choices": [], "reads": {},
         "updates": {"cur": "D!1", "mark(D!1)": True, "mark(D!2)": False, "other": "D!2", "started": True},
         "changed": {"cur": "D!1", "mark(D!1)": True, "mark(D!2)": False, "other": "D!2", "started": True,
                     "D": dom},
         "state": state("D!1", "D!2", 0)},
        {"step": 2, "rule": "r_main", "choices": [], "reads": {}, "updates": {"cur": "D!2", "n": 1, "other": "D!1"},
         "changed": {"cur": "D!2", "n": 1, "other": "D!1"}, "state": state("D!2", "D!1", 1)},
        {"step": 3, "rule": "r_main", "choices": [], "reads": {}, "updates": {"cur": "D!1", "n": 2, "other": "D!2"},
         "changed": {"cur": "D!1", "n": 2, "other": "D!2"}, "state": state("D!1", "D!2", 2)},
        {"step": 4, "rule": "r_main", "choices": [], "reads": {}, "updates": {"cur": "D!2", "n": 3, "other": "D!1"},
         "changed": {"cur": "D!2", "n": 3, "other": "D!1"}, "state": state("D!2", "D!1", 3)},
    ]


def test_trace_steps_keep_the_canonical_states(tmp_path):
    """Steps are re-run from TraceStep.state with the recorded choices: it stays the state
    the explorer stored; the display state is beside it."""
    path = write_spec(tmp_path, REP, REP_PROPS)
    m, ex, tr = explore_trace(path, "inv_n")
    cur = m.fname.index("cur")
    names = [[st.state[k].name for k in st.state if k == cur] for st in tr.steps]
    shown = [[st.display[k].name for k in st.display if k == cur] for st in tr.steps]
    # canonically the element in cur is always D!1 (its place names it); shown, it swaps
    assert names == [[], ["D!1"], ["D!1"], ["D!1"], ["D!1"]]
    assert shown == [[], ["D!1"], ["D!2"], ["D!1"], ["D!2"]]
    for st in tr.steps:
        assert ex.layout.freeze(st.state) in ex.frozen
    # re-running a step from the canonical state reproduces the next canonical state
    for prev, st in zip(tr.steps, tr.steps[1:]):
        _, raw, _ = m.step(prev.state, ScriptChooser([c.pick for c in st.choices]))
        assert ex._norm(raw) == st.state
    assert len(step_inputs(m, tr)) == len(tr.steps)


def test_new_elements_are_numbered_after_all_earlier_ones(tmp_path, capsys):
    path = write_spec(tmp_path, DROP, DROP_PROPS)
    out = explore_text(path, capsys)
    assert trace_lines(out, "inv_t") == [
        "inv_t (Drop.prop:2:11) is violated -- shortest counterexample, 4 steps:",
        "  formula: t < 4",
        "  state 0 (initial)",
        "      t = 0",
        "  step 1: r_main",
        "      cur = D!1",
        "      t = 1",
        "      D = {D!1}",
        "  step 2: r_main",
        "      cur = D!2",
        "      t = 2",
        "      D = {D!2}",
        "  step 3: r_main",
        "      cur = D!3",
        "      keep = D!2",
        "      t = 3",
        "      D = {D!2, D!3}",
        "  step 4: r_main  <- violates the property",
        "      cur = D!4",
        "      t = 4",
        "      D = {D!2, D!4}",
    ]


def without_domains(state: dict) -> dict:
    return {k: v for k, v in state.items() if not is_dom_key(k)}


def test_a_deterministic_trace_names_elements_as_the_simulation(tmp_path):
    """The simulator keeps every element (no canonical names, nothing dropped): the trace's
    locations are the simulation's, step by step."""
    for text, props, name in ((REP, REP_PROPS, "inv_n"), (DROP, DROP_PROPS, "inv_t")):
        path = write_spec(tmp_path, text, props)
        m, _, tr = explore_trace(path, name)
        sim = list(simulate(m, len(tr.steps) - 1))
        assert [without_domains(st.display) for st in tr.steps] == [without_domains(s.state) for s in sim], name


def test_choices_are_shown_under_display_names(tmp_path, capsys):
    path = write_spec(tmp_path, PICK, PICK_PROPS)
    out = explore_text(path, capsys)
    # $a (marked) is D!1 as in a simulation; canonically the unmarked element comes first
    assert trace_lines(out, "inv_t") == [
        "inv_t (Pick.prop:2:11) is violated -- shortest counterexample, 4 steps:",
        "  formula: t < 3",
        "  state 0 (initial)",
        "      started = false",
        "      t = 0",
        "  step 1: r_main",
        "      mark(D!1) = true",
        "      mark(D!2) = false",
        "      started = true",
        "      D = {D!1, D!2}",
        "  step 2: r_main chooses $x = D!2",
        "      last = D!2",
        "      t = 1",
        "  step 3: r_main chooses $x = D!2",
        "      t = 2",
        "  step 4: r_main chooses $x = D!2  <- violates the property",
        "      t = 3",
    ]
    m, ex, tr = explore_trace(path, "inv_t")
    js = trace_json(m, tr)
    assert [c["value"] for st in js[1:] for c in st["choices"]] == [{"$x": "D!2"}] * 3
    recs = step_records(m, tr, ChooseIndex(m.spec))
    assert step_header(recs[2]) == "step 2: r_main chooses $x = D!2"
    # the recorded choices are untouched: canonically $x is D!1
    assert [c.value["$x"].name for c in tr.steps[2].choices] == ["D!1"]


def test_monitored_inputs_are_shown_under_display_names(tmp_path, capsys):
    """The step reads sense(other): canonically always sense(D!2), shown the element in other."""
    path = write_spec(tmp_path, SENSE, SENSE_PROPS)
    out = explore_text(path, capsys)
    assert [ln for ln in trace_lines(out, "inv_h") if ln.startswith("  step")] == [
        "  step 1: r_main", "  step 2: r_main; reads sense(D!2) = true",
        "  step 3: r_main; reads sense(D!1) = true  <- violates the property"]
    main(["check", path])
    out = capsys.readouterr().out.splitlines()
    assert [ln.split("  <-")[0] for ln in out if ln.startswith("  step")] == [
        "  step 1: r_main", "  step 2: r_main; reads sense(D!2) = true", "  step 3: r_main; reads sense(D!1) = true"]


def test_a_temporal_lasso_keeps_the_names(tmp_path, capsys):
    path = write_spec(tmp_path, GEN)
    out = explore_text(path, capsys)
    assert trace_lines(out, "ltlSpec_two") == [
        "ltlSpec_two (Gen.asm:10:2) is violated -- counterexample, 4 steps: a lasso, 3 steps to the loop, then"
        " a loop of 1 step repeated for ever:",
        "  formula: g(k < 2)",
        "  state 0 (initial)",
        "      k = 0",
        "  step 1: r_main",
        "      cur = D!1",
        "      k = 1",
        "      D = {D!1}",
        "  step 2: r_main",
        "      cur = D!2",
        "      k = 2",
        "      prev = D!1",
        "      D = {D!1, D!2}",
        "  step 3: r_main  <- the loop starts here (state 3)",
        "      cur = D!3",
        "      prev = D!2",
        "      D = {D!2, D!3}",
        "  step 4: r_main  <- back to state 3 (up to the names of the elements made by extend)",
        "      cur = D!4",
        "      prev = D!3",
        "      D = {D!3, D!4}",
    ]
    main(["explore", path, "--format", "json"])
    (v,) = json.loads(capsys.readouterr().out)["violations"]
    assert v["loop_start"] == 3
    assert [st["changed"] for st in v["trace"]][2:] == [
        {"cur": "D!2", "k": 2, "prev": "D!1", "D": {"tuple": ["D!1", "D!2"]}},
        {"cur": "D!3", "prev": "D!2", "D": {"tuple": ["D!2", "D!3"]}},
        {"cur": "D!4", "prev": "D!3", "D": {"tuple": ["D!3", "D!4"]}},
    ]


def test_gate_reports_use_the_display_names(tmp_path, capsys):
    path = write_spec(tmp_path, GEN)
    html = tmp_path / "r.html"
    main(["check", path, "--html", str(html), "--traces", "all"])
    out = capsys.readouterr().out
    assert "  step 4: r_main  <- back to state 3 (up to the names of the elements made by extend)" in out
    assert "state 4 is state 3 again (up to the names of the elements made by extend): the loop repeats" \
        in html.read_text()
    path = write_spec(tmp_path, REP, REP_PROPS)
    main(["check", path, "--json", "-"])
    doc = json.loads(capsys.readouterr().out)
    (row,) = [p for p in doc["specs"][0]["properties"] if p["property"] == "inv_n"]
    assert [st["changed"] for st in row["counterexample"]["trace"]][2:] == [
        {"cur": "D!2", "n": 1, "other": "D!1"}, {"cur": "D!1", "n": 2, "other": "D!2"},
        {"cur": "D!2", "n": 3, "other": "D!1"}]


def test_a_loop_back_to_the_same_names_has_no_note(tmp_path, capsys):
    """The swap returns to the same names every second step: the loop needs no note."""
    path = write_spec(tmp_path, REP.replace("import StandardLibrary\n", "import StandardLibrary\nimport LTLLibrary\n"),
                      "applies to Rep\nLTLSPEC ltlSpec_small: g(n < 4)\n")
    out = explore_text(path, capsys)
    marks = [ln for ln in out if "(state 6)" in ln or "back to" in ln]
    assert marks == ["  step 6: r_main  <- the loop starts here (state 6)", "  step 8: r_main  <- back to state 6"]
    assert out[out.index("  step 8: r_main  <- back to state 6") + 1:][:2] == ["      cur = D!2", "      other = D!1"]


def run_scenario(path: Path, capsys) -> dict:
    main(["scenario", str(path), "--format", "json"])
    return json.loads(capsys.readouterr().out)


def test_avalla_export_names_elements_as_the_validator_run(tmp_path, capsys):
    """``asmcheck scenario`` runs a scenario without canonical names: the locations the
    export leaves out (they name made elements) hold the values it quotes, under the
    display names."""
    for text, props, name in ((REP, REP_PROPS, "inv_n"), (DROP, DROP_PROPS, "inv_t"), (SENSE, SENSE_PROPS, "inv_h")):
        path = write_spec(tmp_path, text, props)
        m, _, tr = explore_trace(path, name)
        out = tmp_path / f"{name}.avalla"
        scenario = trace_scenario(m, tr, spec_path=path, out_path=str(out), prop=tr.prop)
        left_out = re.findall(r"^// not checked: (.+) = (.+) \(an element made by extend has no name\)$", scenario,
                              re.M)
        assert left_out
        out.write_text(scenario)
        doc = run_scenario(out, capsys)
        checks = [e for e in doc["events"] if e["kind"] == "check"]
        if "// not set:" not in scenario:      # (unset inputs of made elements: the run may differ)
            assert all(c["ok"] for c in checks[:-1]) and not checks[-1]["ok"], checks
        # the same checks, with the made elements named: they pass as well
        named = re.sub(r"^// not checked: (.+) = (.+) \(an element made by extend has no name\)$",
                       r"check \1 = \2;", scenario, flags=re.M)
        named = re.sub(r"^// not set: (.+) := (.+) \(an element made by extend has no name\)$",
                       r"set \1 := \2;", named, flags=re.M)
        out.write_text(named)
        doc = run_scenario(out, capsys)
        checks = [e for e in doc["events"] if e["kind"] == "check"]
        assert len(checks) > len(left_out)
        assert all(c["ok"] for c in checks[:-1]) and not checks[-1]["ok"], [c for c in checks if not c["ok"]]


def test_display_names_of_a_step_that_makes_elements_out_of_order():
    """Made elements get numbers in the order the step made them, whatever their canonical
    names; an element of the state before keeps its name."""
    d1, d2, d3 = (fresh_value("Dn", k) for k in (1, 2, 3))
    dom = ("#dom", "Dn")
    s0 = {"f": d1, dom: (d1,)}
    raw = {"f": d1, "g": d2, "h": d3, dom: (d1, d2, d3)}
    # canonically: d3 -> D!1, d1 -> D!2, d2 -> D!3
    mapping = {d3: d1, d1: d2, d2: d3}
    canon = {"f": d2, "g": d3, "h": d1, dom: (d1, d2, d3)}
    (n0, v0), (n1, v1) = display_names([(s0, None, None), (canon, raw, mapping)])
    assert (n0, v0) == ({}, {})
    assert n1 == {d2: d1, d3: d2, d1: d3}
    assert v1 == {}        # raw names are the display names here
    # a second step from canon: f goes (its element, canon's d2 shown D!1, is dropped) and a
    # new element (raw D!4) is made, canonically D!1; canon's d3 and d1 keep their names D!2, D!3
    d4 = fresh_value("Dn", 4)
    raw2 = {"g": d3, "h": d1, "k": d4, dom: (d1, d2, d3, d4)}
    canon2 = {"g": d2, "h": d3, "k": d1, dom: (d1, d2, d3)}
    mapping2 = {d4: d1, d3: d2, d1: d3}
    *_, (n2, v2) = display_names([(s0, None, None), (canon, raw, mapping), (canon2, raw2, mapping2)])
    assert n2 == {d1: d4}               # D!2 and D!3 show as themselves; the new one is D!4
    assert v2 == {d1: d3, d2: d1, d3: d2}   # the step's values: canon's elements as shown there; d4 itself


def test_a_spec_without_extend_shows_its_states_as_they_are(tmp_path):
    path = write_spec(tmp_path, "asm Plain\nimport StandardLibrary\nsignature:\n\tdynamic controlled x: Integer\n"
                                "definitions:\n\tmain rule r_main = if x < 3 then x := x + 1 endif\n"
                                "default init s0:\n\tfunction x = 0\n", "applies to Plain\ninvariant inv_x: x < 2\n")
    m, _, tr = explore_trace(path, "inv_x")
    assert all(st.display is st.state and st.names == {} for st in tr.steps)
    assert trace_text(m, tr)[-2:] == ["step 2: r_main  <- violates the property", "    x = 2"]


def test_the_names_do_not_depend_on_the_run(tmp_path):
    path = write_spec(tmp_path, PICK, PICK_PROPS)
    outs = []
    for seed in ("0", "1", "12345"):
        env = dict(os.environ, PYTHONHASHSEED=seed)
        out = subprocess.run([sys.executable, "-m", "asmcheck", "explore", path, "--format", "json"],
                             capture_output=True, text=True, cwd=str(ROOT), env=env).stdout
        outs.append(re.sub(r'"(compile_)?seconds": [0-9.e-]+', r'"\1seconds": 0', out))
    assert outs[0] and outs[0] == outs[1] == outs[2]
    assert '"D!2"' in outs[0]


STEP_PROPS = """applies to Rep
step stp_swap: started implies (let ($x = cur) in next(other = $x) endlet)
step stp_mark_kept: started implies (let ($x = cur) in next(mark($x)) = mark($x) endlet)
"""


def test_step_property_keeps_extend_made_elements_across_the_step(tmp_path, capsys):
    """A step property reads the successor as the step made it: an element carried across the step
    by a let is the same element after it, whatever names the explorer stores the states under."""
    import json

    from asmcheck.cli import main

    (tmp_path / "Rep.asm").write_text(REP, encoding="utf-8")
    (tmp_path / "rep.prop").write_text(STEP_PROPS, encoding="utf-8")
    assert main(["explore", str(tmp_path / "Rep.asm"), "--no-default-properties", "--properties",
                 str(tmp_path / "rep.prop"), "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {p["property"]: p["verdict"] for p in out["properties"]} == {"stp_swap": "holds", "stp_mark_kept": "holds"}
