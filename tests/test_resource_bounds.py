"""Specs too large to build end with a located message and the same verdict on both engines,
never with gigabytes taken or a C compiler that fails after half a minute: an interval of more
than ten million elements is a failing step, and a layout of more locations than the native
engine compiles goes to the Python engine with the reason."""
from __future__ import annotations

import pytest

import asmcheck
from asmcheck.explore import native

from helpers import write

pytestmark = pytest.mark.engines("native")

HUGE = """asm Huge
import StandardLibrary
signature:
	domain Big subsetof Integer
	dynamic controlled f: Big -> Boolean
	dynamic controlled n: Integer
definitions:
	domain Big = {1 : 100000000}
	main rule r_main = forall $i in Big with $i < 3 do f($i) := true
default init s0:
	function n = 0
"""

MESSAGE = "this interval has 100,000,000 elements: more than asmcheck builds (10,000,000); narrow it"


@pytest.mark.parametrize("engine", ["auto", "python"])
def test_an_interval_of_a_hundred_million_elements_is_a_failing_step(tmp_path, engine):
    path = write(tmp_path, HUGE)
    run = asmcheck.load(path).explore(engine=engine)
    assert run.result.engine == "python"
    if engine == "auto":
        assert run.result.native_refused == f"{MESSAGE} (while the C code was generated)"
    assert run.result.verdict == "violated"
    [v] = run.result.violations
    assert v.prop.name == "error"
    assert v.message == MESSAGE
    assert (v.error.span.line, v.error.span.col) == (8, 15)
    assert (run.result.states, run.result.transitions) == (1, 0)


def test_the_native_engine_names_the_interval_it_cannot_build(tmp_path):
    with pytest.raises(asmcheck.UsageError) as e:
        asmcheck.load(write(tmp_path, HUGE)).explore(engine="native")
    assert str(e.value) == f"the native explorer cannot run Huge.asm: {MESSAGE} (while the C code was generated)"


WIDE = """asm Wide
import StandardLibrary
signature:
	domain Cell subsetof Integer
	dynamic controlled f: Cell -> Boolean
definitions:
	domain Cell = {1 : 101}
	main rule r_main = forall $i in Cell with $i < 3 do f($i) := true
default init s0:
	function f($i in Cell) = false
"""


def test_more_locations_than_the_native_engine_lays_out_go_to_the_python_engine(tmp_path, monkeypatch):
    monkeypatch.setattr(native, "MAX_SLOTS", 100)
    run = asmcheck.load(write(tmp_path, WIDE)).explore()
    assert run.result.engine == "python"
    assert run.result.native_refused == "more than 100 locations (the C compiler fails on a million)"
    assert (run.result.states, run.result.transitions) == (2, 2)
    monkeypatch.setattr(native, "MAX_SLOTS", 101)
    run = asmcheck.load(write(tmp_path, WIDE)).explore()
    assert run.result.engine == "native"
    assert (run.result.states, run.result.transitions) == (2, 2)
