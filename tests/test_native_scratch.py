"""What the native search holds besides its tables: the buffers of one state's expansion (its
successors, their set of distinct ones) are sized by what they hold and freed when the search has
ended; the explorer does not keep the generated C source.  The Python engine's reports are the
reference (counts, verdicts, traces).  Engines pinned: native, compared with python."""
from __future__ import annotations

import pytest

from asmcheck.explore.native import NativeExplorer, thread_unsafe
from asmcheck.explore.native_build import compiler
from asmcheck.props import spec_properties
from asmcheck.props.load import load_machine

from helpers import both, write

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")]

# the first step has 1,500 x 4 runs and 1,500 distinct successors (the set of distinct successors
# grows from 1,024 entries while the state is expanded, past duplicates); every later state has
# one successor
FAN = """asm Fan
import StandardLibrary
import LTLLibrary
import CTLLibrary
signature:
	domain Big subsetof Integer
	domain Few subsetof Integer
	controlled x: Big
	controlled started: Boolean
definitions:
	domain Big = {0 : 1499}
	domain Few = {0 : 3}
	LTLSPEC g(started implies f(x = 0))
	LTLSPEC g(x < 1000)
	CTLSPEC ag(ef(x = 0))
	main rule r_main =
		if not started then
			choose $v in Big with true do
				choose $w in Few with true do
					par
						x := $v
						started := true
					endpar
		else
			x := 0
		endif
default init s0:
	function x = 0
	function started = false
"""


def test_a_state_with_thousands_of_runs_and_distinct_successors(tmp_path, capsys):
    # the same report as the Python engine: states, transitions, verdicts and the lasso
    code, rep = both(tmp_path, capsys, FAN)
    assert (rep["states"], rep["transitions"]) == (1501, 3000)
    assert rep["verdict"] == "violated"


def test_the_same_without_the_temporal_properties(tmp_path, capsys):
    text = FAN.replace("\tLTLSPEC g(started implies f(x = 0))\n", "").replace(
        "\tLTLSPEC g(x < 1000)\n", "").replace("\tCTLSPEC ag(ef(x = 0))\n", "")
    code, rep = both(tmp_path, capsys, text)
    assert (rep["states"], rep["transitions"]) == (1501, 3000)


def test_a_search_run_again_after_its_buffers_were_freed(tmp_path):
    # the expansion's buffers are freed at the end of each search and made again by the next one
    spec, m = load_machine(write(tmp_path, FAN), {})
    sp, stp = spec_properties(m)
    ex = NativeExplorer(m, state_props=sp, step_props=stp)
    try:
        for _ in range(3):
            r = ex.run()
            assert (r.states, r.transitions, r.depth) == (1501, 3000, 1)
    finally:
        ex.close()


def test_the_explorer_keeps_no_source_and_still_tells_the_thread_unsafe_variables(tmp_path):
    spec, m = load_machine(write(tmp_path, FAN), {})
    sp, stp = spec_properties(m)
    one = NativeExplorer(m, state_props=sp, step_props=stp)
    two = NativeExplorer(m, state_props=sp, step_props=stp, workers=2)
    try:
        for ex in (one, two):
            assert not [k for k, v in vars(ex).items() if isinstance(v, str) and len(v) > 10_000]
        # worked out from the source at once for threads, from the source generated again for one
        assert one.thread_unsafe == two.thread_unsafe == thread_unsafe(one._regenerate(one.gen.cn_k).generate())
    finally:
        one.close()
        two.close()
