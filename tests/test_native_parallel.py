"""The native engine's threaded search (explore --workers N, engine: native) gives the one-thread
search's result exactly: the same JSON and text reports, state numbers, parents, edges, violations
and traces, for 1, 2, 3 and 8 workers (8 threads on a 2-core machine: the threads' timing varies
from run to run, the result may not); the bound on its memory stops it with a partial report at the
same state for any number of workers, and its time limit at the end of a chunk, with the states
numbered as one worker numbers them."""
from __future__ import annotations

import contextlib
import ctypes
import io
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from asmcheck.cli import main
from asmcheck.explore.native import NativeExplorer, thread_unsafe
from asmcheck.props import spec_properties
from asmcheck.props.load import load_machine

from conftest import need_bench
from helpers import native_search

pytestmark = pytest.mark.engines("native")

ROOT = Path(__file__).resolve().parent.parent
SPECS = sorted((ROOT / "specs").glob("*.asm")) + sorted((ROOT / "specs" / "buggy").glob("*.asm")) + \
    sorted((ROOT / "specs" / "temporal").glob("*.asm"))
# specs the native engine refuses: --workers then runs the partitioned search in Python
NOT_NATIVE: set = set()


def cli(*args) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main([str(a) for a in args])
    return code, out.getvalue()


def report(*args, workers: int) -> tuple[int, dict]:
    code, out = cli("explore", *args, "--format", "json", "--workers", workers)
    doc = json.loads(out)
    doc.pop("seconds"), doc.pop("compile_seconds")
    return code, doc


def text(*args, workers: int) -> tuple[int, list]:
    code, out = cli("explore", *args, "--workers", workers)
    lines = out.splitlines()
    first = re.sub(r", \d+\.\d+ s, ", ", ", lines[0])
    return code, [first] + lines[1:]


@pytest.mark.slow
@pytest.mark.parametrize("path", SPECS, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_the_same_json_report_for_1_2_3_and_8_workers(path, monkeypatch):
    # every level on the threads, however small (by default a level of fewer than 8 states a
    # thread runs on one)
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    code1, one = report(path, workers=1)
    assert "workers" not in one
    native = path.name not in NOT_NATIVE
    assert one["engine"] == ("native" if native else "python")
    for n in (2, 3, 8):
        code, doc = report(path, workers=n)
        assert doc.pop("workers") == n
        assert (code, doc) == (code1, one)
    # with the deadlock check and a state bound (a stop inside a level)
    code1, one = report(path, "--deadlock", "--max-states", "150", workers=1)
    code2, two = report(path, "--deadlock", "--max-states", "150", workers=2)
    two.pop("workers")
    assert (code2, two) == (code1, one)


def twin(tmp_path, t, k, bug=False) -> Path:
    bench = need_bench()
    subprocess.run([sys.executable, str(bench / "gen_swing.py"), str(t), str(k), *(["--bug"] if bug else []),
                    str(tmp_path)], capture_output=True, text=True, check=True)
    return tmp_path / f"swing_T{t}_K{k}{'_bug' if bug else ''}.asm"


@pytest.mark.parametrize("t,k,states,transitions", [(7, 16, 205, 457), (15, 32, 268, 594)])
def test_a_twin_with_its_bug_gives_the_same_trace(tmp_path, t, k, states, transitions):
    path = twin(tmp_path, t, k, bug=True)
    code1, one = text(path, workers=1)
    assert code1 == 1
    assert one[0] == f"{path.name}: {states:,} states, {transitions:,} transitions, depth 14, native engine"
    # the shortest counterexample: 13 steps from the initial state
    assert any(line.startswith("inv_exclusive") and "13 steps" in line for line in one), one
    for n in (2, 3, 8):
        code, lines = text(path, workers=n)
        assert code == 1
        assert lines[0] == one[0] + f", {n} workers"
        assert lines[1:] == one[1:]
    _, j1 = report(path, workers=1)
    assert len(j1["violations"][0]["trace"]) == 14
    for n in (2, 3, 8):
        _, doc = report(path, workers=n)
        assert doc.pop("workers") == n
        assert doc == j1


def explore(path, workers, **kw):
    r, ex, parents, states = native_search(path, workers, **kw)
    edges = None if ex.edge_src is None else (list(ex.edge_src), list(ex.edge_dst))
    return (r.verdict, r.states, r.transitions, r.depth, r.reason,
            [(v.prop.name, v.state) for v in r.violations]), parents, states, edges


def test_state_numbers_parents_and_edges_do_not_depend_on_the_workers(tmp_path):
    path = twin(tmp_path, 15, 32)
    one = explore(path, 1, keep_graph=True)
    assert one[0] == ("holds", 38403, 111252, 426, "", [])
    assert len(one[3][0]) == 111252
    for n in (2, 3, 4, 8):
        assert explore(path, n, keep_graph=True) == one
    # a state bound stops inside a level: the same states, numbered alike
    cut = explore(path, 1, max_states=20000, deadlock=True)
    assert cut[0][:5] == ("incomplete", 20000, cut[0][2], cut[0][3], "state limit 20000 reached")
    assert explore(path, 2, max_states=20000, deadlock=True) == cut
    assert cut[1] == one[1][:20000] and cut[2] == one[2][:20000]


def test_the_memory_bound_stops_at_the_same_state_for_any_number_of_workers(tmp_path):
    path = twin(tmp_path, 15, 32)
    # 300,000 bytes of tables: 12 bytes a state (one word and a parent) and the hash table
    one = explore(path, 1, table_memory=300_000)
    assert one[0] == ("incomplete", 12288, 35306, 142, "memory limit 0.3 MB of tables reached", [])
    for n in (2, 3, 8):
        assert explore(path, n, table_memory=300_000) == one


def test_the_memory_limit_gives_a_partial_report_and_exit_3(tmp_path):
    path = twin(tmp_path, 15, 32)
    # the process holds more than 1 MB before the search: the tables may grow no more
    for n in (1, 2):
        code, lines = text(path, "--max-memory", "1M", workers=n)
        assert code == 3
        assert lines[0] == "swing_T15_K32.asm: 3 states, 2 transitions, depth 1, native engine" + \
            (f", {n} workers" if n > 1 else "")
        assert "incomplete: memory limit 1 MB reached" in lines
        assert lines[-1] == "verdict: incomplete"


GROWING_SEQUENCES = """asm SeqGrow
import StandardLibrary
signature:
	dynamic controlled q: Seq(Integer)
definitions:
	invariant inv_short over q: length(q) <= 5
	main rule r_main =
		choose $x in {1, 2, 3} with true do
			if length(q) < 5 then q := append(q, $x) else q := tail(q) endif
default init s0:
	function q = []
"""


def test_values_made_during_the_search_are_numbered_as_on_one_thread(tmp_path):
    # every level makes new sequences: the threads may not add to the value table, so such a
    # chunk is expanded again on one thread
    path = tmp_path / "SeqGrow.asm"
    path.write_text(GROWING_SEQUENCES)
    code1, one = report(path, "--deadlock", workers=1)
    assert one["engine"] == "native"
    assert (one["states"], one["transitions"], one["depth"]) == (364, 606, 5)
    for n in (2, 4):
        code, doc = report(path, "--deadlock", workers=n)
        doc.pop("workers")
        assert (code, doc) == (code1, one)
    assert explore(path, 2) == explore(path, 1)
    # both ways were taken: level 3 makes new sequences (sent back to one thread), level 5 none
    spec, m = load_machine(str(path), {})
    sp, stp = spec_properties(m)
    ex = NativeExplorer(m, state_props=sp, step_props=stp, workers=2)
    ex.thread_stats()
    ex.run()
    stats = ex.thread_stats()
    assert (stats["serial_chunks"], stats["parallel_chunks"]) == (1, 1)


def test_workers_with_engine_native_and_what_stays_python(tmp_path):
    path = twin(tmp_path, 7, 16)
    code, lines = text(path, "--engine", "native", workers=2)
    assert code == 0 and lines[0] == "swing_T7_K16.asm: 5,571 states, 14,404 transitions, depth 218, native engine, " \
                                     "2 workers"
    # --graph on the threads: the same report and the same graph as one worker
    one_dot, two_dot, py_dot = tmp_path / "one.dot", tmp_path / "two.dot", tmp_path / "py.dot"
    code1, one = report(path, "--graph", one_dot, workers=1)
    code, doc = report(path, "--graph", two_dot, workers=2)
    assert one["engine"] == doc["engine"] == "native" and doc.pop("workers") == 2
    assert (code, doc) == (code1, one) and two_dot.read_text() == one_dot.read_text()
    # the partitioned search on the Python step function (--engine python): the same counts,
    # verdicts and graph
    code, doc = report(path, "--graph", py_dot, "--engine", "python", workers=2)
    assert doc["engine"] == "python" and doc.pop("workers") == 2
    assert code == code1 and py_dot.read_text() == one_dot.read_text()
    assert {k: doc[k] for k in ("states", "transitions", "depth", "verdict", "properties")} == \
        {k: one[k] for k in ("states", "transitions", "depth", "verdict", "properties")}


def test_code_that_keeps_state_in_shared_variables_runs_on_one_thread(tmp_path):
    # a scratch buffer or a cache that lives as long as the library would be shared by the threads
    assert thread_unsafe("static V buf[1 << 16]; static int n = 0; static V a[4], b[4]; static volatile int f;\n"
                         "static V g(Ctx *c) { static uint32_t gen = 0; return 0; }") == ["a", "buf", "f", "gen", "n"]
    assert thread_unsafe("static _Thread_local V buf[8]; static const V T[] = {1}; static inline V h(Ctx *c);\n"
                         "static V g(Ctx *c); static uint64_t *states = 0;") == []
    # the generated code of the twin has none: its levels are expanded on the threads
    path = twin(tmp_path, 15, 32)
    spec, m = load_machine(str(path), {})
    sp, stp = spec_properties(m)
    ex = NativeExplorer(m, state_props=sp, step_props=stp, workers=2)
    assert ex.thread_unsafe == []
    ex.thread_stats()
    assert ex.run().states == 38403
    stats = ex.thread_stats()
    assert stats["serial_chunks"] == 0 and stats["parallel_chunks"] > 300
    # with such a variable the search runs on one thread, and says so
    ex = NativeExplorer(m, state_props=sp, step_props=stp, workers=2)
    ex.thread_unsafe = ["buf"]
    ex.thread_stats()
    r = ex.run()
    assert (r.states, r.workers, ex.thread_stats()["parallel_chunks"]) == (38403, 1, 0)
    assert ex.warnings == ["the native search runs on one thread, not 2: its C code keeps state in variables the "
                           "threads would share (buf)"]


# elements made by extend (canonical names), a monitored input and a counter
EXTEND = """asm Rep
import StandardLibrary
signature:
	dynamic abstract domain D
	dynamic controlled cur: D
	dynamic controlled other: D
	dynamic controlled started: Boolean
	dynamic controlled n: Integer
	dynamic monitored flip: Boolean
definitions:
	invariant inv_n over n: n < 4
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
				if flip then
					par
						cur := other
						other := cur
					endpar
				else
					extend D with $c do
						cur := $c
				endif
				if n < 5 then n := n + 1 endif
			endpar
		endif
default init s0:
	function started = false
	function n = 0
"""


def test_extend_made_elements_give_the_same_report_for_any_number_of_workers(tmp_path, monkeypatch):
    # whichever engine runs it (the Python engine while the native one refuses extend), the
    # report with 2 and 3 workers is that of one
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    path = tmp_path / "Rep.asm"
    path.write_text(EXTEND)
    code1, one = report(path, "--deadlock", workers=1)
    assert one["verdict"] == "violated" and one["violations"][0]["property"] == "inv_n"
    for n in (2, 3, 8):
        code, doc = report(path, "--deadlock", workers=n)
        assert doc.pop("workers") == n
        assert (code, doc) == (code1, one)


CLASH = """asm Clash
import StandardLibrary
import CTLLibrary
signature:
	dynamic controlled x: Integer
	dynamic monitored go: Boolean
definitions:
	CTLSPEC ag(x < 4)
	main rule r_main =
		par
			if x < 4 then x := x + 1 endif
			if go and x = 2 then x := 0 endif
		endpar
default init s0:
	function x = 0
"""


def test_a_search_that_ends_on_a_run_time_error_gives_the_report_of_one_worker(tmp_path):
    # the native search goes on past a run-time error; with workers too (the threaded search), the
    # report is that of one worker (the error's trace, the CTL verdict relative to the error)
    path = tmp_path / "Clash.asm"
    path.write_text(CLASH)
    code1, one = report(path, workers=1)
    assert code1 == 1 and one["engine"] == "native"
    assert [(r["property"], r["verdict"]) for r in one["properties"]] == [("error", "violated"), ("ctl_1", "violated")]
    code2, two = report(path, workers=2)
    two.pop("workers", None)
    assert (code2, two) == (code1, one)
    # the partitioned search on the Python engine sends the error, recorded in a worker process,
    # to the coordinator (it once failed to unpickle it): the same error and trace
    code3, three = report(path, "--engine", "python", workers=2)
    assert code3 == 1 and three["violations"][0] == one["violations"][0]


@pytest.mark.parametrize("t,k,states,transitions,depth", [(7, 16, 5571, 14404, 218), (15, 32, 38403, 111252, 426)])
def test_twins_give_the_same_json_report_for_any_number_of_workers(tmp_path, monkeypatch, t, k, states, transitions,
                                                                    depth):
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    path = twin(tmp_path, t, k)
    code1, one = report(path, "--deadlock", workers=1)
    assert (code1, one["states"], one["transitions"], one["depth"], one["verdict"]) == \
        (0, states, transitions, depth, "holds")
    for n in (2, 3, 8, 2, 8):       # twice: the threads' timing differs from run to run
        code, doc = report(path, "--deadlock", workers=n)
        assert doc.pop("workers") == n
        assert (code, doc) == (code1, one)


def stats_of(path, workers, **kw):
    spec, m = load_machine(str(path), {})
    sp, stp = spec_properties(m)
    ex = NativeExplorer(m, state_props=sp, step_props=stp, workers=workers, **kw)
    ex.adapt = False                 # every slice on the threads, however busy the machine
    ex.thread_stats()
    r = ex.run()
    return r, ex.thread_stats()


def test_two_barriers_a_chunk_and_nothing_walked_when_nothing_needs_recording(tmp_path):
    path = twin(tmp_path, 15, 32)
    r, st = stats_of(path, 2)
    assert (r.states, r.transitions) == (38403, 111252)
    chunks = st["parallel_chunks"]
    assert chunks > 300 and st["serial_chunks"] == 0 and st["walked_chunks"] == 0
    # the table grows inside chunks (the threads meet three to five times more each time)
    growths = st["table_growths"]
    assert growths >= 1
    # two barriers a chunk, and a few more where thread 0 takes over (small levels on one
    # thread, the end of a slice)
    assert 2 * chunks + 3 * growths < st["barriers"] < 2 * chunks + 5 * growths + 60, st
    # a violation: the chunks where something is recorded are walked by thread 0 in order
    bug = twin(tmp_path, 15, 32, bug=True)
    r, st = stats_of(bug, 2)
    assert (r.states, r.verdict) == (268, "violated")
    assert st["walked_chunks"] >= 1


def test_a_time_limit_stops_at_the_end_of_a_chunk_with_the_states_numbered_as_on_one_thread(tmp_path):
    path = twin(tmp_path, 63, 250)
    for n in (2, 8):
        code, lines = text(path, "--max-seconds", "0.2", workers=n)
        assert code == 3
        assert "incomplete: time limit 0.2 s reached" in lines and lines[-1] == "verdict: incomplete"
    spec, m = load_machine(str(path), {})
    sp, stp = spec_properties(m)
    part = NativeExplorer(m, state_props=sp, step_props=stp, workers=2, max_seconds=0.2)
    r = part.run()
    assert r.verdict == "incomplete" and r.reason == "time limit 0.2 s reached" and 0 < r.states < 4245995
    n = r.states
    # the states kept are those one worker numbers first, with the same parents
    full = NativeExplorer(m, state_props=sp, step_props=stp, workers=1, max_states=n)
    assert full.run().states >= n
    pa, pb = (ctypes.c_int64 * full.nstates)(), (ctypes.c_int64 * n)()
    full.dll.asm_parents(pa)
    part.dll.asm_parents(pb)
    assert list(pa)[:n] == list(pb)
    wa, wb = (ctypes.c_uint64 * part.gen.nwords)(), (ctypes.c_uint64 * part.gen.nwords)()
    for i in range(0, n, 97):
        full.dll.asm_state(i, wa)
        part.dll.asm_state(i, wb)
        assert list(wa) == list(wb)


def test_levels_cut_into_chunks_give_the_same_numbers_parents_and_edges(tmp_path, monkeypatch):
    # a level of more states than a chunk holds (65,536; here 37) is expanded chunk after chunk:
    # the new states of a chunk are numbered after those of the chunks before it
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    monkeypatch.setenv("ASMCHECK_THREAD_MAX_CHUNK", "37")
    path = twin(tmp_path, 15, 32)
    one = explore(path, 1, keep_graph=True)
    assert one[0] == ("holds", 38403, 111252, 426, "", [])
    for n in (2, 3, 8):
        assert explore(path, n, keep_graph=True) == one
        assert explore(path, n) == explore(path, 1)
    cut = explore(path, 1, max_states=20000, deadlock=True)
    assert cut[0][1] == 20000
    for n in (2, 8):
        assert explore(path, n, max_states=20000, deadlock=True) == cut
    r, st = stats_of(path, 2)
    assert r.states == 38403 and st["parallel_chunks"] > 38403 // 37 and st["serial_chunks"] == 0


# many successors a state, most of them equal (the distinct ones counted in a set)
MANY = """asm Many
import StandardLibrary
signature:
	dynamic controlled x: Integer
	dynamic controlled n: Integer
definitions:
	invariant inv_small over x: x < 50
	main rule r_main =
		choose $i in {0 : 40} with true do
			if n < 7 then
				par
					x := x + $i mod 9
					n := n + 1
				endpar
			endif
default init s0:
	function x = 0
	function n = 0
"""


def test_states_with_many_equal_successors_give_the_same_report(tmp_path, monkeypatch):
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    path = tmp_path / "Many.asm"
    path.write_text(MANY)
    for extra in ((), ("--deadlock",)):
        code1, one = report(path, *extra, workers=1)
        assert one["engine"] == "native"
        for n in (2, 3, 8):
            code, doc = report(path, *extra, workers=n)
            assert doc.pop("workers") == n
            assert (code, doc) == (code1, one)
    assert explore(path, 2) == explore(path, 1)


@pytest.mark.parametrize("name", ["LOTS", "ABSORB", "AFTER", "IN_SEQ", "AGENTS"])
def test_merged_chooses_give_the_same_report_for_any_number_of_workers(tmp_path, monkeypatch, name):
    # the combinations of merged chooses a run of the step ends with are written by each thread
    # into its own buffer (mc_tail), as one worker writes them
    import test_native_choose_merge as merged
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    src = getattr(merged, name)
    path = tmp_path / f"{src.split()[1]}.asm"
    path.write_text(src)
    for extra in ((), ("--deadlock",)):
        code1, one = report(path, *extra, workers=1)
        assert one["engine"] == "native"
        for n in (2, 3, 8):
            code, doc = report(path, *extra, workers=n)
            assert doc.pop("workers") == n
            assert (code, doc) == (code1, one)
