"""A search stopped by a limit under fairness constraints or INVAR decides no LTL/CTL property on
the states explored; the reason says why (it said only 'state limit 5 reached')."""
from __future__ import annotations

import pytest

import asmcheck

pytestmark = pytest.mark.engines("both")

COUNT = """asm Count
import StandardLibrary
import CTLLibrary
signature:
	domain Cnt subsetof Integer
	dynamic controlled x: Cnt
	monitored inc: Boolean
definitions:
	domain Cnt = {0 : 9}
EXTRA
	CTLSPEC ag(x < 3)
	CTLSPEC ef(x = 2)
	main rule r_main =
		if inc then
			if x < 9 then x := x + 1 else x := 0 endif
		endif
default init s0:
	function x = 0
"""

FAIR = "under fairness constraints a partial state space decides no LTL/CTL property"
INVAR = "with INVAR constraints a partial state space decides no LTL/CTL property"


@pytest.mark.parametrize("extra, why", [("\tJUSTICE inc\n", FAIR), ("\tINVAR x < 9\n", INVAR)])
def test_the_reason_says_why_nothing_is_decided(write_spec, extra, why):
    run = asmcheck.load(write_spec(COUNT.replace("EXTRA\n", extra))).explore(max_states=5)
    assert run.states == 5
    assert [r["verdict"] for r in run.rows] == ["incomplete", "incomplete"]
    assert run.result.reason == "state limit 5 reached; " + why
    assert run.json()["incomplete"] == "state limit 5 reached; " + why


def test_without_them_the_same_bound_decides(write_spec):
    run = asmcheck.load(write_spec(COUNT.replace("EXTRA\n", ""))).explore(max_states=5)
    assert [r["verdict"] for r in run.rows] == ["violated", "holds"]
    assert run.result.reason == "state limit 5 reached"
