"""Two limits of the native engine lifted, each on a small spec written for the test and run on
both engines (pinned with --engine: equal JSON reports, the counts written here).

- A location may hold more than eight distinct elements made by ``extend`` (a set of them): the
  canonical form keeps each location's elements in one pool for the state, where it kept eight a
  location (the engine refused such a state: "a state with elements made by extend that the
  native canonical form does not handle").
- When the search keeps no graph, the Python step function recovers the error of a failing step
  only from the states where the error property is reported, not from every state where a step
  fails (a spec where most states have a failing branch ran the Python step function from each).

Engines: both (python is the reference, native is checked)."""
import pytest

import asmcheck
from asmcheck.explore import bfs
from asmcheck.explore.native_build import compiler
from helpers import both, write

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

# up to twelve tokens in one set, each with a birth mark that tells most of them apart
MANY_FRESH = """\
asm ManyFresh
import StandardLibrary
signature:
	dynamic abstract domain Tok
	controlled pool: Powerset(Tok)
	controlled made: Integer
	controlled born: Tok -> Integer
	monitored drop: Boolean
definitions:
	main rule r_Main =
		if drop and size(pool) > 0 then
			choose $t in pool with true do pool := excluding(pool, $t)
		else
			if made < 12 then
				extend Tok with $t do
					par
						pool := including(pool, $t)
						made := made + 1
						born($t) := made mod 3
					endpar
			endif
		endif
default init s0:
	function pool = {}
	function made = 0
"""

# from x = 4 on, the step fails whenever m holds: 17 of the 21 states have a failing branch
MANY_FAILS = """\
asm ManyFails
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled x: D
	controlled y: D
	monitored m: Boolean
definitions:
	domain D = {0 : 20}
	main rule r_Main =
		par
			if x < 20 then x := x + 1 endif
			if m and x > 3 then
				par
					y := 1
					y := 2
				endpar
			endif
		endpar
default init s0:
	function x = 0
	function y = 0
"""


def test_a_set_of_twelve_fresh_elements_runs_native(tmp_path, capsys):
    code, out = both(tmp_path, capsys, MANY_FRESH)
    assert code == 0
    assert (out["verdict"], out["states"], out["transitions"], out["depth"]) == \
        ("no property checked", 525, 1691, 24)


def test_failing_steps_recovered_only_where_the_error_is_reported(tmp_path, capsys, monkeypatch):
    code, out = both(tmp_path, capsys, MANY_FAILS)
    assert code == 1
    assert (out["verdict"], out["states"], out["transitions"], out["depth"]) == ("violated", 21, 21, 20)
    assert [v["property"] for v in out["violations"]] == ["error"]
    # the Python step function runs from the one state the report shows (x = 4), not from all 17
    sources = []
    real = bfs.Explorer.admitted_successors

    def counted(self, state, errors, *a, **k):
        sources.append(state)
        return real(self, state, errors, *a, **k)

    monkeypatch.setattr(bfs.Explorer, "admitted_successors", counted)
    res = asmcheck.load(write(tmp_path, MANY_FAILS)).explore(engine="native")
    assert res.engine == "native" and res.verdict == "violated"
    assert len(sources) == 1
