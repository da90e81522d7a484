// asmcheck: expect violated inv_mutex
/*
 * tiny_mutex_fixed -- tiny_mutex with its bug fixed, but still declaring the violation:
 * the gate must fail on it ("holds (expected to be violated)").
 */
asm tiny_mutex_fixed

import StandardLibrary

signature:
	enum domain Proc = {PA | PB}
	enum domain Phase = {IDLE | WAITING | CRITICAL}
	controlled phase: Proc -> Phase
	monitored want: Proc -> Boolean

definitions:
	rule r_move($p in Proc) =
		if phase($p) = IDLE then
			if want($p) then phase($p) := WAITING endif
		else
			if phase($p) = WAITING then
				if (forall $q in Proc with $q = $p or phase($q) != CRITICAL) then
					phase($p) := CRITICAL
				endif
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
