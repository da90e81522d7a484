"""The native engine's packed store (native_bfs.c: one thread keeps each state as the dictionary
codes of its words, in bit fields that widen as the dictionaries grow) gives the plain store's
result exactly: the same states in the same numbering, parents, transitions, decoded words,
look-ups and traces, and the Python engine's report; the threaded search keeps the plain store.
Speed and memory are measured by benchmarks/bench_native.py, not here."""
from __future__ import annotations

import pytest

from asmcheck.explore.native_build import compiler
from helpers import both, engine_free, native_search, write

pytestmark = pytest.mark.engines("native")

# seven words a state (six Integer locations, one word of narrow ones): the packed store is used
COUNTERS = """asm PackedCounters
import StandardLibrary
signature:
	enum domain Mode = {IDLE | BUSY | DONE}
	controlled a: Integer
	controlled b: Integer
	controlled c: Integer
	controlled d: Integer
	controlled e: Integer
	controlled f: Integer
	controlled mode: Mode
	monitored up: Boolean
definitions:
	invariant inv_small over a, b: a + b < 8
	main rule r_main =
		par
			if up then a := (a + 1) mod 5 else b := (b + 2) mod 6 endif
			c := (c + a) mod 3
			if a = 3 then d := (d + 1) mod 2 endif
			f := b * 1000000 - 7
			if mode = IDLE then mode := BUSY else if a = 0 then mode := IDLE endif endif
		endpar
default init s0:
	function a = 0
	function b = 0
	function c = 0
	function d = 0
	function e = 100
	function f = 0
	function mode = IDLE
"""

# n takes 70,001 values: its dictionary outgrows 1, 2, 4, ... 32 bits, then the word is kept
# as it is (more than 65,536 values); k1 takes 35,001, m 1,000, the rest one each
GROWTH = """asm PackedGrowth
import StandardLibrary
signature:
	controlled n: Integer
	controlled m: Integer
	controlled k1: Integer
	controlled k2: Integer
	controlled k3: Integer
	controlled k4: Integer
definitions:
	main rule r_main =
		if n < 70000 then
			par
				n := n + 1
				m := (n * 7) mod 1000
				if n mod 2 = 0 then k1 := k1 + 3 endif
			endpar
		endif
default init s0:
	function n = 0
	function m = 0
	function k1 = 0
	function k2 = 5
	function k3 = 6
	function k4 = 7
"""


def need_cc():
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")


def run(path, packed=True, workers=1, **kw):
    """(result, explorer, parents, words of every state, words a stored state takes (-1: plain))."""
    r, ex, parents, states = native_search(path, workers, packed, **kw)
    return r, ex, parents, states, ex.dll.asm_packed_words()


def summary(r):
    return (r.verdict, r.states, r.transitions, r.depth, [(v.prop.name, v.state) for v in r.violations])


def test_the_packed_store_gives_the_python_engines_report(tmp_path, capsys):
    code, out = both(tmp_path, capsys, COUNTERS)
    assert code == 1
    assert (out["states"], out["transitions"], out["depth"]) == (91, 126, 7)
    (v,) = out["violations"]
    assert v["property"] == "inv_small"
    # the shortest trace: a to 4 (four steps) and b to 4 (two), from the initial state
    assert len(v["trace"]) == 7
    code, out = both(tmp_path, capsys, COUNTERS, "--deadlock")
    assert (out["states"], out["transitions"]) == (217, 434)     # on after the violation: all of it


def test_packed_and_plain_stores_number_the_states_alike(tmp_path):
    need_cc()
    path = write(tmp_path, COUNTERS)
    r1, ex1, par1, st1, pw1 = run(path, packed=True)
    r0, ex0, par0, st0, pw0 = run(path, packed=False)
    assert ex1.gen.nwords == 7
    assert pw1 == 1 and pw0 == -1           # 7 words in one
    assert summary(r1) == summary(r0)
    assert summary(r0)[:4] == ("violated", 91, 126, 7) and [v.prop.name for v in r0.violations] == ["inv_small"]
    assert par1 == par0 and st1 == st0
    # every state found again from its Python form, and the path to it
    for sid in range(r1.states):
        assert ex1.find(ex1.state(sid)) == sid
    assert ex1.path_to(90) == ex0.path_to(90)
    # the threaded search keeps the plain store: the same numbering
    r2, ex2, par2, st2, pw2 = run(path, packed=True, workers=2)
    assert pw2 == -1
    assert summary(r2) == summary(r1) and par2 == par1 and st2 == st1


def test_a_dictionary_that_outgrows_its_field_widens_it_and_then_keeps_the_word(tmp_path):
    need_cc()
    path = write(tmp_path, GROWTH)
    r1, ex1, par1, st1, pw1 = run(path, packed=True)
    r0, ex0, par0, st0, pw0 = run(path, packed=False)
    assert summary(r1) == summary(r0) == ("holds", 70001, 70001, 70000, [])
    # n kept as it is (64 bits), k1 in 32, m in 16 (with room for three times as many values
    # again), the three constants in none: two words instead of six
    assert ex1.gen.nwords == 6 and pw1 == 2
    assert par1 == par0 == [-1] + list(range(70000))
    assert st1 == st0
    last = ex1.state(70000)
    assert ex1.find(last) == 70000 and ex1.find(ex1.state(12345)) == 12345


# ----------------------------------------------------------------- the working state kept
def checked_explore(monkeypatch, capsys, args):
    """``explore --format json ARGS`` on the native engine with every delta load of the working
    state (asm_run decodes again only the slots of the words that differ from the state expanded
    before) compared with a whole load: (exit code, report, differences counted)."""
    import json
    from asmcheck.cli import main
    from asmcheck.explore.native import NativeExplorer
    need_cc()
    diffs = []
    orig = NativeExplorer.run

    def run(self):
        self.dll.asm_check_loads(1)
        try:
            return orig(self)
        finally:
            diffs.append(self.dll.asm_load_differences())

    monkeypatch.setattr(NativeExplorer, "run", run)
    code = main(["explore", *args, "--format", "json", "--engine", "native"])
    out = json.loads(capsys.readouterr().out)
    monkeypatch.setattr(NativeExplorer, "run", orig)
    return code, out, diffs


def test_the_working_state_kept_from_state_to_state_is_a_whole_load(tmp_path, capsys, monkeypatch):
    from test_native_errors import LOCALS, SEQ_LEAK
    # seq blocks whose runs fail half-way (the working state then loaded again), local functions
    # (their slots set in a run and restored), the packed store: no delta load differs from a
    # whole one, and the reports are the Python engine's
    for text, counts in ((SEQ_LEAK, (4, 4)), (LOCALS, (5, 5)), (COUNTERS, (91, 126))):
        path = write(tmp_path, text)
        code, out, diffs = checked_explore(monkeypatch, capsys, [path])
        assert diffs and set(diffs) == {0}
        assert (out["states"], out["transitions"]) == counts
        code2, out2 = both(tmp_path, capsys, text)
        assert (code, engine_free(out)) == (code2, out2)


@pytest.mark.corpus
def test_the_working_state_kept_on_the_rtpattern_models(capsys, monkeypatch):
    from rtpattern.rtlib import PROPS_NONDET, PROPS_SB, app, nondet_spec
    props = ["--no-default-properties"]
    for p in PROPS_SB:
        props += ["--properties", p]
    code, out, diffs = checked_explore(monkeypatch, capsys, [app("VisualServoing"), *props])
    assert set(diffs) == {0} and (out["verdict"], out["states"], out["transitions"]) == ("holds", 15710, 31420)
    # extend-made elements (canonical forms), a first search with too few element slots
    code, out, diffs = checked_explore(monkeypatch, capsys, [app("CompleteApplication"), *props])
    assert set(diffs) == {0} and (out["verdict"], out["states"], out["transitions"]) == ("holds", 70867, 141734)
    path, imp = nondet_spec("RtNondetVS")
    code, out, diffs = checked_explore(monkeypatch, capsys, [path, *props, "--properties", PROPS_NONDET[-1],
                                                              "--deadlock", *imp])
    assert set(diffs) == {0}
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == \
        (1, "violated", 132077, 392131, 81)


# ----------------------------------------------------------------- invariants checked where they may change
# x changes in every step, y only when x = 5 and go, z (read through the derived dz) only when
# x = 4 and y = 2, the cells of grid only when x = 2: each invariant is checked again in a state
# only when a location it reads differs from the parent's, and each is violated only once such a
# location changed, several steps after the last change of the others
SKIPPY = """asm Skippy
import StandardLibrary
signature:
	enum domain Side = {LEFT | RIGHT}
	domain Small subsetof Integer
	controlled x: Small
	controlled y: Small
	controlled z: Small
	controlled grid: Side -> Small
	derived dz: Integer
	monitored go: Boolean
definitions:
	domain Small = {0 : 5}
	function dz = z * 2
	invariant inv_y over y: y < 3
	invariant inv_dz over z: dz < 4
	invariant inv_grid over grid: grid(LEFT) + grid(RIGHT) < 3
	invariant inv_x over x: x >= 0
	main rule r_main =
		par
			x := (x + 1) mod 6
			if x = 5 and go then y := (y + 1) mod 6 endif
			if x = 4 and y = 2 then z := (z + 1) mod 6 endif
			if x = 2 then
				if go then grid(LEFT) := (grid(LEFT) + 1) mod 6 else grid(RIGHT) := (grid(RIGHT) + 1) mod 2 endif
			endif
		endpar
default init s0:
	function x = 0
	function y = 0
	function z = 0
	function grid($s in Side) = 0
"""


def test_invariants_are_checked_where_their_locations_change(tmp_path, capsys):
    code, out = both(tmp_path, capsys, SKIPPY)
    assert code == 1
    assert (out["states"], out["transitions"]) == (2592, 3456)
    got = {v["property"]: len(v["trace"]) for v in out["violations"]}
    # the shortest traces (states): grid(LEFT) to 3 at step 15 (x = 2 in steps 2, 8, 14), y to 3
    # at step 18 (x = 5 in steps 5, 11, 17), z to 2 at step 23 (y = 2 from step 12, x = 4 in steps
    # 16 and 22)
    assert got == {"inv_grid": 16, "inv_y": 19, "inv_dz": 24}
    code, out = both(tmp_path, capsys, SKIPPY, "--deadlock")
    assert {v["property"] for v in out["violations"]} == {"inv_grid", "inv_y", "inv_dz"}


# ----------------------------------------------------------------- the time limit while the store grows
def limited_search(path, delay, log2_piece, max_seconds):
    """The one-thread search of ``path`` with the time limit ``max_seconds``, each piece of a table
    growth or repack (2^log2_piece entries or states) followed by a pause of ``delay`` seconds, as
    on a very slow machine: (result, explorer, growths and repacks given up)."""
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.props import spec_properties
    from asmcheck.props.load import load_machine
    need_cc()
    spec, m = load_machine(str(path), {})
    sp, stp = spec_properties(m)
    ex = NativeExplorer(m, state_props=sp, step_props=stp, max_seconds=max_seconds)
    ex.dll.asm_grow_test(delay, log2_piece)
    try:
        r = ex.run()
    finally:
        ex.dll.asm_grow_test(0.0, -1)
    return r, ex, ex.dll.asm_grow_abandoned()


def stored_words(ex, n):
    import ctypes
    words = (ctypes.c_uint64 * ex.gen.nwords)()
    out = []
    for i in range(n):
        ex.dll.asm_state(i, words)
        out.append(tuple(words))
    return out


def test_a_table_growth_that_meets_the_time_limit_is_given_up(tmp_path):
    path = write(tmp_path, GROWTH)
    # the table of 1,024 entries is full at 768 states; its growth pauses longer than the limit:
    # the search stops there, with the table as it was (before, the growth went on to its end and
    # the search past it, overshooting the limit by the growth's length)
    r, ex, given_up = limited_search(path, 1.5, 18, 1.0)
    assert (r.verdict, r.states, r.transitions, given_up) == ("incomplete", 768, 767, 1)
    assert r.reason == "time limit 1.0 s reached" and r.time_limit is not None
    # the states stored are the first 768 of the whole search, each found again
    full, _, parents, states = native_search(path)
    assert full.states == 70001
    assert stored_words(ex, 768) == states[:768]
    for sid in (0, 1, 500, 767):
        assert ex.find(ex.state(sid)) == sid


def test_a_repack_that_meets_the_time_limit_is_given_up(tmp_path):
    path = write(tmp_path, GROWTH)
    # pieces of one state: the first repack (n's dictionary outgrows its field at the second
    # state) pauses past the limit and is given up; the state that needed it is not stored
    r, ex, given_up = limited_search(path, 1.5, 0, 1.0)
    assert (r.verdict, r.states, r.transitions, given_up) == ("incomplete", 1, 0, 1)
    assert r.reason == "time limit 1.0 s reached"
    assert ex.find(ex.state(0)) == 0
    assert stored_words(ex, 1) == native_search(path)[3][:1]       # the layout as it was
    # no limit: no growth is given up
    r, ex, given_up = limited_search(path, 0.0, 18, None)
    assert (r.verdict, r.states, given_up) == ("holds", 70001, 0)


# ----------------------------------------------------------------- a run that updates nothing
# go false updates nothing below 5: the state itself is a successor (taken as the expanded state's
# own number, with no record or look-up); at n = 5 the only successor sets done, then nothing more
# happens: a deadlock (only the state itself); seven Integer words, so the packed store is used
SELF_LOOPS = """asm SelfLoops
import StandardLibrary
signature:
	controlled n: Integer
	controlled k1: Integer
	controlled k2: Integer
	controlled k3: Integer
	controlled k4: Integer
	controlled k5: Integer
	controlled done: Boolean
	monitored go: Boolean
definitions:
	invariant inv_n over n: n <= 5
	main rule r_main =
		if go and n < 5 then
			par
				n := n + 1
				k1 := k1 + n
			endpar
		else
			if n = 5 and not done then done := true endif
		endif
default init s0:
	function n = 0
	function k1 = 0
	function k2 = 2
	function k3 = 3
	function k4 = 4
	function k5 = 5
	function done = false
"""


def test_a_run_that_updates_nothing_leads_to_the_state_itself(tmp_path, capsys):
    code, out = both(tmp_path, capsys, SELF_LOOPS, "--deadlock")
    assert (out["states"], out["transitions"], out["depth"]) == (7, 12, 6)
    (v,) = [v for v in out["violations"] if v["property"] == "deadlock"]
    assert len(v["trace"]) == 7            # the initial state, five steps of n, done
    path = write(tmp_path, SELF_LOOPS)
    r1, ex1, par1, st1, pw1 = run(path, packed=True, deadlock=True)
    r0, ex0, par0, st0, pw0 = run(path, packed=False, deadlock=True)
    assert pw1 >= 1 and pw0 == -1
    assert summary(r1) == summary(r0) and par1 == par0 == [-1, 0, 1, 2, 3, 4, 5] and st1 == st0
    assert [v.state for v in r1.violations if v.prop.name == "deadlock"] == [6]
