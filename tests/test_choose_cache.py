"""The native engine keeps a choose's candidates for the later runs of the step from one state
when the run reached the choose after the same earlier choices (Generator.candidate_cache).  Each
spec below gives other states when one condition of the cache is dropped (the counts in the
comments were measured with that condition removed).  Both engines
run each spec (``both``: equal JSON reports), and the counts are pinned.

Engines: both (python is the reference, native is checked)."""
import pytest

from helpers import both

pytestmark = pytest.mark.engines("native")

# the choose's candidates depend on the monitored m chosen before it (a seq block);
# reusing them whatever the earlier choices gives 16 states, 72 transitions
CACHESEQ2 = """\
asm CacheSeq2
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled f: D
	controlled g: D
	monitored m: Boolean
definitions:
	domain D = {0 : 3}
	main rule r_Main =
		seq
			if m then f := (f + 1) mod 4 endif
			choose $x in D with $x != f and $x != g do g := $x
		endseq
default init s0:
	function f = 0
	function g = 0
"""

# a choose in a forall: its first visit has one candidate (no choice), so its second visit
# is at the same choice position; reusing the list at a later visit gives 5 states, 8 transitions
CACHELOOP = """\
asm CacheLoop
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled h: D -> D
	monitored lim: D
	controlled k: D
definitions:
	domain D = {0 : 3}
	main rule r_Main =
		forall $i in D with $i < 2 do
			choose $y in D with $y >= 3 - $i and $y != h($i) do
				par
					h($i) := $y
					if $i = 1 then k := lim endif
				endpar
default init s0:
	function h($d in D) = 0
	function k = 0
"""

# candidates computed at run time (a set in the state) after a monitored choice in a seq
# block; reusing them whatever the earlier choices gives 24 states, 96 transitions
CACHERUN = """\
asm CacheRun
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled pool: Powerset(D)
	controlled g: D
	monitored m: Boolean
definitions:
	domain D = {0 : 3}
	main rule r_Main =
		seq
			if m then pool := excluding(pool, g) else pool := including(pool, g) endif
			choose $x in pool with true do g := $x
		endseq
default init s0:
	function pool = {0, 1, 2}
	function g = 0
"""

# the guard reads a monitored value first, so making the list takes a choice: a list kept
# then gives 4 states, 8 transitions
CACHEMON = """\
asm CacheMon
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled g: D
	controlled h: D
	monitored lim: D
	monitored m: Boolean
definitions:
	domain D = {0 : 3}
	main rule r_Main =
		seq
			if m then h := (h + 1) mod 4 endif
			choose $x in D with $x <= lim and $x != h do g := $x
		endseq
default init s0:
	function g = 0
	function h = 0
"""

# a merged choose in a seq block beside a forall whose choose's body reads a monitored value
CACHESEQ = """\
asm CacheSeq
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled f: D
	controlled g: D
	controlled h: D -> D
	controlled k: D
	monitored m: Boolean
	monitored lim: D
definitions:
	domain D = {0 : 3}
	main rule r_Main =
		par
			seq
				if m then f := (f + 1) mod 4 endif
				choose $x in D with $x != f and $x != g do g := $x
			endseq
			forall $i in D with $i < 2 do
				choose $y in D with $y > $i and $y != h($i) do
					par
						h($i) := $y
						if $i = 0 then k := lim endif
					endpar
		endpar
default init s0:
	function f = 0
	function g = 0
	function h($d in D) = 0
	function k = 0
"""


@pytest.mark.parametrize("text, states, transitions, depth", [
    (CACHESEQ2, 13, 57, 3),
    (CACHELOOP, 9, 40, 1),
    (CACHERUN, 15, 45, 4),
    (CACHEMON, 13, 80, 3),
    (CACHESEQ, 289, 10104, 3),
], ids=["seq-after-monitored", "forall-second-visit", "run-time-range", "monitored-in-guard", "merged-and-forall"])
def test_candidate_cache_gives_the_python_engines_states(tmp_path, capsys, text, states, transitions, depth):
    code, out = both(tmp_path, capsys, text)
    assert code == 0
    assert (out["states"], out["transitions"], out["depth"]) == (states, transitions, depth)
