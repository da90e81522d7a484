"""The native explorer against the Python one on small specs that use what the native engine
translates beyond finite flat locations: Integer locations, seq blocks and loops, agents and
program(), sequences, step properties and run-time errors.  Each spec runs on both engines
(pinned with --engine); the JSON reports must be equal apart from the engine and the time."""
import json

import pytest

from asmcheck.cli import main
from asmcheck.explore.native_build import compiler
from helpers import both, write

pytestmark = pytest.mark.engines("native")

SEQS = """asm Seqs
import StandardLibrary
signature:
	enum domain Phase = {PA | PB | PC}
	controlled x: Integer
	controlled y: Integer
	controlled q: Seq(Phase)
	controlled done: Boolean
	monitored go: Boolean
definitions:
	invariant inv_short over q: length(q) < 4
	main rule r_main =
		if not done then
			seq
				x := x + 1
				y := x * 2
				if go then q := append(q, PA) else q := append(q, at([PB, PC], iton(x mod 2))) endif
				if x >= 3 then done := true endif
			endseq
		else
			while x > 0 do x := x - 1
		endif
default init s0:
	function x = 0
	function y = 0
	function q = []
	function done = false
"""

AGENTS = """asm Agents
import StandardLibrary
signature:
	domain Worker subsetof Agent
	controlled count: Worker -> Integer
	controlled last: Worker
	controlled total: Integer
	static w1: Worker
	static w2: Worker
definitions:
	rule r_work =
		par
			count(self) := (count(self) + 1) mod 3
			last := self
		endpar
	invariant inv_total over total: total <= 4
	main rule r_main =
		seq
			choose $w in Worker with true do program($w)
			total := count(w1) + count(w2)
		endseq
default init s0:
	function count($w in Worker) = 0
	function total = 0
	agent Worker: r_work[]
"""

CLASH = """asm Clash
import StandardLibrary
signature:
	controlled x: Integer
	controlled y: Integer
	monitored m: Boolean
definitions:
	main rule r_main =
		par
			seq
				x := 1
				x := x + 1
			endseq
			if m then y := x + 5 else iterate if y < 3 then y := y + 1 endif enditerate endif
			if y = 3 and x = 2 then x := 7 endif
		endpar
default init s0:
	function x = 0
	function y = 0
"""

TABLE = """asm Table
import StandardLibrary
signature:
	controlled f: Integer -> Integer
	controlled n: Integer
	monitored b: Boolean
definitions:
	invariant inv_small over f: f(3) != 99
	main rule r_main =
		if n < 4 then
			par
				n := n + 1
				seq
					f(n) := n * 2
					f(n + 1) := f(n) + 1
				endseq
				if b then f(0) := n endif
			endpar
		else
			par
				f(n) := 9
				if b then f(4) := 8 endif
			endpar
		endif
default init s0:
	function n = 0
"""

STEPS = """step stp_w2_never_moves_last: not updatedBy(w2, last)
step stp_total_changes: changed(total) or next(total) = total
"""




def ends_on_error(tmp_path, capsys, text):
    """A spec whose search meets a failing step: the native search finds the same first error
    (message and trace) as the Python engine and, as it does, keeps the well-defined successors of
    a failing state: the same report."""
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.explore.trace import build_trace
    from asmcheck.props.load import load_machine
    from asmcheck.report.trace import trace_json
    path = write(tmp_path, text)
    code_n = main(["explore", path, "--format", "json", "--engine", "native"])
    handed = json.loads(capsys.readouterr().out)
    # the native engine itself goes on past the failing step (tests/test_native_errors.py)
    assert (handed.pop("engine"), handed.pop("engine_note", None)) == ("native", None)
    handed.pop("compile_seconds")
    code = main(["explore", path, "--format", "json", "--engine", "python"])
    out = json.loads(capsys.readouterr().out)
    for doc in (handed, out):
        doc.pop("seconds")
    assert (code_n, handed) == (code, {k: x for k, x in out.items() if k not in ("engine", "compile_seconds")})
    _, m = load_machine(path)
    nat = NativeExplorer(m)
    (v,) = [v for v in nat.run().violations if v.prop.name == "error"]
    (py,) = [x for x in out["violations"] if x["property"] == "error"]
    assert v.message == py["message"]
    assert trace_json(m, build_trace(nat, v)) == py["trace"]
    for key in ("compile_seconds", "engine"):
        out.pop(key, None)
    return code, out


def test_integers_seq_blocks_loops_and_sequences(tmp_path, capsys):
    code, out = both(tmp_path, capsys, SEQS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (0, "holds", 23, 30, 4)


def test_agents_and_a_step_property_with_updated_by(tmp_path, capsys):
    prop = tmp_path / "steps.prop"
    prop.write_text(STEPS)
    code, out = both(tmp_path, capsys, AGENTS, "--properties", str(prop))
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 19, 38, 5)
    (v,) = out["violations"]
    assert v["property"] == "stp_w2_never_moves_last" and v["kind"] == "step"
    assert [s["state"] for s in v["trace"]] == [
        {"count(w1)": 0, "count(w2)": 0, "total": 0},
        {"count(w1)": 0, "count(w2)": 1, "last": "w2", "total": 1}]


def test_a_clash_between_a_seq_block_and_its_sibling_is_a_violation_with_its_trace(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, CLASH)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 4, 5, 2)
    (v,) = out["violations"]
    assert (v["property"], v["message"]) == ("error", "inconsistent update of x: 2 and 7")
    assert [s["state"] for s in v["trace"]] == [{"x": 0, "y": 0}, {"x": 2, "y": 3}]


def test_a_function_over_the_integers_is_held_as_a_map(tmp_path, capsys):
    # f(n) and f(n + 1) in a seq block, f(0) beside it, and a clash of f(4) := 9 with f(4) := 8
    code, out = ends_on_error(tmp_path, capsys, TABLE)
    # the failing state's well-defined successors (b false) are explored too
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 15, 21, 5)
    assert out["properties"][0] == {"property": "inv_small", "kind": "invariant", "verdict": "holds",
                                    "relative_to": f"{tmp_path / 'Table.asm'}:22:15"}
    (v,) = out["violations"]
    assert (v["property"], v["message"], len(v["trace"])) == ("error", "inconsistent update of f(4): 9 and 8", 5)
    assert v["trace"][-1]["state"] == {"f(0)": 0, "f(1)": 2, "f(2)": 4, "f(3)": 6, "f(4)": 7, "n": 4}
