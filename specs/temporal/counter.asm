// A counter over {0, 1, 2}: 0 -> 1; 1 -> 0 or 2 (nondeterministically); 2 -> 1.
//   - ctlSpec_reset_possible  ag(ef(c = 0))   holds, but only through EF: a reset is always
//     possible, never inevitable;
//   - ctlSpec_reset_inevitable ag(af(c = 0))  is violated (the lasso 1, 2, 1, 2, ...);
//   - ltlSpec_reset_often     g(f(c = 0))     is violated, and only an infinite run refutes
//     it: the counterexample is a lasso (every finite run can still be extended to reset);
//   - ltlSpec_never_two_twice g(c = 2 implies x(c = 1)), ltlSpec_before_two g(c = 2 implies y(c = 1))
//     (past) and ltlSpec_once_one g(c = 2 implies o(c = 1)) hold.
// asmcheck: expect violated ctlSpec_reset_inevitable, ltlSpec_reset_often, ltlSpec_wrong_past
// (these properties are false on purpose: the examples show how each one is refuted;
// with the fairness of the .prop file beside the spec some of them hold)
asm counter

import StandardLibrary
import CTLLibrary
import LTLLibrary

signature:
	domain Val subsetof Integer
	dynamic controlled c: Val

definitions:
	domain Val = {0 : 2}

	CTLSPEC ctlSpec_reset_possible: ag(ef(c = 0))
	CTLSPEC ctlSpec_reset_inevitable: ag(af(c = 0))
	CTLSPEC ctlSpec_two_reachable: ef(c = 2)
	CTLSPEC ctlSpec_can_stay_away: ef(eg(c != 0))
	CTLSPEC ctlSpec_au: au(c = 0, c = 1)
	LTLSPEC ltlSpec_reset_often: g(f(c = 0))
	LTLSPEC ltlSpec_never_two_twice: g(c = 2 implies x(c = 1))
	LTLSPEC ltlSpec_before_two: g(c = 2 implies y(c = 1))
	LTLSPEC ltlSpec_once_one: g(c = 2 implies o(c = 1))
	LTLSPEC ltlSpec_zero_since: g(c = 1 implies s(c != 2, c = 0) or y(c = 2))
	LTLSPEC ltlSpec_historically: h(c <= 2)
	LTLSPEC ltlSpec_wrong_past: g(c = 1 implies y(c = 0))

	main rule r_main =
		if c = 0 then
			c := 1
		else
			if c = 1 then
				choose $v in {0, 2} with true do
					c := $v
			else
				c := 1
			endif
		endif

default init s0:
	function c = 0
