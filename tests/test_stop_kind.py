"""Why a search stopped, in one word (Result.stop, a bfs.Stop): set where the reason text is set,
the same on the Python engine, the native engine and the partitioned search, and what the
check of a partial state space reads (never the reason's words)."""
from __future__ import annotations

import pytest

import asmcheck
from asmcheck import api
from asmcheck.explore.bfs import Stop

pytestmark = pytest.mark.engines("native")

# x counts 0..9 when inc is read true: 10 states
COUNT = """asm Count
import StandardLibrary
import CTLLibrary
signature:
	domain Cnt subsetof Integer
	dynamic controlled x: Cnt
	monitored inc: Boolean
definitions:
	domain Cnt = {0 : 9}
	CTLSPEC ag(x < 3)
	CTLSPEC ef(x = 2)
	main rule r_main =
		if inc then
			if x < 9 then x := x + 1 else x := 0 endif
		endif
default init s0:
	function x = 0
"""

CASES = [
    # (limits, states, stop, reason, rows)
    ({}, 10, "", "", ["violated", "holds"]),
    ({"max_states": 5}, 5, Stop.STATES, "state limit 5 reached", ["violated", "holds"]),
    ({"max_depth": 2}, 3, Stop.DEPTH, "depth limit 2 reached", ["incomplete", "holds"]),
]


@pytest.mark.parametrize("engine", ["python", "native"])
@pytest.mark.parametrize("limits, states, stop, reason, rows", CASES)
def test_the_stop_kind_is_set_with_the_reason(write_spec, engine, limits, states, stop, reason, rows):
    run = asmcheck.load(write_spec(COUNT)).explore(engine=engine, **limits)
    assert (run.states, run.result.stop, run.result.reason) == (states, stop, reason)
    assert run.stop == stop
    assert [r["verdict"] for r in run.rows] == rows


@pytest.mark.parametrize("limits, states, stop, reason, rows", CASES)
def test_the_partitioned_search_sets_the_same_stop_kind(write_spec, limits, states, stop, reason, rows):
    run = asmcheck.load(write_spec(COUNT)).explore(engine="python", workers=2, **limits)
    assert run.result.engine == "python"
    assert (run.states, run.result.stop, run.result.reason) == (states, stop, reason)


def test_a_time_limit_is_a_time_stop(write_spec):
    run = asmcheck.load(write_spec(COUNT)).explore(engine="python", max_seconds=0)
    assert run.result.stop == Stop.TIME and run.result.reason.startswith("time limit 0 s reached")
    assert [r["verdict"] for r in run.rows] == ["incomplete", "incomplete"]


def test_the_partial_check_reads_the_stop_kind_not_the_reason(write_spec, monkeypatch):
    """On the native threads the partial check runs only after a state or depth limit: with the
    reason's words changed the same verdicts are decided; with the stop kind of a time limit,
    none is."""
    from asmcheck.explore.native import NativeExplorer
    spec = write_spec(COUNT)
    real = NativeExplorer.run
    kind = {}

    def reworded(self):
        res = real(self)
        res.reason = "stopped (reworded)"
        res.stop = kind.get("stop", res.stop)
        return res
    monkeypatch.setattr(NativeExplorer, "run", reworded)
    run = asmcheck.load(spec).explore(engine="native", workers=2, max_states=5)
    assert run.result.workers == 2 and run.result.stop == Stop.STATES
    assert [r["verdict"] for r in run.rows] == ["violated", "holds"]
    kind["stop"] = Stop.TIME
    run = asmcheck.load(spec).explore(engine="native", workers=2, max_states=5)
    assert [r["verdict"] for r in run.rows] == ["incomplete", "incomplete"]


def test_every_limit_kind_is_a_limit():
    assert Stop.BOUNDS == {Stop.STATES, Stop.DEPTH}
    assert Stop.LIMITS == {Stop.STATES, Stop.DEPTH, Stop.TIME, Stop.MEMORY}


@pytest.mark.parametrize("limits, rows", [({"max_states": 5}, ["violated", "holds"]),
                                          ({"max_depth": 2}, ["incomplete", "holds"])])
def test_the_partitioned_search_decides_what_one_worker_decides(write_spec, limits, rows):
    """After a state or depth limit the partitioned search (processes) has the states and steps of
    the sequential search: the same verdicts are decided, with the same traces (it decided none)."""
    spec = write_spec(COUNT)
    one = asmcheck.load(spec).explore(engine="python", **limits)
    two = asmcheck.load(spec).explore(engine="python", workers=2, **limits)
    assert type(two.explorer).__name__ == "PartitionedExplorer"
    assert [r["verdict"] for r in two.rows] == [r["verdict"] for r in one.rows] == rows
    assert [r.get("decided_on") for r in two.rows] == [r.get("decided_on") for r in one.rows]
    assert two.json()["properties"] == one.json()["properties"]
    assert two.json()["violations"] == one.json()["violations"]
    assert two.verdict == one.verdict
