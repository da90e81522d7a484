"""The native search loop's shortcuts, each checked on small specs written for the test: exact
counts, equality with the Python engine, and what the engine does (how many times its C is
generated)."""
from pathlib import Path

import pytest

from asmcheck.explore import native_build
from asmcheck.explore.native import Generator, NativeExplorer

from helpers import engine_free, write

pytestmark = pytest.mark.engines("native")


def need_compiler():
    if native_build.compiler_command() is None:
        pytest.skip("no C compiler on this machine")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    d = tmp_path / "cache"
    monkeypatch.setenv("ASMCHECK_CACHE", str(d))
    return d


def test_a_spec_that_needs_more_element_slots_is_generated_once_on_the_next_run(tmp_path, cache, monkeypatch):
    need_compiler()
    from test_native_build import stack20
    from asmcheck.semantics.machine import Machine
    from asmcheck.semantics.resolve import check_file
    path = write(tmp_path, stack20())
    made = []
    orig = Generator.generate

    def counted(self):
        made.append(self.cn_k)
        return orig(self)
    monkeypatch.setattr(Generator, "generate", counted)

    def search():
        made.clear()
        ex = NativeExplorer(Machine(check_file(path), {}))
        try:
            r = ex.run()
            return list(made), ex.gen.cn_k, (r.verdict, r.states, r.transitions, r.depth)
        finally:
            ex.close()

    # the first search: 16 slots, stopped, generated again with 32
    assert search() == ([16, 32], 32, ("holds", 21, 21, 20))
    # the next: generated once, with 32 (the note is found before the C is generated)
    assert search() == ([32], 32, ("holds", 21, 21, 20))
    assert native_build.last_compile_seconds == 0.0
    # the note is keyed by the spec's content: an edited spec starts from 16 again
    Path(path).write_text(Path(path).read_text() + "// edited\n")
    assert search() == ([16, 32], 32, ("holds", 21, 21, 20))
    assert search() == ([32], 32, ("holds", 21, 21, 20))


# ----------------------------------------------------------------- the successor's values (make_post)
POST = """asm PostKept
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	controlled k: Small
	controlled f: Small -> Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 3}
	rule r_bad = if not go and n = 2 then k := 7 endif
	main rule r_main =
		seq
			n := (n + 1) mod 4
			if go then f(n) := (f(n) + k) mod 4 endif
			r_bad[]
			if go then k := (k + 1) mod 4 endif
		endseq
default init s0:
	function n = 0
	function k = 0
	function f($x in Small) = 0
"""
POST_PROPS = """step st_n_moves: next(n) = (n + 1) mod 4
step st_k_with_go: changed(k) implies next(k) = (k + 1) mod 4
step st_f_small: (forall $x in Small with next(f($x)) <= 3)
step st_f_only_at_n: (forall $x in Small with changed(f($x)) implies $x = next(n))
step st_k_grows: changed(k) implies next(k) > k
"""


def test_the_successors_values_kept_between_steps_are_a_whole_copy(tmp_path, capsys, monkeypatch):
    # step properties read the successor's values (post): kept from step to step, only the slots
    # the last step wrote restored; a seq block, a branch that fails (the working state loaded
    # whole again), a function of several locations: every post is what a whole copy gives, and
    # the report is the Python engine's
    from test_native_perf import checked_explore
    from helpers import both
    props = tmp_path / "post.prop"
    props.write_text(POST_PROPS)
    path = write(tmp_path, POST)
    args = [path, "--no-default-properties", "--properties", str(props)]
    code, out, diffs = checked_explore(monkeypatch, capsys, args)
    assert diffs and set(diffs) == {0}
    assert (out["states"], out["transitions"]) == (2048, 3584)
    assert [(p["property"], p["verdict"]) for p in out["properties"]][-2:] == [("st_k_grows", "violated"),
                                                                             ("error", "violated")]
    code2, out2 = both(tmp_path, capsys, POST, "--no-default-properties", "--properties", str(props))
    assert (code, engine_free(out)) == (code2, out2)


# ----------------------------------------------------------------- seq steps
SEQS = """asm SeqSteps
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled a: Small
	controlled b: Small
	controlled c: Small
	controlled d: Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 5}
	rule r_inner =
		seq
			b := (a + 1) mod 6
			a := (b + 1) mod 6
			par
				b := (b + a) mod 6
				c := (c + 1) mod 6
			endpar
		endseq
	rule r_loc =
		local x : Small [ x := c ]
		seq
			x := (x + 1) mod 6
			d := x
		endseq
	invariant inv_seen over b, d: not (b = 3 and d = 2)
	main rule r_main =
		seq
			a := (a + 1) mod 6
			if go then r_inner[] else b := (b + a) mod 6 endif
			par
				seq
					c := (c + b) mod 6
					a := (a + c) mod 6
				endseq
				d := (d + 1) mod 6
			endpar
			r_loc[]
			iterate if a > 0 then a := a - 1 endif enditerate
			b := (a + b) mod 6
		endseq
default init s0:
	function a = 0
	function b = 0
	function c = 0
	function d = 0
"""


def test_seq_steps_nested_rewritten_iterated_and_local_make_the_python_engines_states(tmp_path, capsys):
    # the working state a seq step leaves to the next (what make_post starts from): nested blocks,
    # a location an earlier step of the block wrote written again, a par of a block and an update,
    # a local rule's block, an iterate; the same states, transitions and trace as the Python engine
    from helpers import both
    code, out = both(tmp_path, capsys, SEQS, "--deadlock")
    assert code == 1
    assert (out["states"], out["transitions"], out["depth"]) == (37, 74, 13)
    (v,) = out["violations"]
    assert v["property"] == "inv_seen" and len(v["trace"]) == 7


# ----------------------------------------------------------------- canonical forms not looked up
REWRITE = """asm Rewrite
import StandardLibrary
signature:
	dynamic abstract domain Job
	enum domain Phase = {IDLE | RUN}
	domain Tick subsetof Integer
	controlled phase: Job -> Phase
	controlled first: Job
	controlled second: Job
	controlled made: Tick
	controlled tick: Tick
	monitored go: Boolean
definitions:
	domain Tick = {0 : 3}
	main rule r_main =
		if made < 2 then
			extend Job with $j do
				par
					phase($j) := IDLE
					if made = 0 then first := $j else second := $j endif
					made := made + 1
				endpar
		else
			par
				if go then first := first
				else
					par
						first := second
						second := first
					endpar
				endif
				tick := (tick + 1) mod 4
				if tick = 3 then phase(first) := RUN endif
				if tick = 1 and phase(second) = RUN then phase(second) := IDLE endif
			endpar
		endif
default init s0:
	function made = 0
	function tick = 0
"""


def test_a_step_that_leaves_the_element_bits_as_they_were_keeps_its_state_canonical(tmp_path):
    # a step that writes an element location with the value it holds (go: first := first), no
    # element made: its successor is the expanded state's canonical form (not looked up); the
    # other steps swap the elements or change a location they key (looked up, renamed): the
    # Python engine's states, in the same order
    from test_native_extend import same_states
    assert same_states(tmp_path, REWRITE) == (16, 24, 11)


@pytest.mark.parametrize("whole_keys", [False, True], ids=["differences", "whole"])
def test_the_kept_canonical_forms_as_differences_or_whole_keys_give_the_same_states(tmp_path, monkeypatch,
                                                                                     whole_keys):
    # native_canon.c keeps a key as the low bytes of its words' differences from the first key
    # kept, and its result as those of the words that differ; or whole keys (forced here with
    # -DCN_NO_DIFF): the Python engine's states, in the same order, either way
    import os
    from test_native_extend import FOREST, QUEUE, TOKENS, same_states
    flags = os.environ.get("ASMCHECK_CFLAGS") or "-O1"
    if whole_keys:
        monkeypatch.setenv("ASMCHECK_CFLAGS", flags + " -DCN_NO_DIFF")
    assert same_states(tmp_path, FOREST) == (476, 1088, 11)
    assert same_states(tmp_path, QUEUE) == (14, 20, 9)
    assert same_states(tmp_path, TOKENS) == (43, 74, 6)
    assert same_states(tmp_path, REWRITE) == (16, 24, 11)
