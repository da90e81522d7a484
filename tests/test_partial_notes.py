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


SYMMETRIC = """asm Sym
import StandardLibrary
import CTLLibrary
signature:
	enum domain Proc = {PA | PB | PC}
	dynamic controlled on: Proc -> Boolean
definitions:
	CTLSPEC ef((forall $p in Proc with on($p)))
	main rule r_main =
		choose $p in Proc with true do on($p) := not on($p)
default init s0:
	function on($p in Proc) = false
"""

SYMMETRY = "under symmetry reduction a partial state space decides no LTL/CTL property"


def test_under_symmetry_the_reason_says_why_nothing_is_decided(write_spec):
    path = write_spec(SYMMETRIC)
    run = asmcheck.load(path).explore(symmetry=True, max_depth=1)
    assert (run.states, [r["verdict"] for r in run.rows]) == (2, ["incomplete"])
    assert run.result.reason == "depth limit 1 reached; " + SYMMETRY
    run = asmcheck.load(path).explore(max_depth=1, engine="python")
    assert (run.states, [r["verdict"] for r in run.rows]) == (4, ["incomplete"])
    assert run.result.reason == "depth limit 1 reached"
    run = asmcheck.load(path).explore(symmetry=True)
    assert (run.states, [r["verdict"] for r in run.rows]) == (4, ["holds"])


# four processes and a lock: at 8 states the native engine decided ctl_3, ctl_4 and ltl_2 under
# --symmetry, the Python engine none
MUTEX = """asm Mutex
import StandardLibrary
import CTLLibrary
import LTLLibrary
signature:
	enum domain Proc = {PA | PB | PC | PD}
	enum domain Phase = {IDLE | WAIT | CRIT}
	dynamic controlled st: Proc -> Phase
	dynamic controlled last: Proc
	derived busy: Boolean
definitions:
	function busy = (exists $q in Proc with st($q) = CRIT)
	invariant over st: not (exists $p in Proc, $q in Proc with $p != $q and st($p) = CRIT and st($q) = CRIT)
	CTLSPEC ag(ef((forall $p in Proc with st($p) = IDLE)))
	CTLSPEC ef((forall $p in Proc with st($p) = WAIT))
	CTLSPEC ag(not((forall $p in Proc with st($p) = WAIT)))
	LTLSPEC g(f(busy))
	LTLSPEC g(busy implies x(busy))
	main rule r_Main =
		choose $p in Proc with true do
			if st($p) = IDLE then
				st($p) := WAIT
			else if st($p) = WAIT and not(busy) then
				par
					st($p) := CRIT
					last := $p
				endpar
			else if st($p) = CRIT then
				st($p) := IDLE
			endif endif endif
default init s0:
	function st($p in Proc) = IDLE
"""


@pytest.mark.parametrize("engine", ["python", "native"])
def test_under_symmetry_both_engines_decide_nothing_on_a_partial_state_space(write_spec, engine):
    run = asmcheck.load(write_spec(MUTEX, "Mutex")).explore(symmetry=True, max_states=8, engine=engine)
    assert run.result.engine == engine
    assert run.states == 9
    assert [r["verdict"] for r in run.rows] == ["incomplete"] * 6
    assert run.result.reason == "state limit 8 reached; " + SYMMETRY
