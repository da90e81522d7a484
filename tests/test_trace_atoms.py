"""Temporal traces show the monitored values that only the atoms of the property read: a node of
the temporal structure keeps each atom's truth value, and the replay finds again the first values
(in the enumeration order) that give it, prints them with the values the step read (text, JSON,
ITF, Avalla, HTML) and evaluates the atoms again from the printed values."""
from __future__ import annotations

import json

import pytest

from asmcheck import api
from asmcheck.explore.bfs import ReplayError
from asmcheck.explore.trace import atom_reads
from asmcheck.report.avalla_export import trace_scenario
from asmcheck.report.trace import temporal_json, temporal_text
from asmcheck.semantics.values import show

from helpers import write

pytestmark = pytest.mark.engines("both")

# the rule reads inc only; the atoms read level and open(RIGHT) / open(LEFT) too
NOISE = """asm Noise
import StandardLibrary
import LTLLibrary
import CTLLibrary
signature:
	domain Cnt subsetof Integer
	enum domain Level = {LOW | MID | HIGH}
	enum domain Side = {LEFT | RIGHT}
	controlled x: Cnt
	monitored inc: Boolean
	monitored level: Level
	monitored open: Side -> Boolean
definitions:
	domain Cnt = {0 : 3}
	LTLSPEC g(x = 2 implies level != HIGH)
	LTLSPEC g(open(RIGHT) implies x < 3)
	CTLSPEC ag(x = 1 implies level = LOW)
	CTLSPEC ef(x = 2 and level = MID and open(LEFT))
	main rule r_main =
		if inc then
			if x < 3 then x := x + 1 else x := 0 endif
		endif
default init s0:
	function x = 0
"""

LTL_1 = """\
ltl_1 (Noise.asm:15:2) is violated -- counterexample, 4 steps: a lasso, 3 steps to the loop, then a loop of 1 step repeated for ever:
  formula: g(x = 2 implies level != HIGH)
  state 0 (initial)
      x = 0
  step 1: r_main; reads inc = true
      x = 1
  step 2: r_main; reads inc = true
      x = 2
  step 3: r_main; reads inc = false, level = HIGH  <- the loop starts here (state 3)
      (no change: the state repeats, state 3 = state 2)
  step 4: r_main; reads inc = false, level = LOW  <- back to state 3
      (no change: the state repeats for ever)"""

LTL_2 = """\
ltl_2 (Noise.asm:16:2) is violated -- counterexample, 5 steps: a lasso, 4 steps to the loop, then a loop of 1 step repeated for ever:
  formula: g(open(RIGHT) implies x < 3)
  state 0 (initial)
      x = 0
  step 1: r_main; reads inc = true, open(RIGHT) = false
      x = 1
  step 2: r_main; reads inc = true, open(RIGHT) = false
      x = 2
  step 3: r_main; reads inc = true, open(RIGHT) = false
      x = 3
  step 4: r_main; reads inc = false, open(RIGHT) = true  <- the loop starts here (state 4)
      (no change: the state repeats, state 4 = state 3)
  step 5: r_main; reads inc = false, open(RIGHT) = false  <- back to state 4
      (no change: the state repeats for ever)"""

CTL_1 = """\
ctl_1 (Noise.asm:17:2) is violated -- counterexample, 2 steps:
  formula: ag(x = 1 implies level = LOW)
  state 0 (initial)
      x = 0
  step 1: r_main; reads inc = true
      x = 1
  step 2: r_main; reads inc = false, level = MID
      (no change)
  (step 2 only shows the monitored inputs and choices of state 1, which are part of its state for the property)"""

CTL_2 = """\
ctl_2 (Noise.asm:18:2) holds -- witness, 3 steps:
  formula: ef(x = 2 and level = MID and open(LEFT))
  state 0 (initial)
      x = 0
  step 1: r_main; reads inc = true
      x = 1
  step 2: r_main; reads inc = true
      x = 2
  step 3: r_main; reads inc = false, level = MID, open(LEFT) = true
      (no change)
  (step 3 only shows the monitored inputs and choices of state 2, which are part of its state for the property)"""

# from x = 2 every step fails: the CTL counterexample ends with the failing step, whose atom reads
# level (the step does not)
HALT = """asm Halt
import StandardLibrary
import LTLLibrary
import CTLLibrary
signature:
	domain Cnt subsetof Integer
	enum domain Level = {LOW | MID | HIGH}
	controlled x: Cnt
	monitored inc: Boolean
	monitored level: Level
definitions:
	domain Cnt = {0 : 2}
	CTLSPEC ag(x = 2 implies level = LOW)
	main rule r_main =
		if x < 2 then
			if inc then x := x + 1 endif
		else
			x := x + 1
		endif
default init s0:
	function x = 0
"""

HALT_CTL = """\
ctl_1 (Halt.asm:13:2) is violated, relative to the run-time error at Halt.asm:18:4 -- counterexample, 2 steps, then step 3 fails:
  formula: ag(x = 2 implies level = LOW)
  state 0 (initial)
      x = 0
  step 1: r_main; reads inc = true
      x = 1
  step 2: r_main; reads inc = true
      x = 2
  step 3: r_main; reads level = MID  <- fails (the step cannot be made)
  (step 3 fails: value out of domain: 3 is not in Cnt (the codomain of x); the run stops there and stays in state 2 for ever)"""


def _run(tmp_path, text, asmcheck_engine):
    from asmcheck.explore.native_build import compiler
    model = api.load(write(tmp_path, text))
    run = model.explore(engine=asmcheck_engine)
    want = "native" if asmcheck_engine == "auto" and compiler() is not None else "python"
    assert run.engine == want
    return model, run


def test_text_of_ltl_and_ctl_traces(tmp_path, asmcheck_engine):
    model, run = _run(tmp_path, NOISE, asmcheck_engine)
    assert (run.states, run.transitions) == (4, 8)
    assert [(r.name, r.verdict) for r in run.temporal] == [
        ("ltl_1", "violated"), ("ltl_2", "violated"), ("ctl_1", "violated"), ("ctl_2", "holds")]
    texts = ["\n".join(temporal_text(r, model.machine)) for r in run.temporal]
    assert texts == [LTL_1, LTL_2, CTL_1, CTL_2]


def test_the_failing_step_shows_the_atoms_values(tmp_path, asmcheck_engine):
    model, run = _run(tmp_path, HALT, asmcheck_engine)
    r = run.temporal[0]
    assert "\n".join(temporal_text(r, model.machine)) == HALT_CTL
    js = temporal_json(r, model.machine)
    assert js["failing_step"] == {"step": 3, "choices": [{"kind": "monitored", "at": "level", "value": "MID"}]}


def test_json_itf_avalla_and_html_carry_the_values(tmp_path, asmcheck_engine, capsys):
    model, run = _run(tmp_path, NOISE, asmcheck_engine)
    m = model.machine
    reads = {r.name: [e.get("reads") for e in temporal_json(r, m)["trace"]] for r in run.temporal}
    assert reads == {
        "ltl_1": [None, {"inc": True}, {"inc": True}, {"inc": False, "level": "HIGH"},
                  {"inc": False, "level": "LOW"}],
        "ltl_2": [None] + [{"inc": True, "open(RIGHT)": False}] * 3 +
                 [{"inc": False, "open(RIGHT)": True}, {"inc": False, "open(RIGHT)": False}],
        "ctl_1": [None, {"inc": True}, {"inc": False, "level": "MID"}],
        "ctl_2": [None, {"inc": True}, {"inc": True}, {"inc": False, "level": "MID", "open(LEFT)": True}],
    }
    # the report of `explore --format json`
    doc = json.loads(json.dumps(run.json()))
    ltl = next(v for v in doc["violations"] if v["property"] == "ltl_1")
    assert ltl["trace"][3]["reads"] == {"inc": False, "level": "HIGH"}
    # ITF (`explore --format itf`): the inputs of each state
    from asmcheck.cli import main
    capsys.readouterr()
    main(["explore", str(tmp_path / "Noise.asm"), "--format", "itf"])
    itf = json.loads(capsys.readouterr().out)
    ctl = next(t for t in itf if "ctl_1" in t["#meta"]["description"])
    assert [s["#meta"].get("inputs") for s in ctl["states"]] == [
        None, {"inc": "true"}, {"inc": "false", "level": "MID"}]
    # Avalla: the scenario sets the value the atom read
    tr, _, _ = run.temporal[2].trace()
    sc = trace_scenario(m, tr, spec_path=str(tmp_path / "Noise.asm"), out_path=str(tmp_path / "c.avalla"),
                        prop=run.temporal[2].prop)
    assert "// step 2: r_main; reads inc = false, level = MID\nset inc := false;\nset level := MID;\nstep\n" in sc
    # HTML
    page = run.html()
    assert "step 2: r_main; reads inc = false, level = MID" in page


def test_the_values_are_the_first_that_give_the_atoms(tmp_path, asmcheck_engine):
    model, run = _run(tmp_path, NOISE, asmcheck_engine)
    m = model.machine
    r = run.temporal[3]
    items = r.K.mon_items
    state = run.explorer.state(0)
    # the atoms in the order of the structure: the four properties' monitored ones
    assert [a.text for a in items] == ["x = 2 implies level != HIGH", "open(RIGHT) implies x < 3",
                                       "x = 1 implies level = LOW", "x = 2 and level = MID and open(LEFT)"]
    x2 = run.explorer.state(2)
    assert {m.location_text(k): v for k, v in x2.items()} == {"x": 2}

    def reads(state, vec):
        got = atom_reads(m, items, state, {}, vec)
        return None if got is None else {m.location_text(k): show(v) for k, v in got.items()}
    # x = 0: only 'open(RIGHT) implies x < 3' reads a value, the first of Boolean
    assert reads(state, (True, True, True, False)) == {"open(RIGHT)": "false"}
    # no values make it false while x < 3
    assert reads(state, (True, False, True, False)) is None
    # x = 2: level LOW makes the last atom false, MID is the first that makes it true
    assert reads(x2, (True, True, True, False)) == {"level": "LOW", "open(RIGHT)": "false"}
    assert reads(x2, (True, True, True, True)) == {"level": "MID", "open(RIGHT)": "false", "open(LEFT)": "true"}
    assert reads(x2, (False, True, True, False)) == {"level": "HIGH", "open(RIGHT)": "false"}
    # level HIGH and MID at once
    assert reads(x2, (False, True, True, True)) is None
    # a value the step read is kept, not shown again
    full = atom_reads(m, items, x2, {}, (False, True, True, False))
    lev = next(k for k in full if m.location_text(k) == "level")
    high, low = full[lev], atom_reads(m, items, x2, {}, (True, True, True, False))[lev]
    got = atom_reads(m, items, x2, {lev: high}, (False, True, True, False))
    assert {m.location_text(k): show(v) for k, v in got.items()} == {"open(RIGHT)": "false"}
    assert atom_reads(m, items, x2, {lev: low}, (False, True, True, False)) is None


def test_the_printed_values_are_checked(tmp_path, asmcheck_engine, monkeypatch):
    """Values that do not give the node's atom values are refused (the atoms are evaluated again
    from the values printed)."""
    model, run = _run(tmp_path, NOISE, asmcheck_engine)
    import asmcheck.explore.trace as T
    real = T.atom_reads

    def wrong(machine, items, state, mon, vec):
        got = real(machine, items, state, mon, vec)
        return {k: (not v if isinstance(v, bool) else v) for k, v in (got or {}).items()}
    monkeypatch.setattr(T, "atom_reads", wrong)
    r = run.temporal[1]
    with pytest.raises(ReplayError, match="do not give the values of the path"):
        r.trace()


# an INVAR over a monitored function excludes values: the values shown satisfy it (level LOW is
# never shown), and a monitored Integer bounded by --monitored
INV = """asm Inv
import StandardLibrary
import LTLLibrary
import CTLLibrary
signature:
	enum domain Level = {LOW | MID | HIGH}
	domain Cnt subsetof Integer
	controlled x: Cnt
	monitored level: Level
	monitored temp: Integer
	monitored tick: Boolean
definitions:
	domain Cnt = {0 : 2}
	INVAR level != LOW
	CTLSPEC ag(x = 1 implies level = MID)
	LTLSPEC g(x = 2 implies temp < 3)
	main rule r_main =
		if tick then
			if x < 2 then x := x + 1 endif
		endif
default init s0:
	function x = 0
"""


def test_values_satisfy_the_invar(tmp_path, asmcheck_engine):
    from asmcheck.explore.native_build import compiler
    model = api.load(write(tmp_path, INV), monitored={"temp": "0..4"})
    run = model.explore(engine=asmcheck_engine)
    assert run.engine == ("native" if asmcheck_engine == "auto" and compiler() is not None else "python")
    heads = [[ln for ln in temporal_text(r, model.machine) if ln.startswith("  step")] for r in run.temporal]
    assert heads == [
        ["  step 1: r_main; reads level = MID, tick = true",
         "  step 2: r_main; reads level = HIGH, tick = false"],
        ["  step 1: r_main; reads level = MID, tick = true",
         "  step 2: r_main; reads level = MID, tick = true",
         "  step 3: r_main; reads level = MID, temp = 3, tick = false  <- the loop starts here (state 3)",
         "  step 4: r_main; reads level = MID, temp = 0, tick = false  <- back to state 3"]]


# a JUSTICE over a monitored function the rule does not read: the lasso's loop shows where it holds
FAIR = """asm Fair
import StandardLibrary
import LTLLibrary
signature:
	enum domain Level = {LOW | MID | HIGH}
	domain Cnt subsetof Integer
	controlled x: Cnt
	monitored level: Level
	monitored tick: Boolean
definitions:
	domain Cnt = {0 : 2}
	JUSTICE level = HIGH
	LTLSPEC g(x < 2)
	main rule r_main =
		if tick then
			if x < 2 then x := x + 1 endif
		endif
default init s0:
	function x = 0
"""


def test_the_justice_atoms_values_are_shown(tmp_path, asmcheck_engine):
    model, run = _run(tmp_path, FAIR, asmcheck_engine)
    heads = [ln for ln in temporal_text(run.temporal[0], model.machine) if ln.startswith("  step")]
    assert heads == ["  step 1: r_main; reads level = LOW, tick = true",
                     "  step 2: r_main; reads level = LOW, tick = true",
                     "  step 3: r_main; reads level = LOW, tick = false  <- the loop starts here (state 3)",
                     "  step 4: r_main; reads level = LOW, tick = false",
                     "  step 5: r_main; reads level = HIGH, tick = false  <- back to state 3"]
