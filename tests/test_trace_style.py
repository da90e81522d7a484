"""One trace style everywhere: ``asmcheck explore``, ``asmcheck check``, the HTML report and
the JSON describe a replayed trace alike (report/trace.py): per step the rule that chose what,
the monitored values it read and the locations it changed; the violated formula with its
location; a lasso marked where its loop starts, saying so when the state repeats."""
from __future__ import annotations

import html as html_lib
import json
import re
from pathlib import Path

import pytest

from asmcheck.cli import main

# the same trace on both engines (each trace is replayed through the Python machine)
pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parent.parent

# the choose rule is in r_pick (not the main rule), and the step reads m inside its body
TICK = """asm Ts
import StandardLibrary
signature:
	enum domain Act = {TICK | RESET}
	domain Small subsetof Integer
	dynamic controlled n: Small
	dynamic monitored m: Boolean
definitions:
	domain Small = {0 : 3}
	rule r_pick =
		choose $a in Act with true do
			if $a = TICK then
				if m then n := n + 1 endif
			else
				n := 0
			endif
	// n stays below 2
	invariant inv_small over n: n < 2
	main rule r_main = r_pick[]
default init s0:
	function n = 0
"""

TICK_TRACE = [
    "  formula: n < 2",
    "  state 0 (initial)",
    "      n = 0",
    "  step 1: r_pick chooses $a = TICK; reads m = true",
    "      n = 1",
    "  step 2: r_pick chooses $a = TICK; reads m = true  <- violates the property",
    "      n = 2",
]

# a lasso whose last step changes nothing: the state repeats for ever
STAY = """asm Lp
import StandardLibrary
import LTLLibrary
signature:
	enum domain Proc = {PA | PB}
	dynamic controlled done: Proc -> Boolean
	dynamic controlled turn: Proc
definitions:
	rule r_run($p in Proc) =
		if not done($p) then done($p) := true endif
	LTLSPEC ltlSpec_pb_done: f(done(PB))
	main rule r_main =
		choose $p in Proc with true do
			par
				r_run[$p]
				turn := $p
			endpar
default init s0:
	function done($p in Proc) = false
	function turn = PA
"""

STAY_TRACE = [
    "ltlSpec_pb_done (Lp.asm:11:2) is violated -- counterexample, 2 steps: a lasso, 1 step to the loop, then a "
    "loop of 1 step repeated for ever:",
    "  formula: f(done(PB))",
    "  state 0 (initial)",
    "      done(PA) = false",
    "      done(PB) = false",
    "      turn = PA",
    "  step 1: r_main chooses $p = PA  <- the loop starts here (state 1)",
    "      done(PA) = true",
    "  step 2: r_main chooses $p = PA  <- back to state 1",
    "      (no change: the state repeats for ever)",
]

# a lasso of two different states: every step changes something
CYCLE = """asm Cy
import StandardLibrary
import LTLLibrary
signature:
	domain Val subsetof Integer
	dynamic controlled c: Val
definitions:
	domain Val = {0 : 2}
	LTLSPEC ltlSpec_resets: g(f(c = 0))
	main rule r_main =
		if c = 2 then c := 1 else c := c + 1 endif
default init s0:
	function c = 0
"""

CYCLE_TRACE = [
    "ltlSpec_resets (Cy.asm:9:2) is violated -- counterexample, 4 steps: a lasso, 2 steps to the loop, then a "
    "loop of 2 steps repeated for ever:",
    "  formula: g(f(c = 0))",
    "  state 0 (initial)",
    "      c = 0",
    "  step 1: r_main",
    "      c = 1",
    "  step 2: r_main  <- the loop starts here (state 2)",
    "      c = 2",
    "  step 3: r_main",
    "      c = 1",
    "  step 4: r_main  <- back to state 2",
    "      c = 2",
]


def write(tmp_path: Path, text: str) -> str:
    name = re.match(r"asm (\w+)", text).group(1)
    path = tmp_path / f"{name}.asm"
    path.write_text(text)
    return str(path)


def run(capsys, *argv) -> tuple[int, str]:
    code = main(list(argv))
    return code, capsys.readouterr().out


def block(out: str, head: str) -> list[str]:
    """The lines of the trace block that starts with ``head`` (up to a blank line or the verdict)."""
    lines = out.splitlines()
    i = next(i for i, ln in enumerate(lines) if ln.startswith(head))
    j = i + 1
    while j < len(lines) and lines[j] and not lines[j].startswith("verdict:"):
        j += 1
    return lines[i:j]


def test_explore_prints_rule_choices_reads_and_the_formula(tmp_path, capsys):
    path = write(tmp_path, TICK)
    code, out = run(capsys, "explore", path)
    assert code == 1
    assert block(out, "inv_small") == [
        "inv_small (Ts.asm:18:2) is violated -- shortest counterexample, 2 steps:"] + TICK_TRACE
    assert "[choose at" not in out and "(initial):" not in out


def test_check_prints_the_same_trace(tmp_path, capsys):
    path = write(tmp_path, TICK)
    code, out = run(capsys, "check", path)
    assert code == 1
    head = f"FAIL {Path(path).as_posix()}: inv_small ({Path(path).as_posix()}:18:2) is violated"
    assert block(out, head) == [head + " -- shortest counterexample, 2 steps:"] + TICK_TRACE


def _html_steps(text: str, anchor: str) -> list[str]:
    """Per row of the trace table of one counterexample: the step column and the rule column,
    tags removed and entities decoded."""
    section = text[text.index(f'<section id="{anchor}">'):]
    section = section[:section.index("</section>")]
    rows = re.findall(r'<tr[^>]*><td class="num">(\d+)</td><td>(.*?)</td><td>(.*?)</td>', section)
    return [(int(n), html_lib.unescape(re.sub(r"<[^>]+>", "", head)), html_lib.unescape(re.sub(r"<[^>]+>", "", chg)))
            for n, head, chg in rows]


def test_html_shows_the_same_step_text(tmp_path, capsys):
    path = write(tmp_path, TICK)
    report = tmp_path / "r.html"
    run(capsys, "check", path, "--html", str(report))
    text = report.read_text()
    assert "<pre>n &lt; 2</pre>" in text
    rows = _html_steps(text, "cx1")
    assert rows == [(0, "initial state", "n = 0"),
                    (1, "r_pick chooses $a = TICK; reads m = true", "n = 1"),
                    (2, "r_pick chooses $a = TICK; reads m = true <- violates the property", "n = 2")]
    # each row is the text report's step line, without its "step N: " and with one blank before the mark
    steps = [ln.strip() for ln in TICK_TRACE if ln.startswith("  step")]
    assert [h for n, h, _ in rows[1:]] == [re.sub(r"^step \d+: ", "", s).replace("  <-", " <-") for s in steps]


def test_a_lasso_whose_state_repeats_says_so(tmp_path, capsys):
    path = write(tmp_path, STAY)
    code, out = run(capsys, "explore", path)
    assert code == 1
    assert block(out, "ltlSpec_pb_done") == STAY_TRACE
    assert "    (no change)" not in out
    code, out = run(capsys, "check", path)
    head = f"FAIL {Path(path).as_posix()}: ltlSpec_pb_done"
    got = block(out, head)
    assert got[1:] == STAY_TRACE[1:]
    report = tmp_path / "r.html"
    run(capsys, "check", path, "--html", str(report))
    rows = _html_steps(report.read_text(), "cx1")
    assert rows[-1] == (2, "r_main chooses $p = PA <- back to state 1", "(no change: the state repeats for ever)")
    assert rows[1][1] == "r_main chooses $p = PA <- the loop starts here (state 1)"


def test_a_lasso_without_a_repeat_has_no_no_change_line(tmp_path, capsys):
    path = write(tmp_path, CYCLE)
    code, out = run(capsys, "explore", path)
    assert code == 1
    assert block(out, "ltlSpec_resets") == CYCLE_TRACE
    assert "no change" not in out and "repeats" not in out.replace("repeated for ever", "")
    code, out = run(capsys, "check", path)
    got = block(out, f"FAIL {Path(path).as_posix()}: ltlSpec_resets")
    assert got[1:] == CYCLE_TRACE[1:]


def test_a_step_inside_a_lasso_that_changes_nothing_names_the_repeat(capsys):
    path = ROOT / "specs" / "buggy" / "sb_async_slave_no_recheck.asm"
    if not path.exists():
        pytest.skip("specs/buggy is not in this checkout")
    code, out = run(capsys, "explore", str(path), "--no-default-properties")
    lines = block(out, "ltlSpec_slave_leaves")
    i = lines.index("  step 3: r_main chooses $t = slave  <- the loop starts here (state 3)")
    assert lines[i + 1] == "      (no change: the state repeats, state 3 = state 2)"
    assert lines[-2:] == ["  step 9: r_main chooses $t = slave  <- back to state 3", "      scheduled = slave"]
    assert sum("(no change" in ln for ln in lines) == 1


def test_json_carries_rule_choices_reads_updates_and_loop_start(tmp_path, capsys):
    path = write(tmp_path, TICK)
    _, out = run(capsys, "explore", path, "--format", "json")
    (v,) = json.loads(out)["violations"]
    assert v["trace"] == [
        {"step": 0, "choices": [], "changed": {"n": 0}, "state": {"n": 0}},
        {"step": 1, "rule": "r_main",
         "choices": [{"kind": "choose", "at": "choose at Ts.asm:11:3", "value": {"$a": "TICK"}, "rule": "r_pick"},
                     {"kind": "monitored", "at": "m", "value": True}],
         "reads": {"m": True}, "updates": {"n": 1}, "changed": {"n": 1}, "state": {"n": 1}},
        {"step": 2, "rule": "r_main",
         "choices": [{"kind": "choose", "at": "choose at Ts.asm:11:3", "value": {"$a": "TICK"}, "rule": "r_pick"},
                     {"kind": "monitored", "at": "m", "value": True}],
         "reads": {"m": True}, "updates": {"n": 2}, "changed": {"n": 2}, "state": {"n": 2}},
    ]
    # check --json carries the same steps
    _, out = run(capsys, "check", path, "--json", "-")
    (row,) = json.loads(out)["specs"][0]["properties"]
    assert row["counterexample"]["trace"] == v["trace"]
    assert row["text"] == "n < 2"
    # a lasso: the loop start, and the step that repeats the state has an update set but no change
    path = write(tmp_path, STAY)
    _, out = run(capsys, "explore", path, "--format", "json")
    (v,) = json.loads(out)["violations"]
    assert v["loop_start"] == 1
    assert v["trace"][2]["changed"] == {} and v["trace"][2]["updates"] == {"turn": "PA"}
    assert v["trace"][2]["state"] == v["trace"][1]["state"]


def test_the_trace_text_is_deterministic(tmp_path, capsys):
    outs = set()
    for spec in (TICK, STAY, CYCLE):
        path = write(tmp_path, spec)
        for cmd in ("explore", "check"):
            first = re.sub(r"\d+\.\d\d s|\d+\.\d\d\n", "", run(capsys, cmd, path)[1])
            second = re.sub(r"\d+\.\d\d s|\d+\.\d\d\n", "", run(capsys, cmd, path)[1])
            assert first == second
            outs.add(first)
    assert len(outs) == 6


def test_the_fairness_assumed_is_shown_with_the_formula(tmp_path, capsys):
    path = write(tmp_path, STAY)
    fair = tmp_path / "lp.prop"
    fair.write_text("applies to Lp\nJUSTICE turn = PA\n")
    _, out = run(capsys, "explore", path, "--properties", str(fair))
    assert block(out, "ltlSpec_pb_done") == STAY_TRACE[:2] + ["  under fairness: JUSTICE turn = PA"] + STAY_TRACE[2:]
    _, out = run(capsys, "check", path, "--properties", str(fair))
    assert block(out, f"FAIL {Path(path).as_posix()}: ltlSpec_pb_done")[1:] == \
        STAY_TRACE[1:2] + ["  under fairness: JUSTICE turn = PA"] + STAY_TRACE[2:]


def test_simulate_prints_its_steps_as_a_trace(tmp_path, capsys):
    """Without --random the simulation takes the first choice, here the explorer's shortest trace."""
    path = write(tmp_path, TICK)
    inputs = tmp_path / "in.txt"
    inputs.write_text("m = true\n---\nm = true\n")
    code, out = run(capsys, "simulate", path, "-n", "2", "--input", str(inputs))
    assert code == 1
    assert out.splitlines() == [ln[2:].split("  <-")[0] for ln in TICK_TRACE[1:]] + [
        f"{path}:18:2: invariant inv_small is violated after step 2"]


def test_a_temporal_path_reads_the_same_in_explore_and_check(capsys):
    """Not a lasso: the step that only shows the inputs of the state before it says so, in both
    commands; the path is the shortest, from the initial node where req is read true at once (a
    bare '(no change)' step: test_trace_atoms' CTL_1)."""
    path = ROOT / "specs" / "temporal" / "request_ack.asm"
    if not path.exists():
        pytest.skip("specs/temporal is not in this checkout")
    steps = [
        "  formula: ag(req implies ack)",
        "  state 0 (initial)",
        "      ack = false",
        "      busy = false",
        "  step 1: r_main; reads req = true",
        "      ack = true",
        "      busy = true",
        "  (step 1 only shows the monitored inputs and choices of state 0, which are part of its state for the "
        "property)",
    ]
    _, out = run(capsys, "explore", str(path))
    assert block(out, "ctlSpec_ack_now") == [
        "ctlSpec_ack_now (request_ack.asm:23:2) is violated -- counterexample, 1 step:"] + steps
    _, out = run(capsys, "check", str(path), "--traces", "all")
    assert block(out, "NOTE ")[1:] == steps
