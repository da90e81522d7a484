"""The partitioned search on the native engine's compiled step function (the native expander):
the same states, numbers, parents, choices, edges, verdicts and traces as the sequential search,
in simulated workers, forked worker processes and Ray actors; a spec the native engine refuses
runs on the Python expander, and the report says which ran.  The Ray tests skip without Ray."""
from __future__ import annotations

import functools
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from asmcheck.explore.bfs import Explorer
from asmcheck.parallel import Recipe, WorkerLost, explore_partitioned
from asmcheck.parallel import partition as partition_module
from asmcheck.parallel.expand import PythonExpander
from asmcheck.parallel.native_expand import NativeExpander, Refused

from conftest import need_bench
from test_parallel import REP, SPECS, load, sequential, summary

pytestmark = pytest.mark.engines("native")

ROOT = Path(__file__).resolve().parent.parent
SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))


@pytest.fixture(autouse=True)
def need_compiler():
    from asmcheck.explore.native_build import compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native expander cannot run here")


def native(path, workers, backend, **kw):
    m, sp, stp = load(path)
    ex, r = explore_partitioned(m, workers=workers, backend=backend, state_props=sp, step_props=stp,
                                expander="native", **kw)
    assert (r.engine, r.native_refused) == ("native", "")
    return summary(ex, r, kw.get("keep_graph", False))


ALL_SPECS = sorted(str(p.relative_to(SPECS)) for p in SPECS.rglob("*.asm"))


@functools.lru_cache(maxsize=None)
def reference(name: str, keep_graph: bool) -> dict:
    """The sequential search's summary of specs/NAME, made once per test process for the tests
    that compare the worker processes and the actors of every spec with it (compared, never
    changed)."""
    return sequential(SPECS / name, keep_graph=keep_graph)


@pytest.mark.parametrize("name", ALL_SPECS)
def test_native_expander_in_worker_processes_gives_the_sequential_graph(name):
    """specs/: every state number, parent, choice and edge as the sequential Python search."""
    assert native(SPECS / name, 2, "processes", keep_graph=True) == reference(name, True)


# values of the value table: a sequence, a set of sequences, a string, a tuple and a function over
# an infinite domain (whose defined locations are one map value)
TABLE = """asm Tab
import StandardLibrary
signature:
	enum domain Tok = {AA | BB}
	dynamic controlled q: Seq(Tok)
	dynamic controlled seen: Powerset(Seq(Tok))
	dynamic controlled tag: String
	dynamic controlled last: Prod(Tok, Integer)
	dynamic controlled hits: Integer -> Tok
	dynamic monitored pick: Tok
definitions:
	invariant inv_few over seen: size(seen) < 4
	invariant inv_tag over tag: tag != "zzz"
	main rule r_main =
		if length(q) < 3 then
			par
				q := append(q, pick)
				if length(q) < 2 then seen := including(seen, q) endif
				if pick = AA and tag != "zzz" then tag := tag + "z" endif
				last := (pick, length(q))
				hits(length(q) * 7) := pick
			endpar
		else
			q := []
		endif
default init s0:
	function q = []
	function seen = {}
	function tag = ""
	function last = (AA, 0)
"""


def test_values_of_the_value_table_mean_the_same_in_every_process(write_spec):
    """Each forked worker numbers the composite values it meets in its own order: the keys carry
    the values' structure, so the partitions agree on every state."""
    path = write_spec(TABLE)
    ref = sequential(path, keep_graph=True)
    assert (ref["states"], ref["transitions"], ref["depth"]) == (158, 280, 13)
    assert [v[0] for v in ref["violations"]] == ["inv_tag"]
    for backend, n in (("inline", 3), ("processes", 3)):
        assert native(path, n, backend, keep_graph=True) == ref
    m, sp, stp = load(path)
    x = NativeExpander(m, sp, stp)
    assert [typ is None for _, typ, _ in x.tslots] == [False, False, False, False, True]
    (key, picks), = x.initial()
    (pkey, ppicks), = PythonExpander(m, sp, stp).initial()
    assert (x.state_of(key), picks) == (dict(pkey), ppicks)
    assert x.key_of(x.state_of(key)) == key


def test_extend_made_elements_are_canonical_in_every_worker(write_spec):
    path = write_spec(REP)
    ref = sequential(path, keep_graph=True)
    for backend, n in (("inline", 3), ("processes", 2)):
        assert native(path, n, backend, keep_graph=True) == ref


def test_limits_stop_where_the_sequential_search_stops():
    path = SPECS / "sb_sync_master.asm"
    for kw in ({"max_states": 50}, {"max_depth": 4}):
        assert native(path, 3, "inline", **kw) == sequential(path, **kw)


CLASH = """asm Clash
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


def test_a_failing_step_is_expanded_by_the_python_step_function(write_spec):
    """The compiled step fails from n = 1 when go holds: that state is expanded again by the Python
    step function (its error, as the Python expander reports it), and the search goes on past it
    to the violation of inv_small at n = 3, as the sequential search does."""
    path = write_spec(CLASH)
    m, sp, stp = load(path)
    ex1, r1 = explore_partitioned(m, workers=2, backend="inline", state_props=sp, step_props=stp, expander="python")
    ex2, r2 = explore_partitioned(m, workers=2, backend="inline", state_props=sp, step_props=stp, expander="native")
    assert r2.engine == "native"
    assert summary(ex2, r2) == summary(ex1, r1) == sequential(path)
    assert [(v.prop.name, v.state) for v in r2.violations] == [("error", 1), ("inv_small", 3)]
    assert r2.violations[0].message == r1.violations[0].message != ""


REFUSED = """asm Refused
import StandardLibrary
signature:
	dynamic controlled words: Seq(String)
	dynamic controlled sep: String
	dynamic controlled n: Integer
definitions:
	invariant inv_n over n: n < 3
	main rule r_main = if n < 4 then par words := split("a b", sep) n := n + 1 endpar endif
default init s0:
	function n = 0
	function words = []
	function sep = " "
"""
REFUSAL = "split on String by a regular expression computed in the state"


def test_a_spec_the_native_engine_refuses_runs_on_the_python_expander(write_spec):
    path = write_spec(REFUSED)
    m, sp, stp = load(path)
    reason = REFUSAL
    with pytest.raises(Refused) as e:
        explore_partitioned(m, workers=2, backend="inline", state_props=sp, step_props=stp, expander="native")
    assert str(e.value) == reason
    ex, r = explore_partitioned(m, workers=2, backend="processes", state_props=sp, step_props=stp, expander="auto")
    assert (r.engine, r.native_refused) == ("python", reason)
    assert summary(ex, r) == sequential(path)


def test_a_killed_worker_ends_the_run_with_a_clear_error():
    m, sp, stp = load(SPECS / "sb_sync_master.asm")

    def kill_second(search, depth):
        if depth == 3:
            os.kill(search.b.pids[1], signal.SIGKILL)

    with pytest.raises(WorkerLost) as e:
        explore_partitioned(m, workers=2, backend="processes", state_props=sp, step_props=stp, on_level=kill_second,
                            expander="native")
    assert "died during the search (killed by signal 9 (SIGKILL)); the search has no verdict" in str(e.value)


def test_a_worker_over_its_memory_share_ends_with_a_partial_report(monkeypatch):
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
                                memory_share=60_000, expander="native")
    # the keys hash otherwise than the Python expander's: worker 2 goes over its share first, when
    # level 6 comes in; the report covers levels 0..5 (113 of 395 states), never more
    assert r.engine == "native"
    assert (r.verdict, r.reason) == ("incomplete", "worker 2 went over its memory share at depth 6")
    assert (r.states, r.transitions, r.depth) == (113, 175, 5)
    rr = Explorer(m, state_props=sp, step_props=stp, max_depth=5).run()
    assert (rr.states, rr.transitions) == (113, 175)


def test_the_default_memory_share_divides_among_the_workers_of_one_machine():
    from asmcheck.options import default_max_memory
    from asmcheck.parallel.run import memory_share
    from asmcheck.parallel.cluster import PER_NODE
    d = default_max_memory()
    assert memory_share(None, d, 4) == d // 4
    assert memory_share(None, None, 4) == d // 4
    assert memory_share(None, d, 8, cluster="local") == PER_NODE
    assert memory_share(None, 2 << 30, 8, cluster="local") == (2 << 30) // 8
    assert memory_share(64, d, 8, cluster="local") == 64 << 20


# ------------------------------------------------------------------ Ray
def on_ray(path, workers, **kw):
    m, sp, stp = load(path)
    ex, r = explore_partitioned(m, workers=workers, backend="ray", recipe=Recipe(str(Path(path).resolve())),
                                state_props=sp, step_props=stp, expander="native", **kw)
    assert (r.backend, r.engine) == ("ray", "native")
    return summary(ex, r, kw.get("keep_graph", False))


@pytest.mark.slow
def test_specs_on_two_and_eight_actors(ray_local):
    for name in ALL_SPECS:
        assert on_ray(SPECS / name, 2, keep_graph=True) == reference(name, True), name
    for name in ("buggy/sb_sync_slave_clears_lock.asm", "visual_servoing.asm"):
        assert on_ray(SPECS / name, 8) == reference(name, False), name


@pytest.mark.slow
def test_twins_on_two_and_eight_actors(ray_local, tmp_path):
    bench = need_bench()
    for bug in (False, True):
        subprocess.run([sys.executable, str(bench / "gen_swing.py"), "7", "16"] + (["--bug"] if bug else [])
                       + [str(tmp_path)], capture_output=True, text=True, check=True)
        path = tmp_path / ("swing_T7_K16_bug.asm" if bug else "swing_T7_K16.asm")
        ref = sequential(path)
        assert on_ray(path, 2) == ref
        assert on_ray(path, 8) == ref


def rt_args():
    asmeta = SHARED / "asmeta"
    if not (asmeta / "asm_examples" / "RTPatternLibrary").exists():
        pytest.skip(f"the RTPatternLibrary is not at {asmeta}")
    props = ROOT / "properties"
    # as benchmarks/bench_native.py measures it
    return ["tests/rtpattern/RtNondetVS.asm", "--no-default-properties",
            "--properties", str(props / "rtpattern.prop"), "--properties", str(props / "rtpattern_semaphore.prop"),
            "--properties", str(props / "rtpattern_nondet.prop"), "--deadlock", "-I", str(asmeta / "asm_examples")]


def explore_json(*args):
    r = subprocess.run([sys.executable, "-m", "asmcheck", "explore", *args, "--format", "json"], cwd=ROOT,
                       capture_output=True, text=True, timeout=1200, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode in (0, 1), r.stderr
    doc = json.loads(r.stdout)
    seen = {k: doc.pop(k, None) for k in ("seconds", "compile_seconds", "engine", "workers", "engine_note")}
    return doc, seen


@functools.lru_cache(maxsize=None)
def rt_one_worker_report() -> dict:
    """RtNondetVS's one-worker report, made once per test process for both actor counts (compared,
    never changed)."""
    return explore_json(*rt_args())[0]


@pytest.mark.slow
@pytest.mark.parametrize("actors", [2, 8])
def test_rt_nondet_vs_on_a_local_cluster_gives_the_one_worker_report(actors):
    """132,077 states: the JSON report of a local Ray cluster with 2 workers, and with 8 actors on
    this machine's cores, is the one-worker report (the native expander ran)."""
    pytest.importorskip("ray", reason="Ray is not installed (pip install 'asmcheck[cluster]')")
    args = rt_args()
    one = rt_one_worker_report()
    assert (one["states"], one["transitions"], one["depth"], one["verdict"]) == (132077, 392131, 81, "violated")
    got, seen = explore_json(*args, "--cluster", "local", "--workers", str(actors))
    assert (seen["engine"], seen["workers"], seen["engine_note"]) == ("native", actors, None)
    assert got == one


@pytest.mark.slow
def test_actors_share_the_default_bound_of_their_node(ray_local):
    """8 actors on this one node: each may use an eighth of the node's default bound."""
    from asmcheck.options import default_max_memory
    from asmcheck.parallel.cluster import RayBackend
    from asmcheck.parallel.cluster import PER_NODE
    b = RayBackend(Recipe(str(SPECS / "sb_async_master.asm"), expander="native"), 8, "local", PER_NODE)
    try:
        assert b.shares == [default_max_memory() // 8] * 8
    finally:
        b.close()


@pytest.mark.slow
def test_cli_cluster_on_a_refused_spec_says_which_expander_ran(write_spec):
    pytest.importorskip("ray", reason="Ray is not installed (pip install 'asmcheck[cluster]')")
    path = write_spec(REFUSED)
    one, seen1 = explore_json(path)
    got, seen = explore_json(path, "--cluster", "local", "--workers", "2")
    assert got == one
    assert (seen["engine"], seen["workers"]) == ("python", 2)
    assert seen["engine_note"] == seen1["engine_note"] == f"native engine not used: {REFUSAL}"


@pytest.mark.slow
def test_cli_cluster_worker_memory_gives_a_partial_report():
    """An actor over its share (1 MB: less than any Python process) ends the run at the last complete
    level with exit 3, on the native expander as on the Python one; never a count beyond it."""
    pytest.importorskip("ray", reason="Ray is not installed (pip install 'asmcheck[cluster]')")
    r = subprocess.run([sys.executable, "-m", "asmcheck", "explore", "specs/sb_async_master.asm", "--cluster", "local",
                        "--workers", "2", "--worker-memory", "1"], cwd=ROOT, capture_output=True, text=True,
                       timeout=600, env={**os.environ, "PYTHONPATH": str(ROOT), "NO_COLOR": "1"})
    assert r.returncode == 3, r.stderr
    first = r.stdout.splitlines()[0]
    assert first.startswith("sb_async_master.asm: 1 states, 0 transitions, depth 0, ")
    assert first.endswith(" s, native engine, 2 workers")
    assert "incomplete: worker 1 went over its memory share at depth 0" in r.stdout
    assert r.stdout.rstrip().endswith("verdict: incomplete")


def test_choices_of_a_trace_step_whose_position_differs_in_the_python_enumeration():
    """RushHourMon with --deadlock, partitioned on the native expander: the same result as the
    one-process native search.  The native engine used to enumerate this spec's inputs in another
    order than the Python step function (a trace step was the successor at a position where the
    Python step function has another state, and the deadlock was state 815); it now reads the
    arguments that make choices left to right, as the Python engine does, and numbers the states
    as it does (the deadlock is state 816 on both)."""
    from asmcheck.explore.native import NativeExplorer
    path = SHARED / "asmeta" / "asm_examples" / "examples" / "RushHour" / "RushHourMon.asm"
    if not path.exists():
        pytest.skip(f"the ASMETA corpus is not at {SHARED / 'asmeta'}")
    m, sp, stp = load(path)
    nx = NativeExplorer(m, state_props=sp, step_props=stp, deadlock=True)
    ref = summary(nx, nx.run())
    assert (ref["states"], ref["transitions"], ref["violations"][0][:2]) == (838, 5714, ("deadlock", 816))
    assert native(path, 3, "inline", deadlock=True) == ref


MANY = """asm Many
import StandardLibrary
signature:
	dynamic abstract domain D
	dynamic controlled owned: D -> Boolean
	dynamic controlled n: Integer
	dynamic monitored twice: Boolean
definitions:
	invariant inv_n over n: n < 20
	main rule r_main =
		if n < 20 then
			extend D with $a do
				par
					owned($a) := twice
					n := n + 1
				endpar
		endif
default init s0:
	function n = 0
"""


def test_more_elements_made_by_extend_than_slots_start_again_with_more(write_spec):
    """A state with 17 elements of D: the compiled code has 16 slots per domain at first; the
    partitioned search starts again on code with 32, as the native search does (still native)."""
    path = write_spec(MANY)
    ref = sequential(path, keep_graph=True)
    assert (ref["states"], ref["transitions"], ref["verdict"]) == (231, 441, "violated")
    assert native(path, 2, "processes", keep_graph=True) == ref


LONG = """asm Long
import StandardLibrary
signature:
	dynamic controlled n: Integer
definitions:
	invariant inv_n over n: n < 1500
	main rule r_main = if n < 2000 then n := n + 1 endif
default init s0:
	function n = 0
"""


def test_a_trace_longer_than_the_recursion_limit(write_spec):
    """A 1,500-step trace: the choices of its steps are found state by state, not recursively."""
    path = write_spec(LONG)
    ref = sequential(path)
    assert (ref["states"], ref["violations"][0][:2]) == (1502, ("inv_n", 1500))
    assert native(path, 2, "inline") == ref


@pytest.mark.slow
def test_the_actors_of_a_search_serve_the_next_one(ray_local, write_spec):
    """On an instance this process joined, the actors of a search that ended well serve the next
    attempt (again with more element slots) and the next search, with their results unchanged;
    a killed actor ends its run with a clear error, and the actors of that search are not taken
    again."""
    pids = {}

    def seen(search, depth):
        pids.setdefault(id(search), tuple(search.b.pids))

    def ray_run(path, **kw):
        m, sp, stp = load(path)
        ex, r = explore_partitioned(m, workers=2, backend="ray", recipe=Recipe(str(Path(path).resolve())),
                                    state_props=sp, step_props=stp, expander="native", on_level=seen, **kw)
        assert (r.backend, r.engine) == ("ray", "native")
        return summary(ex, r, kw.get("keep_graph", False))

    path = write_spec(MANY)
    assert ray_run(path, keep_graph=True) == sequential(path, keep_graph=True)
    name = "sb_sync_master.asm"
    assert ray_run(SPECS / name, keep_graph=True) == reference(name, True)
    assert len(pids) == 3 and len(set(pids.values())) == 1     # two attempts, then the next search
    served = set(next(iter(pids.values())))

    def kill_second(search, depth):
        seen(search, depth)
        if depth == 3:
            ray_local.kill(search.b.actors[1])

    m, sp, stp = load(SPECS / name)
    with pytest.raises(WorkerLost) as e:
        explore_partitioned(m, workers=2, backend="ray", recipe=Recipe(str(SPECS / name)), state_props=sp,
                            step_props=stp, on_level=kill_second, expander="native")
    assert "a partition actor failed during the search" in str(e.value)
    assert str(e.value).endswith("the search has no verdict")
    pids.clear()
    assert ray_run(SPECS / name) == reference(name, False)
    assert not served & set(next(iter(pids.values())))
