"""More successors of one state than the explorer enumerates: a limit (incomplete, exit 3) that
names the choices that multiply and the way to bound them, never a violation of the spec.
Engines: python (the native engine hands such a state to the Python engine)."""
from __future__ import annotations

import pytest

import asmcheck
from asmcheck.explore.bfs import Explorer

from helpers import write

pytestmark = pytest.mark.engines("python")

TWO_MON = """asm TwoMon
import StandardLibrary
signature:
	monitored a: Integer
	monitored b: Integer
	controlled s: Integer
definitions:
	invariant inv_s over s: s < 1000
	main rule r_main = s := (a + b) mod 5
default init s0:
	function s = 0
"""

CHOOSER = """asm Chooser
import StandardLibrary
signature:
	domain Big subsetof Integer
	controlled s: Integer
definitions:
	domain Big = {0 : 99}
	main rule r_main = choose $x in Big, $y in Big with true do s := $x * 100 + $y
default init s0:
	function s = 0
"""


def test_too_many_monitored_combinations_is_a_limit(tmp_path, monkeypatch):
    monkeypatch.setattr(Explorer, "MAX_SUCCESSORS", 1000)
    run = asmcheck.load(write(tmp_path, TWO_MON), int_range=(0, 99)).explore(engine="python")
    assert (run.verdict, run.states, run.transitions, run.exit_code) == ("incomplete", 1, 0, 3)
    assert run.violations == []
    assert run.reason == ("more than 1,000 successors of one state: the step chooses among a (100 values), "
                          "b (100 values); bound the monitored inputs with --monitored NAME=LO..HI or NAME=V1,V2")
    assert run.rows == [{"property": "inv_s", "kind": "invariant", "verdict": "incomplete"}]


def test_too_many_choose_alternatives_is_a_limit(tmp_path, monkeypatch):
    monkeypatch.setattr(Explorer, "MAX_SUCCESSORS", 50)
    run = asmcheck.load(write(tmp_path, CHOOSER)).explore(engine="python")
    assert (run.verdict, run.exit_code) == ("incomplete", 3)
    assert run.reason == ("more than 50 successors of one state: the step chooses among choose at "
                          "Chooser.asm:8:21 (10,000 values); bound the ranges of the chooses (a smaller domain, "
                          "or --int-range)")


def test_under_the_limit_nothing_changes(tmp_path):
    run = asmcheck.load(write(tmp_path, TWO_MON), int_range=(0, 9)).explore(engine="python")
    assert (run.verdict, run.states, run.transitions) == ("holds", 5, 25)
