"""A Ctrl-C during a search keeps what the search counted: the states, transitions and depth it
had reached, on the native engine as on the Python one (the native engine reported 0 states,
0 transitions, depth 0 after seconds of search)."""
from __future__ import annotations

import pytest

import asmcheck
from asmcheck.explore.native import NativeExplorer

pytestmark = pytest.mark.engines("native")

# 300 x 300 states: more than one slice of the native search
GRID = """asm Grid
import StandardLibrary
signature:
	domain Cnt subsetof Integer
	dynamic controlled x: Cnt
	dynamic controlled y: Cnt
	monitored right: Boolean
definitions:
	domain Cnt = {0 : 299}
	invariant over x: x >= 0
	main rule r_main =
		if right then
			if x < 299 then x := x + 1 endif
		else
			if y < 299 then y := y + 1 endif
		endif
default init s0:
	function x = 0
	function y = 0
"""


@pytest.mark.parametrize("engine", ["native", "python"])
def test_a_ctrl_c_keeps_the_counts_of_the_search(write_spec, monkeypatch, engine):
    monkeypatch.setattr(NativeExplorer, "SLICE", 0.0)
    seen = []

    def progress(states, depth, transitions, seconds):
        seen.append((states, transitions))
        raise KeyboardInterrupt
    run = asmcheck.load(write_spec(GRID)).explore(engine=engine, progress=progress)
    assert run.result.engine == engine
    assert run.verdict == "incomplete" and run.result.reason == "interrupted (Ctrl-C)"
    assert len(seen) == 1 and seen[0][0] > 0 and seen[0][1] > 0
    assert (run.states, run.transitions) == seen[0]
    assert run.result.depth >= 1
    assert [r["verdict"] for r in run.rows] == ["incomplete"]
