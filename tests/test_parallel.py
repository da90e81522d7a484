"""The partitioned search (explore --workers N) gives the sequential search's result exactly:
counts, verdicts, state numbers, parents, choices, edges and shortest traces (engine: python)."""
from __future__ import annotations

import json
import re
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from asmcheck.props.load import load_machine as _load
from asmcheck.explore.bfs import Explorer
from asmcheck.parallel import WorkerLost, explore_partitioned, parse_workers
from asmcheck.parallel import partition as partition_module
from asmcheck.parallel.stable import StateHasher, vhash
from asmcheck.props import spec_properties
from asmcheck.props.files import properties_for
from asmcheck.report.trace import build_trace, trace_text
from asmcheck.semantics.values import SeqV, SetV

from conftest import need_bench

pytestmark = pytest.mark.engines("python")

ROOT = Path(__file__).resolve().parent.parent
SPECS = ROOT / "specs"
SMALL = ["sb_async_master.asm", "sb_sync_slave.asm", "buggy/sb_async_master_no_release.asm",
         "buggy/sb_sync_slave_clears_lock.asm", "buggy/producer_consumer_reader_takes_writer_array.asm",
         "buggy/sb_sync_master_no_watchdog.asm"]


def load(path):
    spec, m = _load(str(path), {})
    sp, stp = spec_properties(m)
    es, est, temporal = properties_for(spec, m, str(path), None, use_default=True)
    return m, sp + es, stp + est


def summary(ex, r, graph=False):
    out = {"verdict": r.verdict, "states": r.states, "transitions": r.transitions, "depth": r.depth,
           "reason": r.reason,
           "violations": [(v.prop.name, v.state, v.source, v.picks, v.message) for v in r.violations],
           "paths": [ex.path_to(v.source if v.source >= 0 else v.state) for v in r.violations],
           "traces": [trace_text(ex.m, build_trace(ex, v), False) for v in r.violations]}
    if graph:
        out["parent"] = list(ex.parent)
        out["via"] = list(ex.via)
        out["depth_of"] = list(ex.depth_of)
        out["edges"] = list(ex.edges)
    return out


def sequential(path, **kw):
    m, sp, stp = load(path)
    ex = Explorer(m, state_props=sp, step_props=stp, **kw)
    r = ex.run()
    return summary(ex, r, kw.get("keep_graph", False))


def partitioned(path, workers, backend, **kw):
    m, sp, stp = load(path)
    ex, r = explore_partitioned(m, workers=workers, backend=backend, state_props=sp, step_props=stp, **kw)
    return summary(ex, r, kw.get("keep_graph", False))


# ------------------------------------------------------------------ stable hashes
def test_stable_hashes_follow_python_equality():
    assert vhash(1) == vhash(True) and vhash(0) == vhash(False) and vhash(2.0) == vhash(2)
    assert vhash((1, "a")) == vhash(SeqV((1, "a")))
    assert vhash(SetV({1, 2, 3})) == vhash(frozenset({3, 2, 1}))
    assert vhash("a") != vhash("b") and vhash((1, 2)) != vhash((2, 1))
    h = StateHasher()
    assert h([(0, 1), ((2, (3,)), "x")]) == h([((2, (3,)), "x"), (0, 1)])


def test_stable_hashes_are_the_same_in_another_interpreter():
    code = ("from asmcheck.parallel.stable import vhash; "
            "print(vhash(('#dom', 'Task')), vhash((3, ('abc', 1.5, None))))")
    outs = {subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                           env={**os.environ, "PYTHONHASHSEED": seed}).stdout for seed in ("1", "2")}
    assert len(outs) == 1
    a, b = outs.pop().split()
    assert (int(a), int(b)) == (vhash(("#dom", "Task")), vhash((3, ("abc", 1.5, None))))


# ------------------------------------------------------------------ equal to one worker
@pytest.mark.parametrize("name", SMALL)
def test_partitioned_search_equals_the_sequential_one(name):
    ref = sequential(SPECS / name, keep_graph=True)
    for backend, n in (("inline", 1), ("inline", 2), ("inline", 3), ("inline", 8), ("processes", 2)):
        got = partitioned(SPECS / name, n, backend, keep_graph=True)
        assert got == ref, (backend, n)


def test_the_numbers_and_the_trace_of_a_step_violation():
    got = partitioned(SPECS / "buggy/sb_async_master_no_release.asm", 2, "processes")
    assert (got["verdict"], got["states"], got["transitions"], got["depth"]) == ("violated", 207, 484, 12)
    assert got["violations"] == [("stp_lock_release_on_exit", 25, 12, (0,), "")]
    assert got["paths"] == [[0, 2, 5, 12]]
    assert len(got["traces"][0]) == sequential(SPECS / "buggy/sb_async_master_no_release.asm")["traces"][0].__len__()


def test_a_state_violation_without_the_graph_walks_parents_across_owners():
    got = partitioned(SPECS / "buggy/producer_consumer_reader_takes_writer_array.asm", 3, "processes")
    assert got["violations"] == [("inv_no_concurrent_rw", 53, -1, (), "")]
    assert got["paths"] == [[0, 2, 7, 17, 32, 53]]
    assert got == sequential(SPECS / "buggy/producer_consumer_reader_takes_writer_array.asm")


@pytest.mark.parametrize("limits,expect", [
    ({"max_states": 100}, ("incomplete", 101, 149, 5, "state limit 100 reached")),
    ({"max_depth": 5, "deadlock": True}, ("incomplete", 111, 174, 5, "depth limit 5 reached")),
    ({"max_states": 1}, ("incomplete", 3, 2, 1, "state limit 1 reached")),
])
def test_limits_stop_where_the_sequential_search_stops(limits, expect):
    path = SPECS / "buggy/sb_sync_master_no_watchdog.asm"
    ref = sequential(path, **limits)
    assert (ref["verdict"], ref["states"], ref["transitions"], ref["depth"], ref["reason"]) == expect
    for backend, n in (("inline", 2), ("inline", 5), ("processes", 2)):
        assert partitioned(path, n, backend, **limits) == ref


def test_twins_equal_the_sequential_search(tmp_path):
    bench = need_bench()
    for bug, expect in ((False, ("holds", 5571, 14404, 218)), (True, ("violated", 205, 457, 14))):
        out = subprocess.run([sys.executable, str(bench / "gen_swing.py"), "7", "16"] + (["--bug"] if bug else [])
                             + [str(tmp_path)], capture_output=True, text=True, check=True)
        path = tmp_path / ("swing_T7_K16_bug.asm" if bug else "swing_T7_K16.asm")
        ref = sequential(path)
        assert (ref["verdict"], ref["states"], ref["transitions"], ref["depth"]) == expect
        assert partitioned(path, 2, "processes") == ref
        assert partitioned(path, 8, "inline") == ref
        if bug:
            # every property violated: both stop inside level 13, after the same state
            assert ref["paths"] == [[0, 1, 3, 7, 13, 21, 31, 44, 60, 78, 99, 122, 147, 175]]


# elements made by extend: the canonicaliser runs in the workers
REP = """asm Rep
import StandardLibrary
signature:
	dynamic abstract domain D
	dynamic controlled cur: D
	dynamic controlled other: D
	dynamic controlled mark: D -> Boolean
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
					mark($a) := true
					mark($b) := false
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


def test_extend_made_elements_are_canonical_in_every_worker(write_spec):
    path = write_spec(REP)
    ref = sequential(path, keep_graph=True)
    assert (ref["verdict"], ref["violations"][0][0]) == ("violated", "inv_n")
    for backend, n in (("inline", 3), ("processes", 2)):
        assert partitioned(path, n, backend, keep_graph=True) == ref


# ------------------------------------------------------------------ command line
def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "asmcheck", *args], cwd=ROOT, capture_output=True, text=True,
                          env={**os.environ, "NO_COLOR": "1"})


def without_seconds(text):
    lines = text.splitlines()
    return [re.sub(r", \d+ workers$", "", re.sub(r", \d+\.\d+ s\b", "", l)) if i == 0 else l
            for i, l in enumerate(lines)]


def test_cli_workers_prints_what_one_worker_prints():
    spec = "specs/buggy/sb_async_slave_no_recheck.asm"       # an LTL lasso: the graph is gathered
    one = run_cli("explore", spec, "--engine", "python")
    two = run_cli("explore", spec, "--workers", "2", "--engine", "python")
    assert one.returncode == two.returncode == 1
    assert two.stdout.splitlines()[0].endswith("python engine, 2 workers")
    assert without_seconds(two.stdout) == without_seconds(one.stdout)
    assert "ltlSpec_slave_leaves                     violated" in two.stdout
    j1 = json.loads(run_cli("explore", spec, "--engine", "python", "--format", "json").stdout)
    j2 = json.loads(run_cli("explore", spec, "--workers", "2", "--engine", "python", "--format", "json").stdout)
    j1.pop("seconds"), j2.pop("seconds")
    assert j2.pop("workers") == 2
    j1.pop("compile_seconds", None), j2.pop("compile_seconds", None)
    assert j1 == j2


COUNTER = """asm Counter
import StandardLibrary
signature:
	dynamic controlled n: Integer
definitions:
	invariant inv_small over n: n < 10
	main rule r_main = if n < 5 then n := n + 1 endif
default init s0:
	function n = 0
"""


def test_cli_workers_usage_errors(write_spec):
    r = run_cli("explore", "specs/sb_async_master.asm", "--workers", "0")
    assert r.returncode == 2 and "--workers expects 1 to 255 workers, not 0" in r.stderr
    r = run_cli("explore", "specs/sb_async_master.asm", "--workers", "many")
    assert r.returncode == 2 and "--workers expects a number or 'auto', not 'many'" in r.stderr
    r = run_cli("explore", write_spec(COUNTER), "--workers", "2", "--engine", "native")
    assert r.returncode == 0 and r.stdout.startswith("Counter.asm: 6 states, 6 transitions, depth 5, ")
    assert r.stdout.splitlines()[0].endswith(" s, native engine, 2 workers")
    r = run_cli("explore", write_spec(COUNTER), "--bitstate", "16", "--engine", "native")
    assert r.returncode == 2 and "drop --engine native" in r.stderr
    r = run_cli("explore", write_spec(COUNTER), "--workers", "2")
    assert r.returncode == 0 and r.stdout.startswith("Counter.asm: 6 states, 6 transitions, depth 5, ")
    assert parse_workers("auto") >= 1 and parse_workers(None) == 1


# ------------------------------------------------------------------ faults
def test_a_killed_worker_ends_the_run_with_a_clear_error():
    m, sp, stp = load(SPECS / "sb_sync_master.asm")

    def kill_second(search, depth):
        if depth == 3:
            os.kill(search.b.pids[1], signal.SIGKILL)

    with pytest.raises(WorkerLost) as e:
        explore_partitioned(m, workers=2, backend="processes", state_props=sp, step_props=stp, on_level=kill_second)
    assert "worker 2 (process" in str(e.value)
    assert "died during the search (killed by signal 9 (SIGKILL)); the search has no verdict" in str(e.value)


def test_a_worker_over_its_memory_share_ends_with_a_partial_report(monkeypatch):
    # the memory of a partition, made proportional to its states so that the stop is exact
    parts = []
    orig_init = partition_module.Partition.__init__

    def init(self, *a, **k):
        orig_init(self, *a, **k)
        parts.append(self)
    monkeypatch.setattr(partition_module.Partition, "__init__", init)
    monkeypatch.setattr(partition_module, "rss_bytes",
                        lambda: max(len(p.frozen) + len(p.pending) for p in parts) * 1000)
    m, sp, stp = load(SPECS / "sb_sync_master.asm")
    ex, r = explore_partitioned(m, workers=2, backend="inline", state_props=sp, step_props=stp,
                                memory_share=60_000)
    # worker 1 holds more than 60 states when level 6 comes in: the report covers levels 0..5,
    # the states within depth 5 (113 of 395) and the steps from levels 0..4
    assert (r.verdict, r.reason) == ("incomplete", "worker 1 went over its memory share at depth 5")
    assert (r.states, r.transitions, r.depth) == (113, 175, 5)
    rr = Explorer(m, state_props=sp, step_props=stp, max_depth=5).run()
    assert (rr.states, rr.transitions) == (113, 175)


FAN = """asm Fan
import StandardLibrary
signature:
	domain Wide subsetof Integer
	controlled x: Wide
	monitored pick: Wide
definitions:
	domain Wide = {0 : 199999}
	invariant inv_x over x: x >= 0
	main rule r_main = x := pick
default init s0:
	function x = 0
"""


def test_cli_worker_memory_gives_exit_3(write_spec):
    # 200,000 successors of the initial state: each worker adds far more than 1 MB when it takes
    # its half of level 1 (the share counts what a worker adds, not what it was forked with)
    r = run_cli("explore", write_spec(FAN), "--workers", "2", "--worker-memory", "1", "--engine", "python")
    assert r.returncode == 3, r.stderr
    assert "incomplete: worker 1 went over its memory share at depth 1" in r.stdout
    assert r.stdout.rstrip().endswith("verdict: incomplete")


def test_a_worker_forked_from_a_large_process_is_not_charged_for_its_pages(write_spec):
    """The forked workers inherit the calling process's pages (shared until written): a share of
    200 MB each is of what a worker adds.  It was charged for the caller's 300 MB and stopped at
    depth 0 with 1 state ('worker 1 went over its memory share at depth 0')."""
    import asmcheck
    ballast = b"\x01" * (300 << 20)          # resident: every page written
    run = asmcheck.load(write_spec(CLASH_ON_INPUT)).explore(workers=2, engine="python", max_memory=400 << 20)
    assert len(ballast) == 300 << 20
    assert (run.states, run.transitions, run.verdict) == (4, 4, "violated"), (run.result.reason, run.result.stop)


def test_a_time_limit_stops_at_a_level_boundary(tmp_path):
    bench = need_bench()
    subprocess.run([sys.executable, str(bench / "gen_swing.py"), "15", "32", str(tmp_path)], capture_output=True,
                   text=True, check=True)
    path = tmp_path / "swing_T15_K32.asm"          # 38,403 states: several seconds in Python
    m, sp, stp = load(path)
    ex, r = explore_partitioned(m, workers=2, backend="processes", state_props=sp, step_props=stp, max_seconds=0.5)
    assert (r.verdict, r.reason) == ("incomplete", "time limit 0.5 s reached")
    # the states of complete levels only: the count is that of a depth-bounded search
    assert r.states == Explorer(m, state_props=sp, step_props=stp, max_depth=r.depth).run().states
    out = run_cli("explore", str(path), "--workers", "2", "--max-seconds", "0.5", "--engine", "python")
    assert out.returncode == 3 and "incomplete: time limit 0.5 s reached" in out.stdout


CLASH_ON_INPUT = """asm ClashOnInput
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 3}
	invariant inv_small over n: n < 3
	main rule r_main =
		par
			if n < 3 then n := n + 1 endif
			if go and n = 1 then n := 0 endif
		endpar
default init s0:
	function n = 0
"""


@pytest.mark.parametrize("workers", [1, 2, 3])
def test_a_failing_step_gives_the_sequential_report_whatever_the_workers(write_spec, workers):
    """A step fails from n = 1 when go is true: every worker count gives the sequential report (the
    well-defined successor of n = 1 kept, the invariant broken beyond the error), from the
    partitioned search itself, with no note.  (Pickling the step's error between processes once
    crashed the run.)"""
    import asmcheck
    run = asmcheck.load(write_spec(CLASH_ON_INPUT)).explore(workers=workers, engine="python")
    assert (run.states, run.transitions, run.verdict) == (4, 4, "violated"), (run.result.reason, run.result.stop)
    assert [v.property for v in run.violations] == ["error", "inv_small"]
    assert [len(v.trace.raw.steps) - 1 for v in run.violations] == [1, 3]
    assert run.scaling_lines() == []
    assert getattr(run.result, "workers", 1) == workers


def test_a_step_error_survives_pickling():
    import pickle
    from asmcheck.errors import InconsistentUpdate, AsmRuntimeError, Span
    for err in (AsmRuntimeError(Span("a.asm", 3, 4), "boom"), InconsistentUpdate(Span("a.asm", 1, 2), "clash")):
        err.choices = [1, 2]
        back = pickle.loads(pickle.dumps(err))
        assert (type(back), back.span, back.message, str(back), back.choices) == \
            (type(err), err.span, err.message, str(err), [1, 2])
