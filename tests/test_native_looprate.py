"""The native search loop's shortcuts of the step code and of the packed store, each checked on a
small spec written for the test: exact counts, verdicts and traces, and equality with the Python
engine.

* A seq block's last step does not write its updates into the working state (the end of the block
  restores it at once): the blocks' updates still reach the steps after them.
* A successor's words are compared with its parent's only where the step updated a slot or the
  canonical form was worked out; those words drive the ranges, the invariants to check and the
  delta load of the next state expanded.
* A choose keeps its candidates in one thread-local record reached through a pointer taken once;
  the threads of a parallel search each have their own.
"""
import json

import pytest

from asmcheck.cli import main

from helpers import both, engine_free, write

pytestmark = pytest.mark.engines("native")


def need_compiler():
    from asmcheck.explore import native_build
    if native_build.compiler_command() is None:
        pytest.skip("no C compiler on this machine")


# ----------------------------------------------------------------- the last step of a seq block
LAST_STEPS = """asm LastSteps
import StandardLibrary
signature:
	domain Small subsetof Integer
	dynamic abstract domain Tok
	controlled a: Small
	controlled b: Small
	controlled c: Small
	controlled made: Small
	controlled held: Tok
	controlled tally: Small -> Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 2}
	main rule r_main =
		seq
			seq
				a := (a + 1) mod 3
				b := (a + b) mod 3
			endseq
			c := (b + c) mod 3
			if go and made < 2 then
				seq
					made := made + 1
					extend Tok with $t do held := $t
				endseq
			endif
			par
				seq
					tally(a) := b
					tally(b) := c
				endseq
				if go then b := c endif
			endpar
			if isDef(tally(c)) then a := tally(c) endif
		endseq
default init s0:
	function a = 0
	function b = 0
	function c = 0
	function made = 0
"""


def test_the_last_steps_of_seq_blocks_reach_the_steps_after_them(tmp_path, capsys):
    # nested blocks whose last step's update the outer block's next step reads (b, then c), an
    # element made in a block's last step, a block in a par whose last step writes a location the
    # par's other branch writes too, and a step after them all reading what they wrote: the Python
    # engine's states, transitions and verdicts
    code, out = both(tmp_path, capsys, LAST_STEPS, "--deadlock")
    assert code == 0
    assert (out["states"], out["transitions"], out["depth"]) == (38, 68, 10)
    assert [(p["property"], p["verdict"]) for p in out["properties"]] == [("deadlock", "holds")]


# ----------------------------------------------------------------- the words a successor changes
PACKED = """asm Packed
import StandardLibrary
signature:
	dynamic abstract domain Job
	controlled t1: Integer
	controlled t2: Integer
	controlled t3: Integer
	controlled t4: Integer
	controlled t5: Integer
	controlled t6: Integer
	controlled cur: Job
	controlled prev: Job
	controlled started: Integer
	monitored tick: Boolean
definitions:
	invariant inv_sum over t1, t2: t1 + t2 < 7
	invariant inv_t6 over t6: t6 != 2
	invariant inv_t5 over t5, t4: t5 <= t4 + 4
	main rule r_main =
		seq
			if tick then t1 := (t1 + 1) mod 4 else t2 := (t2 + 1) mod 3 endif
			if t1 = 2 and started < 3 then
				extend Job with $j do
					par
						prev := cur
						cur := $j
						started := started + 1
					endpar
			endif
			par
				t3 := (t3 + t1) mod 5
				if t3 = 4 then t6 := (t6 + 1) mod 3 endif
				if t2 = 2 then t4 := (t4 + 1) mod 2 endif
			endpar
			if t1 = 0 and t2 = 0 then prev := undef endif
		endseq
default init s0:
	function t1 = 0
	function t2 = 0
	function t3 = 0
	function t4 = 0
	function t5 = 0
	function t6 = 0
	function started = 0
"""

PACKED_PROPS = """applies to Packed

step st_t6_moves_with_t3:
	changed(t6) implies t3 = 4 or next(t3) = 4

step st_cur_made_at_t1:
	changed(cur) implies next(t1) = 2

step st_t4_small:
	next(t4) < 2

step st_t3_grows:
	next(t3) >= t3
"""


def test_the_words_a_successor_changes_drive_packing_ranges_invariants_and_loads(tmp_path, capsys, monkeypatch):
    # seven Integer locations (a word each: the packed store), an element made in a seq block (its
    # canonical form worked out, the words it may write compared), invariants reading some words
    # only (checked where those changed), step properties reading the successor: every delta load
    # of the working state is a whole load, and the report is the Python engine's
    need_compiler()
    from asmcheck.explore.native import NativeExplorer
    from test_native_perf import checked_explore
    props = tmp_path / "packed.prop"
    props.write_text(PACKED_PROPS)
    path = write(tmp_path, PACKED)
    args = ["--deadlock", "--no-default-properties", "--properties", str(props)]
    packed = []
    orig = NativeExplorer.run

    def run(self):
        try:
            return orig(self)
        finally:
            packed.append(self.dll.asm_packed_words())
    monkeypatch.setattr(NativeExplorer, "run", run)
    code, out, diffs = checked_explore(monkeypatch, capsys, [path, *args])
    assert packed and all(p > 0 for p in packed)       # (the packed store: a record of codes)
    assert diffs and set(diffs) == {0}
    assert code == 1
    assert (out["states"], out["transitions"], out["depth"]) == (1656, 3312, 21)
    assert [(p["property"], p["verdict"]) for p in out["properties"]] == [
        ("inv_sum", "holds"), ("inv_t6", "violated"), ("inv_t5", "holds"), ("st_t6_moves_with_t3", "holds"),
        ("st_cur_made_at_t1", "holds"), ("st_t4_small", "holds"), ("st_t3_grows", "violated"), ("deadlock", "holds")]
    assert [len(v["trace"]) for v in out["violations"]] == [4, 7]
    code2, out2 = both(tmp_path, capsys, PACKED, *args)
    assert (code, engine_free(out)) == (code2, out2)


# ----------------------------------------------------------------- chooses' thread-local records
CHOOSES = """asm Chooses
import StandardLibrary
signature:
	domain Cell subsetof Integer
	controlled v: Cell -> Cell
	controlled last: Cell
	monitored m: Boolean
definitions:
	domain Cell = {0 : 3}
	main rule r_main =
		if m then
			choose $i in Cell, $j in Cell with $i < $j and v($i) > v($j) do
				par
					v($i) := v($j)
					v($j) := v($i)
				endpar
		else
			par
				choose $k in Cell with v($k) = last do last := (v($k) + 1) mod 4
				choose $x in {$y in Cell | v($y) > 1 : $y} with $x != last do v($x) := (v($x) + 3) mod 4
			endpar
		endif
default init s0:
	function v($c in Cell) = 3 - $c
	function last = 0
"""

# the same with one choose in the else branch
CHOOSES1 = CHOOSES.replace("asm Chooses", "asm Chooses1").replace("""			par
				choose $k in Cell with v($k) = last do last := (v($k) + 1) mod 4
				choose $x in {$y in Cell | v($y) > 1 : $y} with $x != last do v($x) := (v($x) + 3) mod 4
			endpar
""", """			choose $x in {$y in Cell | v($y) > 1 : $y} with $x != last do
				par
					v($x) := (v($x) + 3) mod 4
					last := $x
				endpar
""")


@pytest.mark.parametrize("text, counts", [
    (CHOOSES1, (86, 181, 4)),    # one choose a run: candidates over constant ranges, and over a set built in the state
    (CHOOSES, (70, 230, 4)),     # two chooses a run: merged by their effects
], ids=["kept-candidates", "merged"])
def test_chooses_after_a_monitored_choice_on_one_thread_and_two(tmp_path, capsys, monkeypatch, text, counts):
    # the choose is reached after the choice of a monitored value (its candidates are listed again
    # in every run); with every level on the threads, each thread fills its own record: the same
    # report on one thread, two threads and the Python engine
    code, out = both(tmp_path, capsys, text, "--deadlock")
    assert code == 1
    assert (out["states"], out["transitions"], out["depth"]) == counts
    assert [(p["property"], p["verdict"]) for p in out["properties"]] == [("deadlock", "violated")]
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    path = write(tmp_path, text)
    code2 = main(["explore", path, "--format", "json", "--engine", "native", "--workers", "2", "--deadlock"])
    out2 = json.loads(capsys.readouterr().out)
    assert out2.pop("workers", 1) == 2
    assert (code2, engine_free(out2, "native")) == (code, out)
