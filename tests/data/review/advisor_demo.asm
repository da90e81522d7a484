asm advisor_demo

import StandardLibrary

signature:
	enum domain Col = {AA | BB | CC}
	enum domain Unused = {UA | UB}
	domain Small subsetof Integer
	controlled fooA: Col
	controlled fooB: Col
	controlled fooD: Col
	controlled cnt: Small
	controlled never: Col
	controlled u: Unused
	monitored m: Boolean
	derived d: Boolean
	static s: Col -> Boolean

definitions:
	domain Small = {0 : 2}

	function d = cnt > 5
	function s($c in Col) = ($c = AA)

	rule r_unused = skip

	main rule r_main =
		par
			fooA := AA
			if m then fooD := AA endif
			if m then fooD := CC endif
			if cnt < 2 then cnt := cnt + 1 endif
			if d then fooB := BB endif
			choose $x in Col with false do fooB := CC
			forall $y in Col with s($y) do skip
		endpar

default init s0:
	function fooA = AA
	function cnt = 0
