asm mcdc_demo

import StandardLibrary

signature:
	monitored a: Boolean
	monitored b: Boolean
	controlled c: Boolean
	controlled hits: Boolean

definitions:

	main rule r_main =
		par
			c := not c
			if a and (b or c) then hits := true else hits := false endif
		endpar

default init s0:
	function c = false
	function hits = false
