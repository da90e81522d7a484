"""Elements made by ``extend`` on the native engine: fresh elements of dynamic abstract domains
(a count per domain in the state; element slots 1..16, twice as many while a search needs more,
up to 64), canonicalised in C (native_canon.c) with the Python canonicaliser's result
(explore/canonical.py): unreferenced elements dropped, symmetric states merged, elements numbered
by their colours.  Each spec runs on both engines (pinned with
--engine); the JSON reports must be equal apart from the engine and the time, and the states must
be the same, in the same order.

Engines: both (python is the reference, native is checked)."""
import json

import pytest

from asmcheck.cli import main
from asmcheck.explore.bfs import Explorer
from asmcheck.explore.native import NativeExplorer
from asmcheck.explore.native_build import Unsupported, compiler
from asmcheck.semantics.machine import Machine
from asmcheck.semantics.resolve import check_file
from helpers import both, write

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

QUEUE = """asm Queue

import StandardLibrary

signature:
	dynamic abstract domain Job
	enum domain Phase = {IDLE | RUN | DONE}
	controlled phase: Job -> Phase
	controlled queue: Seq(Job)
	controlled made: Integer

definitions:

	main rule r_main =
		par
			if made < 3 then
				extend Job with $j do
					par
						phase($j) := IDLE
						queue := append(queue, $j)
						made := made + 1
					endpar
			endif
			if made >= 3 and length(queue) > 0 then
				choose $k in {0 : 1} with $k < length(queue) do
					let ($x = at(queue, iton($k))) in
						if phase($x) = IDLE then phase($x) := RUN
						else if phase($x) = RUN then
							par
								phase($x) := DONE
								queue := excluding(queue, $x)
							endpar
						endif endif
					endlet
			endif
		endpar

default init s0:
	function queue = []
	function made = 0
"""

TOKENS = """asm Tokens

import StandardLibrary

signature:
	dynamic abstract domain Token
	controlled holder: Token -> Boolean
	controlled cur: Token
	controlled n: Integer

definitions:

	main rule r_main =
		if n < 6 then
			par
				n := n + 1
				choose $b in Boolean with true do
					if $b then
						extend Token with $t do
							par
								holder($t) := true
								cur := $t
							endpar
					else
						cur := undef
					endif
			endpar
		endif

default init s0:
	function n = 0
"""

PAIRS = """asm Pairs

import StandardLibrary

signature:
	dynamic abstract domain Node
	controlled nxt: Node -> Node
	controlled val: Node -> Integer
	controlled head: Node
	controlled steps: Integer

definitions:

	main rule r_main =
		if steps < 4 then
			par
				steps := steps + 1
				forall $i in {1 : 2} with true do
					extend Node with $a do
						par
							val($a) := $i
							nxt($a) := head
						endpar
				choose $v in {1 : 2} with true do
					skip
			endpar
		endif

default init s0:
	function steps = 0
"""

MSGS = """asm Msgs

import StandardLibrary

signature:
	dynamic abstract domain Msg
	enum domain Kind = {REQ | ACK}
	controlled kind: Msg -> Kind
	controlled pending: Powerset(Msg)
	controlled last: Msg
	controlled sent: Integer

definitions:

	main rule r_main =
		par
			if sent < 4 then
				choose $k in Kind with true do
					extend Msg with $m do
						par
							kind($m) := $k
							pending := including(pending, $m)
							last := $m
							sent := sent + 1
						endpar
			endif
			if sent >= 4 then
				choose $b in Boolean with true do
					if $b then last := undef endif
			endif
		endpar

default init s0:
	function pending = {}
	function sent = 0
"""

PROCS = """asm Procs

import StandardLibrary

signature:
	dynamic abstract domain Proc
	controlled busy: Proc -> Boolean
	controlled n: Integer
	controlled seen: Integer

definitions:

	invariant inv_few over busy: not (exists $a in Proc, $b in Proc with $a != $b and busy($a) and busy($b) and n = 3 and seen > 3)

	main rule r_main =
		par
			if n < 3 then
				choose $go in Boolean with true do
					if $go then
						extend Proc with $p do
							par
								busy($p) := false
								n := n + 1
							endpar
					endif
			endif
			choose $q in Proc with busy($q) = false do
				busy($q) := true
			ifnone
				if seen < 3 then seen := seen + 1 endif
			forall $r in Proc with busy($r) and n >= 2 and seen < 2 do
				busy($r) := false
		endpar

default init s0:
	function n = 0
	function seen = 0
"""

FOREST = """asm Forest

import StandardLibrary

signature:
	dynamic abstract domain Node
	controlled parent: Node -> Node
	controlled mark: Node -> Boolean
	controlled n: Integer

definitions:

	main rule r_main =
		if n < 6 then
			par
				n := n + 1
				choose $a in Node with true do
					extend Node with $b do
						parent($b) := $a
				ifnone
					extend Node with $r do
						mark($r) := true
			endpar
		else
			choose $m in Node with mark($m) != true do
				mark($m) := true
		endif

default init s0:
	function n = 0
"""

STACK = """asm Stack

import StandardLibrary

signature:
	dynamic abstract domain Cell
	controlled top: Cell
	controlled below: Cell -> Cell

definitions:

	main rule r_main =
		extend Cell with $c do
			par
				below($c) := top
				top := $c
			endpar
"""

SIZES = """asm Sizes

import StandardLibrary

signature:
	dynamic abstract domain Item
	controlled weight: Item -> Integer
	controlled total: Integer
	controlled steps: Integer

definitions:

	main rule r_main =
		if steps < 4 then
			par
				steps := steps + 1
				choose $w in {1 : 2} with true do
					extend Item with $i do
						weight($i) := $w
				total := size(Item)
			endpar
		endif

default init s0:
	function steps = 0
	function total = 0
"""

SEQSIZE = """asm SeqSize

import StandardLibrary

signature:
	dynamic abstract domain Item
	controlled weight: Item -> Integer
	controlled total: Integer

definitions:

	main rule r_main =
		if total < 3 then
			seq
				extend Item with $i do
					weight($i) := 1
				total := size(Item)
			endseq
		endif

default init s0:
	function total = 0
"""




def same_states(tmp_path, text):
    """Both explorers over ``text``: the states (as dicts, in discovery order) must be equal."""
    spec = check_file(write(tmp_path, text))
    py = Explorer(Machine(spec, {}))
    r_py = py.run()
    nat = NativeExplorer(Machine(spec, {}))
    try:
        r_nat = nat.run()
        assert [py.state(i) for i in range(py.n_states)] == [nat.state(i) for i in range(nat.n_states)]
    finally:
        nat.close()
    assert (r_nat.states, r_nat.transitions, r_nat.depth) == (r_py.states, r_py.transitions, r_py.depth)
    return r_nat.states, r_nat.transitions, r_nat.depth


@pytest.mark.parametrize("text, counts", [
    (QUEUE, (14, 20, 9)),       # elements leave the queue and are dropped from Job
    (TOKENS, (43, 74, 6)),      # tokens that nothing refers to any more are dropped
    (PAIRS, (5, 5, 4)),         # two elements a step from a forall: numbered by their values
    (MSGS, (26, 47, 5)),        # elements in a set: texts of sets sorted member by member
    (PROCS, (20, 35, 6)),       # Proc is ranged over (choose, forall, exists): nothing dropped
    (FOREST, (476, 1088, 11)),  # trees: siblings are symmetric, colours refined over parents
    (SIZES, (15, 25, 4)),       # the domain as a value (size(Item)): the elements of the state
], ids=["queue", "tokens", "pairs", "msgs", "procs", "forest", "sizes"])
def test_the_same_canonical_states_in_the_same_order(tmp_path, text, counts):
    assert same_states(tmp_path, text) == counts


def test_reports_and_shortest_traces_equal_with_fresh_elements(tmp_path, capsys):
    text = QUEUE.replace("definitions:\n", "definitions:\n\tinvariant inv_short over queue: length(queue) < 3\n", 1)
    code, out = both(tmp_path, capsys, text)
    assert (code, out["verdict"], out["states"], out["transitions"]) == (1, "violated", 6, 5)
    (v,) = out["violations"]
    assert v["property"] == "inv_short"
    assert [s["state"] for s in v["trace"]] == [
        {"made": 0, "queue": {"seq": []}},
        {"made": 1, "phase(Job!1)": "IDLE", "queue": {"seq": ["Job!1"]}, "Job": {"tuple": ["Job!1"]}},
        {"made": 2, "phase(Job!1)": "IDLE", "phase(Job!2)": "IDLE", "queue": {"seq": ["Job!1", "Job!2"]},
         "Job": {"tuple": ["Job!1", "Job!2"]}},
        {"made": 3, "phase(Job!1)": "IDLE", "phase(Job!2)": "IDLE", "phase(Job!3)": "IDLE",
         "queue": {"seq": ["Job!1", "Job!2", "Job!3"]}, "Job": {"tuple": ["Job!1", "Job!2", "Job!3"]}}]


def test_ranging_over_an_extended_domain_with_an_invariant(tmp_path, capsys):
    code, out = both(tmp_path, capsys, PROCS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (0, "holds", 20, 35, 6)


def test_more_elements_than_the_slots_is_refused_with_the_reason(tmp_path):
    spec = check_file(write(tmp_path, STACK))
    nat = NativeExplorer(Machine(spec, {}))
    try:
        with pytest.raises(Unsupported, match="more than 256 elements of Cell made by extend in one state"):
            nat.run()
    finally:
        nat.close()


def test_a_second_search_of_the_same_model_starts_from_nothing(tmp_path):
    # the canonical forms kept by the first search hold numbers of its value table: the second
    # (same compiled engine, a new value table) must not reuse them
    spec = check_file(write(tmp_path, FOREST))
    for bound, counts in ((50, (52, 71)), (None, (476, 1088)), (None, (476, 1088))):
        nat = NativeExplorer(Machine(spec, {}), max_states=bound)
        try:
            r = nat.run()
        finally:
            nat.close()
        assert (r.states, r.transitions) == counts


def test_a_domain_read_in_a_seq_block_after_its_extend(tmp_path):
    # the Python step function sees the new element in the later steps of the block (size 1, 2, 3)
    assert same_states(tmp_path, SEQSIZE) == (4, 4, 3)


# ------------------------------------------------------------------ the RTPattern library
# The pattern library's schedulers add their phases with extend (SchedulePhase) and every write
# to a swinging buffer makes a DataStream element.  Counts of the Python engine, recorded in the
# issue that asked for this (VisualServoing 15,710 / 31,420, CompleteApplication 70,867 / 141,734,
# RtNondetVS 132,077 / 392,131); VisualServoing is also compared state by state here.

def rt_spec(path: str):
    from conftest import ASMETA, ROOT, need_asmeta
    need_asmeta()
    if path.startswith("tests/"):
        # it imports the library through the import path (as `-I .../asm_examples`)
        from asmcheck.semantics.resolve import set_import_path
        set_import_path([ASMETA / "asm_examples"])
        try:
            return check_file(str(ROOT / path))
        finally:
            set_import_path([])
    return check_file(str(ASMETA / "asm_examples" / "RTPatternLibrary" / path))


@pytest.mark.slow
def test_rtpattern_visual_servoing_state_by_state(tmp_path):
    spec = rt_spec("Application/VisualServoing.asm")
    py = Explorer(Machine(spec, {}))
    r_py = py.run()
    nat = NativeExplorer(Machine(spec, {}))
    try:
        r_nat = nat.run()
        assert (r_nat.states, r_nat.transitions, r_nat.depth) == (r_py.states, r_py.transitions, r_py.depth) \
            == (15710, 31420, 15708)
        for i in range(0, r_py.states, 97):
            assert py.state(i) == nat.state(i)
        assert py.state(r_py.states - 1) == nat.state(r_nat.states - 1)
    finally:
        nat.close()


@pytest.mark.slow
@pytest.mark.parametrize("path, counts", [
    ("Application/CompleteApplication.asm", (70867, 141734)),
    ("tests/rtpattern/RtNondetVS.asm", (132077, 392131)),
], ids=["complete_application", "rt_nondet_vs"])
def test_rtpattern_counts_on_the_native_engine(path, counts):
    spec = rt_spec(path)
    nat = NativeExplorer(Machine(spec, {}))
    try:
        r = nat.run()
        assert (r.verdict, r.states, r.transitions) == ("holds", *counts)
    finally:
        nat.close()


def test_a_search_that_needs_more_element_slots_starts_again_with_more(tmp_path):
    # 20 cells at once: more than the first 16 slots, so the engine is made again with 32
    text = STACK.replace("asm Stack", "asm Stack20").replace(
        "\t\textend Cell with $c do", "\t\tif size < 20 then extend Cell with $c do").replace(
        "\t\t\tendpar\n", "\t\t\tendpar\n\t\tendif\n").replace(
        "\tcontrolled below: Cell -> Cell\n", "\tcontrolled below: Cell -> Cell\n\tcontrolled size: Integer\n").replace(
        "\t\t\t\ttop := $c\n", "\t\t\t\ttop := $c\n\t\t\t\tsize := size + 1\n") + "default init s0:\n\tfunction size = 0\n"
    assert same_states(tmp_path, text) == (21, 21, 20)


def test_the_threads_of_a_parallel_search_canonicalise_alike(tmp_path, capsys, monkeypatch):
    # every level on the threads, however small: each thread's search context keeps its own tables
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    path = write(tmp_path, FOREST)
    docs = []
    for n in (1, 2, 3):
        code = main(["explore", path, "--format", "json", "--engine", "native", "--workers", str(n), "--deadlock"])
        doc = json.loads(capsys.readouterr().out)
        for key in ("seconds", "compile_seconds"):
            doc.pop(key, None)
        assert doc.pop("workers", 1) == n
        docs.append((code, doc))
    assert docs[0] == docs[1] == docs[2]
    assert (docs[0][1]["engine"], docs[0][1]["states"], docs[0][1]["transitions"]) == ("native", 476, 1069)   # the Python engine: the same
