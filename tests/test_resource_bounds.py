"""Specs too large to build end with a located message and the same verdict on both engines,
never with gigabytes taken or a C compiler that fails after half a minute: an interval of more
than ten million elements is a failing step, and a layout of more locations than the native
engine compiles goes to the Python engine with the reason."""
from __future__ import annotations

from pathlib import Path

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


# recursions that do not end: a derived function, a macro rule (which the C compiler turns into
# a loop) and a turbo rule; each used to crash the native engine (a stack overflow) or spin in
# C code that neither a time limit nor a signal stops
ENDLESS = {
    "derived": ("""asm EndlessDerived
import StandardLibrary
signature:
	dynamic controlled x: Integer
	derived fact: Integer -> Integer
definitions:
	function fact($n in Integer) = if $n = 0 then 1 else $n * fact($n - 1) endif
	main rule r_main = x := fact(x - 1)
default init s0:
	function x = 0
""", (7, 65), "the spec nests too deeply here (recursion limit reached)"),
    "macro": ("""asm EndlessMacro
import StandardLibrary
signature:
	dynamic controlled x: Integer
definitions:
	macro rule r_down($n in Integer) = if $n = 0 then x := 1 else r_down($n - 1) endif
	main rule r_main = r_down(x - 1)
default init s0:
	function x = 0
""", (6, 13), "the rule r_down calls itself without end (or more deeply than asmcheck can follow)"),
    "turbo": ("""asm EndlessTurbo
import StandardLibrary
signature:
	dynamic controlled x: Integer
definitions:
	turbo rule r_down($n in Integer) = seq x := x + 1 if $n = 0 then skip else r_down($n - 1) endif endseq
	main rule r_main = r_down(x - 1)
default init s0:
	function x = 0
""", (6, 13), "the rule r_down calls itself without end (or more deeply than asmcheck can follow)"),
}


@pytest.mark.parametrize("kind", sorted(ENDLESS))
def test_a_recursion_that_does_not_end_is_reported_where_it_recurses_whatever_the_engine(tmp_path, kind):
    text, (line, col), message = ENDLESS[kind]
    path = write(tmp_path, text)
    for engine in ("auto", "python"):
        with pytest.raises(asmcheck.AsmError) as e:
            asmcheck.load(path).explore(engine=engine)
        assert e.value.message == message
        assert (e.value.span.line, e.value.span.col) == (line, col)
    with pytest.raises(asmcheck.UsageError) as e:
        asmcheck.load(path).explore(engine="native")
    assert str(e.value) == (f"the native explorer cannot run {Path(path).name}: a derived function or rule called "
                            f"more than 1,000 times within itself, reached at run time")


@pytest.mark.engines("native")
def test_the_native_compile_comes_out_of_the_time_limit(tmp_path, monkeypatch):
    """--max-seconds bounds the whole run: a compile (a cache miss) that takes longer than the
    limit leaves the search no time; before, the search had the whole limit after the compile."""
    import time

    from asmcheck.explore import native_build
    if native_build.compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    monkeypatch.setenv("ASMCHECK_CACHE", str(tmp_path / "cache"))
    real = native_build._compile

    def slow(*args, **kwargs):
        time.sleep(1.2)
        return real(*args, **kwargs)

    monkeypatch.setattr(native_build, "_compile", slow)
    text = ("asm Counter\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
            "\tmain rule r_main = x := x + 1\ndefault init s0:\n\tfunction x = 0\n")
    run = asmcheck.load(write(tmp_path, text)).explore(engine="native", max_seconds=1.0)
    assert (run.result.engine, run.result.verdict) == ("native", "incomplete")
    assert run.result.reason.startswith("time limit 1.0 s reached")
    assert run.explorer.max_seconds == 0.0
