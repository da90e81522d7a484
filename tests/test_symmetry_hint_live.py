"""A search without --symmetry that runs long says, while it goes on, that the model has
interchangeable elements (after asmcheck.api.SYMMETRY_HINT_SECONDS; set to 0 here), once, through
the run's ``warn``; the report's hint at a limit's end stays as it was.

Engines: native (each test names its engine; the Python engine is run too)."""
import pytest

import asmcheck
import asmcheck.api as api
from asmcheck.explore.bfs import Explorer
from asmcheck.explore.native import NativeExplorer
from helpers import write

pytestmark = pytest.mark.engines("native")

DRAW = """asm Draw
import StandardLibrary
signature:
	domain Num subsetof Integer
	dynamic controlled drawn: Num -> Boolean
definitions:
	domain Num = {1 : 9}
	main rule r_Main =
		choose $n in Num with not drawn($n) do drawn($n) := true
default init s0:
	function drawn($n in Num) = false
"""

HINT = ("hint: Num's 9 unnamed elements are interchangeable; --symmetry explores one state per class of such "
        "states (this search goes on)")


@pytest.mark.parametrize("engine", ["python", "native"])
def test_the_hint_comes_once_while_the_search_runs(tmp_path, monkeypatch, engine):
    monkeypatch.setattr(api, "SYMMETRY_HINT_SECONDS", 0.0)
    # a report between every two slices of the native search (of 256 states), after every state of
    # the Python one
    monkeypatch.setattr(NativeExplorer, "SLICE", 0.0)
    monkeypatch.setattr(Explorer, "REPORT_SECONDS", -1.0)
    model = asmcheck.load(write(tmp_path, DRAW))
    said: list = []
    run = model.explore(engine=engine, warn=said.append)
    assert (run.states, run.transitions) == (512, 2305)
    assert said == [HINT]
    assert run.symmetry_hint == ""          # the search ended: no hint in the report
    said.clear()
    run = model.explore(engine=engine, warn=said.append, symmetry=True)
    assert (run.states, run.transitions) == (10, 10)
    assert said == []


def test_no_hint_without_interchangeable_elements_or_before_its_time(tmp_path, monkeypatch):
    monkeypatch.setattr(Explorer, "REPORT_SECONDS", -1.0)
    named = DRAW.replace("drawn($n) := true", "if $n = 1 or $n = 2 or $n = 3 or $n = 4 or $n = 5 or $n = 6 or $n = 7 or $n = 8 or $n = 9 then "
                                              "drawn($n) := true endif")
    said: list = []
    monkeypatch.setattr(api, "SYMMETRY_HINT_SECONDS", 0.0)
    run = asmcheck.load(write(tmp_path, named)).explore(engine="python", warn=said.append)
    assert run.states == 512 and said == []
    monkeypatch.setattr(api, "SYMMETRY_HINT_SECONDS", 3600.0)
    run = asmcheck.load(write(tmp_path, DRAW)).explore(engine="python", warn=said.append)
    assert run.states == 512 and said == []
