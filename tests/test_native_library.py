"""The native explorer on the StandardLibrary functions over strings, sequences, bags, map values
and sets, and on map, bag and string values held in locations: each spec written for the test runs
on both engines (pinned with --engine, and through the two explorers directly), which must give the
same JSON report and the same states in the same order.  A spec whose search meets a run-time error
is answered by the Python engine (it keeps the well-defined successors of a failing state); there the
native search must find the same first error, with the same message and trace.

Engines: both (python is the reference, native is checked)."""
import json

import pytest

from asmcheck.cli import main
from asmcheck.explore.bfs import Explorer
from asmcheck.explore.native import NativeExplorer
from asmcheck.explore.native_build import Unsupported, compiler
from asmcheck.semantics.values import show
from helpers import both, machine, write

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

STRINGS = """asm Strs
import StandardLibrary
signature:
	controlled s: String
	controlled parts: Seq(String)
	controlled n: Integer
	controlled found: Boolean
	controlled k: Integer
	controlled head: String
	monitored up: Boolean
definitions:
	main rule r_main =
		if k < 3 then
			par
				k := k + 1
				if up then s := toUpper(concat(s, "-b")) else s := toLower(concat(s, "C")) endif
				parts := split(s, "-")
				n := size(s) + print("x", k)
				found := contains(s, "A-")
				head := subString(s, 0, 2)
			endpar
		else
			head := subString(s, 2, 1)
		endif
default init s0:
	function s = "a-A"
	function parts = []
	function n = 0
	function found = false
	function k = 0
	function head = ""
"""

MAPS_BAGS = """asm MapsBags
import StandardLibrary
signature:
	enum domain Color = {RED | GREEN | BLUE}
	controlled m: Map(Integer, Color)
	controlled b: Bag(Integer)
	controlled sq: Seq(Integer)
	controlled st: Powerset(Integer)
	controlled c: Color
	controlled ix: Integer
	static colorOf: Integer -> Color
	controlled w: Integer
	monitored pick: Boolean
definitions:
	function colorOf($x in Integer) = at({1 -> RED, 2 -> GREEN, 1 -> BLUE}, $x)
	main rule r_main =
		if ix < 4 then
			par
				ix := ix + 1
				c := colorOf(ix)
				m := {$x in {1 : 3} | $x <= ix : $x -> colorOf($x)}
				if pick then b := including(b, ix mod 2) else b := excluding(b, 0) endif
				if pick then sq := insertAt(sq, 0n, ix mod 3) else sq := replaceAt(sq, 0n, 7) endif
				st := asSet(sq)
				w := ntoi(count(b, 1)) * 10 + ntoi(count(b, 0))
			endpar
		else
			par
				sq := asSequence(st)
				if count(b, 3) = 0n then b := union(b, <3, 3, 0>) endif
				m := assign(merge(m, {3 -> GREEN, 1 -> RED}), 3, BLUE)
			endpar
		endif
default init s0:
	function m = {2 -> BLUE}
	function b = <1, 0, 1>
	function sq = [5]
	function st = {}
	function c = RED
	function ix = 0
	function w = 0
"""

# insertAt beyond the end of the sequence is a run-time error of the step
INSERT_ERROR = """asm InsertErr
import StandardLibrary
signature:
	controlled q: Seq(Integer)
	monitored far: Boolean
definitions:
	main rule r_main =
		if length(q) < 3 then
			if far then q := insertAt(q, 3n, 1) else q := insertAt(q, 0n, length(q)) endif
		endif
default init s0:
	function q = []
"""

# a function over sets of tuples, a bag comprehension and literals in a switch, the elements of
# a set of enum constants as a sequence
COLLECTIONS = """asm Colls
import StandardLibrary
signature:
	enum domain Dir = {NN | EE | SS | WW}
	domain Point subsetof Prod(Integer, Integer)
	controlled f: Powerset(Point) -> Integer
	controlled ds: Powerset(Dir)
	controlled order: Seq(Dir)
	controlled g: Integer
	monitored d: Dir
definitions:
	main rule r_main =
		par
			f({(0, 0)}) := g
			f({(0, 0), (1, 2)}) := g * 2
			if size(ds) < 3 then ds := including(ds, d) else ds := excluding(ds, d) endif
			order := asSequence(ds)
			switch <1, 4, 9>
				case <>: g := 0
				case <$x in {1 : 3} : $x * $x>: g := (g + 1) mod 3
				otherwise g := 5
			endswitch
		endpar
default init s0:
	function ds = {}
	function order = []
	function g = 0
"""

# intervals with bounds computed in the state, toString of an integer, print of two values, and
# the clock functions, which have no value (the Python engine's run-time error)
RANGES = """asm Ranges
import StandardLibrary
signature:
	controlled n: Integer
	controlled s: Powerset(Integer)
	controlled q: Seq(Integer)
	controlled txt: String
	controlled ok: Boolean
	controlled printed: Integer
definitions:
	main rule r_main =
		if n < 4 then
			par
				n := n + 1
				s := {1 : n}
				q := [n : 6, 2]
				txt := concat(toString(n - 2), "!")
				ok := (let ($d = {0 : n}) in (exists $x in $d, $y in $d with $x * $y = 6) endlet)
				printed := print(n, txt)
			endpar
		else
			printed := currTimeSecs
		endif
default init s0:
	function n = 0
	function txt = ""
"""

# map literals over named elements of an abstract domain (keys alone and in tuples), a map and a
# bag of those elements in locations
ABSTRACT_KEYS = """asm AbsMap
import StandardLibrary
signature:
	abstract domain Node
	enum domain Mode = {IDLE | BUSY}
	static n1: Node
	static n2: Node
	static n3: Node
	static next: Node -> Node
	static modeOf: Node -> Mode
	controlled cur: Node
	controlled seen: Map(Node, Mode)
	controlled hist: Bag(Node)
definitions:
	function next($n in Node) = at({n1 -> n2, n2 -> n3, n3 -> n1}, $n)
	function modeOf($n in Node) = at({(n1, 1) -> IDLE, (n2, 1) -> BUSY}, ($n, 1))
	main rule r_main =
		par
			cur := next(cur)
			seen := assign(seen, cur, modeOf(cur))
			if count(hist, cur) < 2n then hist := including(hist, cur) endif
		endpar
default init s0:
	function cur = n1
	function seen = {->}
	function hist = <>
"""

# $v, bound by the quantifier of the guard, stays known in the rest of the rule but is bound
# nowhere there: reading it is a run-time error
UNBOUND = """asm Unbound
import StandardLibrary
signature:
	controlled x: Integer
	monitored go: Boolean
definitions:
	main rule r_main =
		if (exists $v in {1 : 3} with $v > x) then
			if go then x := x + 1 else x := $v endif
		endif
default init s0:
	function x = 0
"""

# sum, chooseone (the least element outside the initialisation), allin, notallin and
# symmetricDifference on sets of integers
SET_FUNCTIONS = """asm SetFns
import StandardLibrary
signature:
	controlled a: Powerset(Integer)
	controlled b: Powerset(Integer)
	controlled total: Integer
	controlled least: Integer
	controlled sub: Boolean
	controlled nsub: Boolean
	monitored grow: Boolean
definitions:
	main rule r_main =
		if size(a) < 4 then
			par
				if grow then a := including(a, size(a) * 3 - 1) else a := symmetricDifference(a, {2, -1}) endif
				total := sum(a) + sum(<1, 1>)
				least := chooseone(a)
				sub := allin(a, b)
				nsub := notallin(b, a)
			endpar
		endif
default init s0:
	function a = {}
	function b = {-1, 2, 5}
	function total = 0
"""

# asSequence and chooseone of sets of strings (ordered by their characters) and of named elements
# of an abstract domain (by name)
ORDERED = """asm Ordered
import StandardLibrary
signature:
	abstract domain Node
	static alpha: Node
	static beta: Node
	static gamma: Node
	controlled names: Powerset(String)
	controlled nodes: Powerset(Node)
	controlled nameSeq: Seq(String)
	controlled nodeSeq: Seq(Node)
	controlled firstName: String
	controlled firstNode: Node
	monitored pick: Boolean
definitions:
	main rule r_main =
		par
			if size(names) < 4 then
				if pick then names := including(names, concat("b", toString(size(names)))) else names := including(names, "ab") endif
			endif
			if pick then nodes := including(nodes, gamma) else nodes := excluding(including(nodes, alpha), beta) endif
			nameSeq := asSequence(names)
			nodeSeq := asSequence(nodes)
			firstName := chooseone(names)
			firstNode := chooseone(nodes)
		endpar
default init s0:
	function names = {"b", "", "B"}
	function nodes = {}
"""

# strings and sequences that grow for 300 steps: the value table's pool moves while a split or a
# subsequence is made from one of its entries
GROW = """asm Grow
import StandardLibrary
signature:
	controlled s: String
	controlled parts: Seq(String)
	controlled tailq: Seq(Integer)
	controlled q: Seq(Integer)
	controlled k: Integer
definitions:
	main rule r_main =
		if k < 300 then
			par
				k := k + 1
				s := concat(s, concat("-", toString(k)))
				parts := split(s, "-")
				q := append(q, k)
				tailq := subSequence(q, 1n, iton(length(q)))
			endpar
		endif
default init s0:
	function s = "x"
	function parts = []
	function q = []
	function tailq = []
	function k = 0
"""




def ends_on_error(tmp_path, capsys, text):
    """A spec whose search meets a failing step: the native search finds the same first error
    (message and trace) as the Python engine and, as it does, keeps the well-defined successors of
    a failing state: the same report."""
    from asmcheck.explore.trace import build_trace
    from asmcheck.report.trace import trace_json
    path = write(tmp_path, text)
    code_n = main(["explore", path, "--format", "json", "--engine", "native"])
    handed = json.loads(capsys.readouterr().out)
    # the native engine itself goes on past the failing step (tests/test_native_errors.py)
    assert (handed.pop("engine"), handed.pop("engine_note", None)) == ("native", None)
    handed.pop("compile_seconds")
    code = main(["explore", path, "--format", "json", "--engine", "python"])
    out = json.loads(capsys.readouterr().out)
    for doc in (handed, out):
        doc.pop("seconds")
    assert (code_n, handed) == (code, {k: x for k, x in out.items() if k not in ("engine", "compile_seconds")})
    m = machine(tmp_path, text)
    nat = NativeExplorer(m)
    try:
        (v,) = [v for v in nat.run().violations if v.prop.name == "error"]
        (py,) = [x for x in out["violations"] if x["property"] == "error"]
        assert v.message == py["message"]
        assert trace_json(m, build_trace(nat, v)) == py["trace"]
    finally:
        nat.close()
    for key in ("compile_seconds", "engine"):
        out.pop(key, None)
    return code, out


def states(tmp_path, text) -> list[dict]:
    """Every state the two explorers find, in the order found (equal on both), printed."""
    m = machine(tmp_path, text)
    py = Explorer(m)
    r1 = py.run()
    nat = NativeExplorer(m)
    try:
        r2 = nat.run()
        assert (r2.states, r2.transitions) == (r1.states, r1.transitions)
        got = [nat.state(i) for i in range(r2.states)]
    finally:
        nat.close()
    want = [py.state(i) for i in range(r1.states)]
    assert got == want
    return [{m.location_text(k): show(v) for k, v in st.items()} for st in want]


def test_string_functions(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, STRINGS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 15, 14, 3)
    (v,) = out["violations"]
    assert (v["property"], v["message"]) == ("error", "subString: indexes 2, 1 out of range for a string of length 6")
    assert [s["state"]["s"] for s in v["trace"]] == ["a-A", "a-ac", "a-acc", "a-accc"]
    assert v["trace"][1]["state"] == {"found": False, "head": "a-", "k": 1, "n": 5, "parts": {"seq": ["a", "A"]},
                                      "s": "a-ac"}
    sts = states(tmp_path, STRINGS)
    assert len(sts) == 15
    assert sts[2] == {"s": '"A-A-B"', "parts": '["a", "A"]', "n": "5", "found": "false", "k": "1", "head": '"a-"'}
    assert sts[-1] == {"s": '"A-A-B-B-B"', "parts": '["A", "A", "B", "B"]', "n": "9", "found": "true", "k": "3",
                       "head": '"A-"'}


def test_maps_bags_and_sequence_functions(tmp_path, capsys):
    code, out = both(tmp_path, capsys, MAPS_BAGS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (
        0, "no property checked", 47, 62, 5)
    sts = states(tmp_path, MAPS_BAGS)
    assert len(sts) == 47
    assert sts[0] == {"m": "{2->BLUE}", "b": "<0, 1, 1>", "sq": "[5]", "st": "{}", "c": "RED", "ix": "0", "w": "0"}
    # pick false first: colorOf(0) is undef, 0 leaves the bag, [5] becomes [7]
    assert sts[1] == {"m": "{}", "b": "<1, 1>", "sq": "[7]", "st": "{5}", "ix": "1", "w": "21"}
    assert sts[2] == {"m": "{}", "b": "<0, 0, 1, 1>", "sq": "[0, 5]", "st": "{5}", "ix": "1", "w": "21"}
    # the map comprehension's 3 -> undef, merged with 3 -> GREEN and 1 -> RED, then 3 assigned BLUE
    assert sts[-1] == {"m": "{1->RED, 2->GREEN, 3->BLUE}", "b": "<0, 0, 0, 0, 1, 1, 1, 1, 3, 3>",
                       "sq": "[0, 1, 2, 5]", "st": "{0, 1, 2, 5}", "ix": "4", "w": "33"}


def test_insert_at_out_of_range_is_the_run_time_error_of_the_python_engine(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, INSERT_ERROR)
    # far fails in [], [0] and [1, 0]; the other branch goes on to [2, 1, 0]
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 4, 4, 3)
    (v,) = out["violations"]
    assert (v["property"], v["message"]) == ("error", "insertAt: index 3 out of range 0..0")


def test_functions_over_sets_bag_switch_and_a_set_as_a_sequence(tmp_path, capsys):
    code, out = both(tmp_path, capsys, COLLECTIONS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (
        0, "no property checked", 155, 530, 6)
    sts = states(tmp_path, COLLECTIONS)
    assert len(sts) == 155
    assert sts[1] == {"ds": "{NN}", "order": "[]", "g": "1", "f({(0, 0)})": "0", "f({(0, 0), (1, 2)})": "0"}
    # order is the previous ds in the order of the enum's declaration; the bag literal equals the
    # bag comprehension <1, 4, 9> (g counts modulo 3)
    assert sts[-1] == {"ds": "{EE, SS}", "order": "[EE, SS, WW]", "g": "0", "f({(0, 0)})": "2",
                       "f({(0, 0), (1, 2)})": "4"}


def test_what_the_native_engine_leaves_to_the_python_engine(tmp_path):
    # split by a regular expression outside the translated subset (a capturing group), the
    # elements of a set of tuples as a sequence (their codes are not in the Python engine's order)
    for decl, rule, reason in [
        ("controlled s: Seq(String)", 's := split("a.b", "(a)")',
         "split on String by a regular expression outside the translated subset"),
        ("controlled s: Seq(Prod(Integer, Integer))", "s := asSequence({(2, 1), (1, 3)})",
         "asSequence on Powerset(Prod(Integer,Integer))"),
    ]:
        text = f"asm Refused\nimport StandardLibrary\nsignature:\n\t{decl}\ndefinitions:\n\tmain rule r_main = {rule}\n"
        with pytest.raises(Unsupported) as e:
            NativeExplorer(machine(tmp_path, text))
        assert str(e.value).startswith(reason)


def test_intervals_to_string_print_and_the_clock(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, RANGES)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 5, 4, 4)
    (v,) = out["violations"]
    assert v["message"] == "the machine's clock (currTime*) has no value in asmcheck: use a monitored function"
    assert [(s["state"]["q"]["seq"], s["state"]["s"]["set"], s["state"]["txt"], s["state"]["ok"])
            for s in v["trace"][1:]] == [([0, 2, 4, 6], [], "-2!", False), ([1, 3, 5], [1], "-1!", False),
                                         ([2, 4, 6], [1, 2], "0!", False), ([3, 5], [1, 2, 3], "1!", True)]
    assert {s["state"]["printed"] for s in v["trace"][1:]} == {2}


def test_maps_and_bags_over_abstract_elements(tmp_path, capsys):
    code, out = both(tmp_path, capsys, ABSTRACT_KEYS, "--deadlock")
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (0, "holds", 9, 9, 8)
    sts = states(tmp_path, ABSTRACT_KEYS)
    # seen and hist take cur's value before the step; modeOf(n3) is undef, kept in the map
    assert [(st["cur"], st["seen"], st["hist"]) for st in sts[:4]] == [
        ("n1", "{}", "<>"), ("n2", "{n1->IDLE}", "<n1>"), ("n3", "{n1->IDLE, n2->BUSY}", "<n1, n2>"),
        ("n1", "{n1->IDLE, n2->BUSY, n3->undef}", "<n1, n2, n3>")]
    assert (sts[-1]["cur"], sts[-1]["hist"]) == ("n3", "<n1, n1, n2, n2, n3, n3>")


def test_a_variable_read_where_nothing_binds_it_is_the_run_time_error(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, UNBOUND)
    # go false fails while x < 3; go true counts x up to 3, where the guard is false
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 4, 4, 3)
    (v,) = out["violations"]
    assert (v["property"], v["message"]) == ("error", "variable $v is not bound here")
    assert v["failing_step"]["choices"] == [{"kind": "monitored", "at": "go", "value": False}]


def test_sum_chooseone_allin_and_symmetric_difference(tmp_path, capsys):
    code, out = both(tmp_path, capsys, SET_FUNCTIONS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (
        0, "no property checked", 17, 33, 6)
    sts = states(tmp_path, SET_FUNCTIONS)
    assert len(sts) == 17
    # grow false first: {} xor {2, -1}; sum({}) + sum(<1, 1>) = 2; chooseone({}) is undef
    assert sts[1] == {"a": "{-1, 2}", "b": "{-1, 2, 5}", "total": "2", "sub": "true", "nsub": "true"}
    assert sts[7] == {"a": "{5}", "b": "{-1, 2, 5}", "total": "8", "sub": "true", "nsub": "false", "least": "-1"}
    assert sts[11] == {"a": "{-1, 2, 5}", "b": "{-1, 2, 5}", "total": "7", "sub": "true", "nsub": "true",
                       "least": "5"}


def test_sets_of_strings_and_of_abstract_elements_in_the_python_engines_order(tmp_path, capsys):
    code, out = both(tmp_path, capsys, ORDERED)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (
        0, "no property checked", 9, 14, 3)
    sts = states(tmp_path, ORDERED)
    assert len(sts) == 9
    assert sts[3] == {"names": '{"", "B", "ab", "b"}', "nodes": "{alpha}", "nameSeq": '["", "B", "ab", "b"]',
                      "nodeSeq": "[alpha]", "firstName": '""', "firstNode": "alpha"}
    assert sts[5] == {"names": '{"", "B", "b", "b3"}', "nodes": "{alpha, gamma}", "nameSeq": '["", "B", "b", "b3"]',
                      "nodeSeq": "[gamma]", "firstName": '""', "firstNode": "gamma"}
    assert (sts[-1]["nodeSeq"], sts[-1]["firstNode"]) == ("[alpha, gamma]", "alpha")


def test_named_elements_numbered_out_of_the_order_of_their_names_are_left_to_the_python_engine(tmp_path):
    for first, second, accepted in (("zed", "abe", False), ("abe", "zed", True)):
        text = (f"asm Ab\nimport StandardLibrary\nsignature:\n\tabstract domain Node\n\tstatic {first}: Node\n"
                f"\tstatic {second}: Node\n\tcontrolled s: Seq(Node)\ndefinitions:\n"
                f"\tmain rule r_main = s := asSequence({{zed, abe}})\n")
        if accepted:
            assert states(tmp_path, text) == [{}, {"s": "[abe, zed]"}]
        else:
            with pytest.raises(Unsupported, match=r"^asSequence on Powerset\(Node\)$"):
                NativeExplorer(machine(tmp_path, text))


def test_values_made_from_entries_of_a_growing_table(tmp_path, capsys):
    code, out = both(tmp_path, capsys, GROW)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (
        0, "no property checked", 301, 301, 300)
    sts = states(tmp_path, GROW)
    last = sts[-1]
    assert last["k"] == "300" and last["s"] == '"x-' + "-".join(str(i) for i in range(300)) + '"'
    assert last["parts"] == "[" + ", ".join(f'"{x}"' for x in ["x"] + [str(i) for i in range(299)]) + "]"
    assert last["tailq"] == "[" + ", ".join(str(i) for i in range(1, 299)) + "]"


def test_an_ltl_trace_through_states_holding_bags_and_maps_the_search_made(tmp_path, capsys):
    # the trace is replayed: its states, with values made during the search, are found by value
    text = MAPS_BAGS.replace("asm MapsBags", "asm MapsBagsLtl").replace(
        "import StandardLibrary", "import StandardLibrary\nimport LTLLibrary").replace(
        "\tmain rule r_main =", "\tLTLSPEC g(ix < 3)\n\tmain rule r_main =")
    code, out = both(tmp_path, capsys, text)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 47, 62, 5)
    (v,) = out["violations"]
    assert v["property"] == "ltl_1"
    # a lasso: the pick-false path up to ix = 4, then the else branch, which repeats its state
    assert [s["state"]["ix"] for s in v["trace"]] == [0, 1, 2, 3, 4, 4, 4]
    assert [s["state"]["b"]["bag"] for s in v["trace"][4:]] == [[1, 1], [0, 1, 1, 3, 3], [0, 1, 1, 3, 3]]
    assert v["trace"][4]["state"]["m"] == {"map": [[1, "BLUE"], [2, "GREEN"], [3, None]]}
    assert v["trace"][5]["state"]["m"] == {"map": [[1, "RED"], [2, "GREEN"], [3, "BLUE"]]}
