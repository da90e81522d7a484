"""The canonical form of a state with elements made by ``extend`` (native_canon.c), worked out with
fewer steps: what each location's walk looks at is known from its slot (an argument that is an
element, an argument or a value of a type with members, a value that is an element or holds none),
only the values that hold elements are renamed, and texts are ordered by their first eight bytes
before their other bytes are read.  Each shortcut is checked on a small spec written for the test:
the same states in the same order as the Python engine, exact counts, one thread and two.

Engines: both (python is the reference, native is checked)."""
import json

import pytest

from asmcheck.cli import main
from asmcheck.explore.native_build import compiler

from helpers import both, engine_free, write
from test_native_extend import same_states

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

# Tok: ranged over (choose), kept; Msg: nobody ranges over it, an element no location holds is
# dropped.  stateOfTok / stateOfTokB: locations over an element (an argument that is an element)
# whose texts share their first eight bytes; link: over a pair of elements (an argument with
# members); partner, head: an element as the value; q, inbox: values with members; a step that
# changes tick only (no location that may hold elements) beside steps that change such locations.
WALKS = """asm CanonWalks
import StandardLibrary
signature:
	dynamic abstract domain Tok
	dynamic abstract domain Msg
	domain Small subsetof Integer
	controlled stateOfTok: Tok -> Small
	controlled stateOfTokB: Tok -> Small
	controlled partner: Tok -> Tok
	controlled link: Prod(Tok, Tok) -> Boolean
	controlled q: Seq(Tok)
	controlled inbox: Powerset(Msg)
	controlled payload: Msg -> Small
	controlled head: Tok
	controlled made: Small
	controlled tick: Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 3}
	main rule r_main =
		par
			tick := (tick + 1) mod 2
			if go then
				if made < 2 then
					extend Tok with $t do
						par
							stateOfTok($t) := 0
							q := append(q, $t)
							made := made + 1
							head := $t
						endpar
				else
					if tick = 0 and size(inbox) < 2 then
						extend Msg with $m do
							par
								inbox := including(inbox, $m)
								payload($m) := size(inbox)
							endpar
					endif
				endif
			else
				choose $x in Tok with stateOfTok($x) < 2 do
					par
						stateOfTok($x) := stateOfTok($x) + 1
						stateOfTokB($x) := tick
						partner($x) := head
						link($x, head) := true
						if not(isEmpty(inbox)) then
							choose $n in inbox with true do inbox := excluding(inbox, $n)
						endif
					endpar
			endif
		endpar
default init s0:
	function made = 0
	function tick = 0
	function q = []
	function inbox = {}
"""


def test_the_same_canonical_states_in_the_same_order(tmp_path):
    assert same_states(tmp_path, WALKS) == (2490, 5146, 18)


def test_one_thread_two_threads_and_the_python_engine_report_alike(tmp_path, capsys, monkeypatch):
    # every level on the threads, however small: each thread's search context has its own tables
    code, out = both(tmp_path, capsys, WALKS, "--deadlock")
    assert code == 0
    assert (out["states"], out["transitions"], out["depth"]) == (2490, 5146, 18)
    assert [(p["property"], p["verdict"]) for p in out["properties"]] == [("deadlock", "holds")]
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    path = write(tmp_path, WALKS)
    code2 = main(["explore", path, "--format", "json", "--engine", "native", "--workers", "2", "--deadlock"])
    out2 = json.loads(capsys.readouterr().out)
    assert out2.pop("workers", 1) == 2
    assert (code2, engine_free(out2, "native")) == (code, out)
