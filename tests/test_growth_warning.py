"""A search that may not end says why while it runs: an Integer location that keeps taking new
values level after level is named, with its range and the way to bound it, on both engines,
and the reason of a time limit repeats it.  A bounded Integer location in a long search is not
named."""
from __future__ import annotations

import re

import pytest

import asmcheck

from helpers import warm_native, write

pytestmark = pytest.mark.engines("native")

# a counter without a bound: the state at depth d has x = d
UNBOUNDED = """asm Unbounded
import StandardLibrary
signature:
	controlled x: Integer
	controlled b: Boolean
definitions:
	main rule r_main = par x := x + 1 b := not b endpar
default init s0:
	function x = 0
	function b = false
"""

# 26 Boolean locations count in binary (67,108,864 states on one path) while the Integer phase
# goes round 0, 1, 2, 3 and the sequence q grows to three elements and starts again: a long
# search whose Integer location and sequence are bounded
BITS = 26
BOUNDED = ("asm Bounded\nimport StandardLibrary\nsignature:\n\tcontrolled phase: Integer\n\tcontrolled q: Seq(Integer)\n"
           + "".join(f"\tcontrolled b{i}: Boolean\n" for i in range(BITS))
           + "definitions:\n\tmain rule r_main = par\n\t\tphase := (phase + 1) mod 4\n"
           + "\t\tif length(q) < 3 then q := append(q, phase) else q := [] endif\n"
           + "".join(f"\t\tif {' and '.join(f'b{j}' for j in range(i)) or 'true'} then b{i} := not b{i} endif\n"
                     for i in range(BITS))
           + "\tendpar\ndefault init s0:\n\tfunction phase = 0\n\tfunction q = []\n"
           + "".join(f"\tfunction b{i} = false\n" for i in range(BITS)))

MESSAGE = re.compile(r"^x keeps taking new values level after level \(range 0\.\.(\d+) at depth (\d+)\): the "
                     r"search may not end; bound it in the model \(a subset domain or a guard\), or stop the "
                     r"search with --max-depth or --max-states$")


@pytest.mark.parametrize("engine", ["python", "native"])
def test_an_unbounded_counter_is_named_while_the_search_runs(tmp_path, engine):
    warnings: list[str] = []
    path = write(tmp_path, UNBOUNDED)
    if engine == "native":
        warm_native(path)
    run = asmcheck.load(path).explore(engine=engine, max_seconds=2.5, warn=warnings.append)
    assert run.result.engine == engine
    assert run.result.verdict == "incomplete"
    assert len(warnings) == 1, warnings
    m = MESSAGE.match(warnings[0])
    assert m, warnings[0]
    # the greatest value met is that of the level below the one being searched
    assert int(m.group(1)) == int(m.group(2)) + 1
    assert run.result.reason == f"time limit 2.5 s reached; {warnings[0]}"


@pytest.mark.parametrize("engine", ["python", "native"])
def test_a_bounded_integer_in_a_long_search_is_not_named(tmp_path, engine):
    warnings: list[str] = []
    path = write(tmp_path, BOUNDED)
    if engine == "native":
        warm_native(path)
    run = asmcheck.load(path).explore(engine=engine, max_seconds=1.5, warn=warnings.append)
    assert run.result.engine == engine
    assert run.result.reason.startswith("time limit 1.5 s reached"), run.result.reason
    assert warnings == []
    assert "keeps taking" not in run.result.reason


# x wraps round at 64 bits after 3 and then counts up from the least Integer: its values are new
# at every level but never a new least or greatest value
WRAPPED = """asm Wrapped
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	main rule r_main = if x < 3 then x := x + 1 else x := 9223372036854775807 + x endif
default init s0:
	function x = 0
"""


@pytest.mark.parametrize("engine", ["python", "native"])
def test_a_counter_that_wrapped_round_is_still_named(tmp_path, engine):
    warnings: list[str] = []
    path = write(tmp_path, WRAPPED)
    if engine == "native":
        warm_native(path)
    run = asmcheck.load(path).explore(engine=engine, max_seconds=2.5, warn=warnings.append)
    assert run.result.engine == engine
    assert len(warnings) == 1, warnings
    assert warnings[0].startswith("x keeps taking new values level after level "
                                  "(range -9223372036854775806..3 at depth "), warnings[0]
    assert run.result.reason == f"time limit 2.5 s reached; {warnings[0]}"


GROWING = """asm Growing
import StandardLibrary
signature:
	controlled s: Seq(Integer)
definitions:
	main rule r_main = s := append(s, 1)
default init s0:
	function s = []
"""

SIZE = re.compile(r"^s keeps growing level after level \(size ([\d,]+) at depth (\d+)\): the search may not end; "
                  r"bound it in the model \(a guard on its size\), or stop the search with --max-depth or "
                  r"--max-states$")


@pytest.mark.parametrize("engine", ["python", "native"])
def test_a_sequence_that_keeps_growing_is_named_while_the_search_runs(tmp_path, engine):
    warnings: list[str] = []
    path = write(tmp_path, GROWING)
    if engine == "native":
        warm_native(path)
    run = asmcheck.load(path).explore(engine=engine, max_seconds=2.5, warn=warnings.append)
    assert run.result.engine == engine
    assert len(warnings) == 1, warnings
    m = SIZE.match(warnings[0])
    assert m, warnings[0]
    # the state found last is one level below the one being searched: s has one element a level
    assert int(m.group(1).replace(",", "")) == int(m.group(2)) + 1
    assert run.result.reason == f"time limit 2.5 s reached; {warnings[0]}"


def test_windows_that_move_past_each_other_count_only_over_a_wide_span():
    from asmcheck.explore.bfs import DRIFT_SPAN, drifted
    # a location with a few values moves between them by chance: not a drift
    assert not drifted((0, 3), (4, 5))
    assert not drifted((4, 5), (0, 3))
    # a counter: each window beyond the last (sharing the level between two watches)
    assert drifted((0, 700), (700, 1500))
    assert drifted((-9223372036854775806, -9223372036854770000), (-9223372036854770000, -9223372036854760000))
    assert drifted((5000, 6000), (3000, 5000))
    # overlapping windows, a window that did not move, no state in one of them
    assert not drifted((0, 2000), (1000, 3000))
    assert not drifted((7, 7), (7, 7))
    assert not drifted(None, (0, 5000)) and not drifted((0, 5000), None)
    assert not drifted((0, DRIFT_SPAN - 2), (DRIFT_SPAN - 2, DRIFT_SPAN - 1))
    assert drifted((0, DRIFT_SPAN - 2), (DRIFT_SPAN - 2, DRIFT_SPAN))


class _Names:
    def location_text(self, k):
        return k


def test_a_bounded_queue_watched_at_its_growing_sizes_is_not_named():
    from asmcheck.explore.bfs import SIZE_SPAN, SizeWatch
    from asmcheck.semantics.values import SeqV
    watch = SizeWatch(_Names())
    # the last state found at each watch happens to hold a queue of 0, 1, 2, 3 elements, its bound
    assert [watch.watch({"q": SeqV(tuple(range(n)))}, 10 * n) for n in (0, 1, 2, 3, 3, 2, 3)] == [[]] * 7
    # a sequence that keeps growing is named once, at the first watch SIZE_SPAN above the first size
    watch = SizeWatch(_Names())
    sizes = [0, 5, 9, SIZE_SPAN - 1, SIZE_SPAN, SIZE_SPAN + 7, SIZE_SPAN + 9]
    named = [watch.watch({"s": SeqV(tuple(range(n)))}, n) for n in sizes]
    assert [len(w) for w in named] == [0, 0, 0, 0, 1, 0, 0]
    assert named[4][0].startswith(f"s keeps growing level after level (size {SIZE_SPAN} at depth {SIZE_SPAN})")
