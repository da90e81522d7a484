/*
 * tiny_counter -- a counter that the monitored go moves on; it declares no expected
 * violation, so the violation of inv_below_3 fails the gate.
 */
asm tiny_counter

import StandardLibrary

signature:
	domain Small subsetof Integer
	controlled x: Small
	monitored go: Boolean

definitions:
	domain Small = {0 : 3}

	invariant inv_nonnegative over x: x >= 0
	invariant inv_below_3 over x: x < 3

	main rule r_main =
		if go then
			if x < 3 then x := x + 1 else x := 0 endif
		endif

default init s0:
	function x = 0
