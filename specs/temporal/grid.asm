// Two counters modulo 70 moved one at a time (and who moved last): 9,800 states and
// 19,600 transitions, to time the temporal checks on a graph of that size
// (tests/test_temporal.py). Without fairness the scheduler may move b for ever, so
// a = 0 is not inevitable; under weak fairness (grid_fair.prop, or --fair Who) it is.
// asmcheck: expect violated ctlSpec_a_inevitable, ctlSpec_a_fair, ltlSpec_a_often
// (these properties are false on purpose: the examples show how each one is refuted;
// with the fairness of the .prop file beside the spec some of them hold)
asm grid

import StandardLibrary
import CTLLibrary
import LTLLibrary

signature:
	domain Val subsetof Integer
	enum domain Who = {CA | CB}
	dynamic controlled a: Val
	dynamic controlled b: Val
	dynamic controlled last: Who

definitions:
	domain Val = {0 : 69}

	CTLSPEC ctlSpec_origin_reachable: ag(ef(a = 0 and b = 0))
	CTLSPEC ctlSpec_a_inevitable: ag(af(a = 0))
	CTLSPEC ctlSpec_a_fair: ag(af(a = 0)) // holds under JUSTICE last = CA (grid_fair.prop)
	LTLSPEC ltlSpec_a_often: g(f(a = 0))
	LTLSPEC ltlSpec_b_after_a: g(a = 35 implies f(b = 35 or a = 0))

	main rule r_main =
		choose $w in Who with true do
			par
				last := $w
				if $w = CA then a := (a + 1) mod 70 else b := (b + 1) mod 70 endif
			endpar

default init s0:
	function a = 0
	function b = 0
	function last = CA
