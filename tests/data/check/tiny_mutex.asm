// asmcheck: expect violated inv_mutex
/*
 * tiny_mutex -- a fixed spec for the golden tests of 'asmcheck check' (tests/test_check*.py).
 * Two processes ask for a critical section (the monitored want) and enter it.
 * SEEDED BUG: a waiting process enters without looking at the other one, so both can be
 * in the critical section (inv_mutex). Consequences (properties/tiny.prop):
 * inv_last_is_critical and stp_no_reentry fail as well.
 */
asm tiny_mutex

import StandardLibrary

signature:
	enum domain Proc = {PA | PB}
	enum domain Phase = {IDLE | WAITING | CRITICAL}
	controlled phase: Proc -> Phase
	controlled last: Proc
	monitored want: Proc -> Boolean

definitions:
	rule r_move($p in Proc) =
		if phase($p) = IDLE then
			if want($p) then phase($p) := WAITING endif
		else
			if phase($p) = WAITING then
				par
					phase($p) := CRITICAL
					last := $p
				endpar
			else
				phase($p) := IDLE
			endif
		endif

	invariant inv_mutex over phase: not(phase(PA) = CRITICAL and phase(PB) = CRITICAL)

	main rule r_main =
		choose $p in Proc with true do
			r_move[$p]

default init s0:
	function phase($p in Proc) = IDLE
