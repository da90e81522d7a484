"""Constructs the native engine once refused and now translates, each on a small spec written for
the test, run on both engines (pinned with --engine): the JSON reports must be equal apart from the
engine and the times (states, transitions, depth, verdicts, shortest traces), and the counts are
the ones written here.

- a set of elements made by ``extend`` (of a dynamic subset domain) met in the Python engine's
  order: ``chooseone`` picks the least by ``vkey``;
- a domain holding the elements ``extend`` adds to a domain inside it, ranged over by a choose:
  its named elements, then each extended domain's elements in the order of the spec's domains;
- a dynamic domain that no extend grows, as a value and as a range (it keeps its named elements);

Engines: both (python is the reference, native is checked)."""
import pytest

from asmcheck.explore.native_build import compiler
from helpers import both

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

PICK = """asm Pick

import StandardLibrary

signature:
	dynamic abstract domain Ev
	dynamic domain Tmo subsetof Ev
	static e0: Ev
	controlled armed: Ev -> Boolean
	controlled age: Ev -> Integer
	controlled last: Ev
	controlled n: Integer

definitions:

	invariant inv_few over n: not (n = 4 and last = e0)

	main rule r_main =
		par
			if n < 4 then
				par
					n := n + 1
					choose $b in Boolean with true do
						if $b then
							extend Tmo with $t do par armed($t) := true age($t) := n endpar
						else
							extend Ev with $e do par armed($e) := true age($e) := n endpar
						endif
				endpar
			endif
			let ($s = {$x in Tmo | armed($x) : $x}) in
				if notEmpty($s) then
					armed(chooseone($s)) := false
				endif
			endlet
			choose $z in Ev with armed($z) = false do
				last := $z
		endpar

default init s0:
	function n = 0
	function armed($a in Ev) = false
"""


def test_chooseone_on_extended_elements_and_a_domain_holding_two_extended_ones(tmp_path, capsys):
    code, out = both(tmp_path, capsys, PICK)
    assert (out["states"], out["transitions"], out["depth"]) == (51, 71, 4)
    assert out["verdict"] == "violated"
    (v,) = out["violations"]
    assert v["property"] == "inv_few"
    assert len(v["trace"]) == 5


ROSTER = """asm Roster

import StandardLibrary

signature:
	dynamic abstract domain Node
	static na: Node
	static nb: Node
	static nc: Node
	controlled mark: Node -> Boolean
	controlled left: Powerset(Node)
	controlled k: Integer

definitions:

	invariant inv_left over left: k < 3 or size(left) = 0 or contains(left, nc)

	main rule r_main =
		par
			left := difference(Node, {$y in Node | mark($y) : $y})
			choose $x in Node with mark($x) != true do mark($x) := true
			if k < 3 then k := k + 1 endif
		endpar

default init s0:
	function k = 0
	function left = {}
	function mark($n in Node) = false
"""


def test_a_dynamic_domain_nothing_extends_as_a_value(tmp_path, capsys):
    code, out = both(tmp_path, capsys, ROSTER)
    assert (out["states"], out["transitions"], out["depth"]) == (14, 17, 4)
    assert out["verdict"] == "violated"
    (v,) = out["violations"]
    assert v["property"] == "inv_left"
    assert len(v["trace"]) == 4
