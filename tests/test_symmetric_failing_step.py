"""The failing step of a symmetry-reduced search's error trace is the concrete state's branch,
found by renaming only what holds elements of the symmetric domain: a monitored Integer equal
to an element of a subset of Integer is a number, not that element, and a monitored location's
arguments over the domain are renamed with the choose's values.

Engines: both (the reduced search on each engine; the trace is the unreduced search's)."""
import pytest

import asmcheck
from helpers import write

pytestmark = pytest.mark.engines("both")

# the second draw fails when it reads inp = 12, 12 being one of Num's (unnamed) elements too: no
# literal names one of them (12 is (1 + 1 + 1) * (1 + 1 + 1 + 1))
NUMBER = """asm Sym
import StandardLibrary
signature:
	domain Num subsetof Integer
	dynamic controlled drawn: Num -> Boolean
	dynamic controlled cnt: Integer
	dynamic monitored inp: Integer
definitions:
	domain Num = {11 : 13}
	main rule r_Main =
		choose $n in Num with not drawn($n) do
			par
				drawn($n) := true
				cnt := cnt + 1
				if cnt = 1 and inp = (cnt + cnt + cnt) * (cnt + cnt + cnt + cnt) then cnt := 7 endif
			endpar
default init s0:
	function drawn($n in Num) = false
	function cnt = 0
"""

# the second draw fails when it reads sensor($n): the location's argument is an element
ARGUMENT = (NUMBER.replace("asm Sym", "asm Sym2").replace("dynamic monitored inp: Integer",
                                                          "dynamic monitored sensor: Num -> Boolean")
            .replace("inp = (cnt + cnt + cnt) * (cnt + cnt + cnt + cnt)", "sensor($n)"))


@pytest.mark.parametrize("text,monitored,counts,last", [
    (NUMBER, {"inp": "11..13"}, (4, 4), "  step 2: r_Main chooses $n = 12; reads inp = 12  <- fails (the step cannot be made)"),
    (ARGUMENT, None, (4, 4), "  step 2: r_Main chooses $n = 12; reads sensor(12) = true  <- fails (the step cannot be "
                             "made)"),
], ids=["integer-equal-to-an-element", "element-argument"])
@pytest.mark.parametrize("engine", ["python", "native"])
def test_the_failing_step_is_the_concrete_branch(tmp_path, text, monitored, counts, last, engine):
    model = asmcheck.load(write(tmp_path, text), monitored=monitored)
    full = model.explore(engine="python")
    red = model.explore(engine=engine, symmetry=True)
    assert (full.states, full.transitions) == (8, 13)
    assert (red.states, red.transitions) == counts
    if engine == "native":
        assert red.engine == "native"
    want = full.violation_text()
    got = red.violation_text()
    assert len(want) == len(got) == 1
    assert got[0][-1] == last
    assert got == want
