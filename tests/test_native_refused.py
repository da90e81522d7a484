"""Constructs the native engine once refused and now translates, each on a small spec written for
the test, run on both engines (pinned with --engine): the JSON reports must be equal apart from the
engine and the times (states, transitions, depth, verdicts, shortest traces), and the counts are
the ones written here.

- a set of elements made by ``extend`` (of a dynamic subset domain) met in the Python engine's
  order: ``chooseone`` picks the least by ``vkey``;
- a domain holding the elements ``extend`` adds to a domain inside it, ranged over by a choose:
  its named elements, then each extended domain's elements in the order of the spec's domains;
- a dynamic domain that no extend grows, as a value and as a range (it keeps its named elements);
- ``split`` by a regular expression (a backtracking matcher in C over a program made of the
  expression: the parts of Python's ``re.split`` and the Python engine's clean-up), and the
  expressions outside that subset refused with the reason;
- a domain read inside a seq block after an extend of it: the elements finished steps of the block
  made are in the working state (not those of a parallel branch: the visible elements need not be
  numbered 1..n);
- elements made by extend in the keys or values of a function held as a map (an argument over an
  infinite domain), and Reals beside them: each entry is a location of the canonical form, with the
  Python engine's text (a Real's text is Python's repr of the double).

Still refused, with the reason: a local function over Integer of codomain Real (a location of one
call of its rule, which the native state has no slot for).

Engines: both (python is the reference, native is checked)."""
import pytest

from asmcheck.explore.bfs import Explorer
from asmcheck.explore.native_build import Unsupported
from asmcheck.explore.native import NativeExplorer, regex_program
from asmcheck.explore.native_build import compiler
from asmcheck.semantics.machine import Machine
from asmcheck.semantics.resolve import check_file
from helpers import both, write

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


ZED = """asm Zed

import StandardLibrary

signature:
	dynamic abstract domain Zed
	dynamic domain Abc subsetof Zed
	static z0: Zed
	controlled pool: Powerset(Zed)
	controlled got: Zed

definitions:

	main rule r_main =
		par
			extend Abc with $a do pool := including(pool, $a)
			if notEmpty(pool) then got := chooseone(pool) endif
		endpar

default init s0:
	function pool = {z0}
"""


def test_chooseone_is_refused_where_codes_do_not_sort_as_the_python_engine_sorts(tmp_path):
    # the Python engine puts Abc!1 (domain Abc) before z0 (domain Zed): the codes put every named
    # element first, so chooseone on Powerset(Zed) is left to the Python engine
    spec = check_file(write(tmp_path, ZED))
    with pytest.raises(Unsupported, match=r"^chooseone on Powerset\(Zed\)$"):
        NativeExplorer(Machine(spec, {}))


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


SPLIT = r"""asm Split

import StandardLibrary

signature:
	controlled txt: String
	controlled bar: Seq(String)
	controlled sep: Seq(String)
	controlled alt: Seq(String)
	controlled star: Seq(String)
	controlled grp: Seq(String)
	controlled lazy: Seq(String)
	controlled n: Integer

definitions:

	invariant inv_bar over bar: n = 0 or bar = ["a", "|", "b"]
	invariant inv_sep over sep: n = 0 or sep = ["a", "b", "c", "", "d"]
	invariant inv_alt over alt: n = 0 or alt = ["b", "", "b"]
	invariant inv_star over star: n = 0 or star = ["a", "", "b", "c"]
	invariant inv_grp over grp: n = 0 or grp = ["x", "y", "z"]
	invariant inv_lazy over lazy: n = 0 or lazy = ["", "", "b", "b"]
	invariant inv_txt over txt: n < 2 or txt != "a,b"

	main rule r_main =
		par
			bar := split("a|b", "\\|")
			sep := split("a,b; c;;d", "[,;] *")
			alt := split("bab", "a|")
			star := split("axbc", "x*")
			grp := split("xabcyabz", "(?:ab|c)+")
			lazy := split("aabab", "a{1,2}?")
			choose $t in {"a,b", "a;b"} with true do
				if n < 2 then par txt := $t n := n + 1 endpar endif
		endpar

default init s0:
	function txt = ""
	function n = 0
"""


def test_split_by_regular_expressions(tmp_path, capsys):
    # each invariant holds only if the native split gives the Python engine's parts exactly
    code, out = both(tmp_path, capsys, SPLIT)
    assert (out["states"], out["transitions"], out["depth"]) == (5, 8, 2)
    assert [(v["property"], len(v["trace"])) for v in out["violations"]] == [("inv_txt", 3)]


@pytest.mark.parametrize("pattern", ["(a)", "a(?=b)", "(?i)a", "(?:a?)*", "a*+", "a{2", "[[a]", "\\b", "x{3,2}"])
def test_regular_expressions_outside_the_subset_are_refused(pattern):
    assert regex_program(pattern) is None


def test_the_program_of_a_regular_expression():
    # instructions (op, a, b): 3 split, 1 char, 4 jump, 7 match; the literal backslash or the empty text
    assert regex_program("\\\\|") == [4, 3, 1, 3, 1, 92, 0, 4, 3, 0, 7, 0, 0]
    # x*: split to the body or past it, the body, a jump back
    assert regex_program("x*") == [4, 3, 1, 3, 1, 120, 0, 4, 0, 0, 7, 0, 0]


TWIN = """asm Twin

import StandardLibrary

signature:
	dynamic abstract domain Traffic
	controlled status: Traffic -> Boolean
	controlled seen: Agent -> Integer
	controlled picked: Agent -> Traffic
	controlled steps: Integer
	static agentA: Agent
	static agentB: Agent

definitions:

	rule r_agentRule =
		seq
			extend Traffic with $t do
				status($t) := false
			seen(self) := size({$x in Traffic | true : $x})
			choose $q in Traffic with not(status($q)) do
				picked(self) := $q
		endseq

	invariant inv_seen over seen: steps < 2 or seen(agentA) != seen(agentB)

	main rule r_Main =
		if steps < 2 then
			par
				steps := steps + 1
				program(agentA)
				program(agentB)
			endpar
		endif

default init s0:
	function steps = 0

	agent Agent:
		r_agentRule[]
"""


def test_a_domain_read_in_a_seq_block_after_an_extend_by_agents_in_parallel(tmp_path, capsys):
    # step 1: agent A makes Traffic!1 and sees {Traffic!1}; agent B (in parallel) makes Traffic!2
    # and sees {Traffic!2} only, and picks it
    code, out = both(tmp_path, capsys, TWIN)
    assert (out["states"], out["transitions"], out["depth"]) == (4, 4, 2)
    (v,) = out["violations"]
    assert v["property"] == "inv_seen"
    first = v["trace"][1]["state"]
    assert (first["seen(agentA)"], first["seen(agentB)"]) == (1, 1)
    assert (first["picked(agentA)"], first["picked(agentB)"]) == ("Traffic!1", "Traffic!2")


FRAMES = """asm Frames

import StandardLibrary

signature:
	dynamic abstract domain Proc
	enum domain Speed = {SLOW | FAST}
	controlled frame: Prod(Proc, Integer) -> Integer
	controlled rate: Proc -> Real
	controlled owner: Integer -> Proc
	controlled n: Integer

definitions:

	main rule r_main =
		if n < 3 then
			par
				n := n + 1
				choose $s in Speed with true do
					extend Proc with $p do
						par
							if $s = SLOW then rate($p) := 0.00001 else rate($p) := 2.5 endif
							frame($p, n) := n * 10
							owner(n) := $p
						endpar
			endpar
		else
			forall $q in Proc with rate($q) > 1.0 do
				frame($q, 0) := 7
		endif

default init s0:
	function n = 0
"""


def test_elements_made_by_extend_in_a_function_held_as_a_map_and_reals_beside_them(tmp_path, capsys):
    code, out = both(tmp_path, capsys, FRAMES)
    assert (out["states"], out["transitions"], out["depth"]) == (22, 29, 4)
    # the same canonical states, in the same order
    spec = check_file(write(tmp_path, FRAMES))
    py = Explorer(Machine(spec, {}))
    py.run()
    nat = NativeExplorer(Machine(spec, {}))
    try:
        nat.run()
        assert [py.state(i) for i in range(py.n_states)] == [nat.state(i) for i in range(nat.n_states)]
    finally:
        nat.close()


LOCAL = """asm Loc

import StandardLibrary

signature:
	controlled y: Integer

definitions:

	turbo rule r_t =
		local x : Integer -> Real [ x(0) := 1.5 ]
		seq
			x(0) := x(0) + 1.0
			y := rtoi(x(0))
		endseq

	main rule r_main =
		r_t[]

default init s0:
	function y = 0
"""


def test_a_local_function_over_integer_of_codomain_real_is_refused_with_the_reason(tmp_path):
    # (the others run native: tests/test_native_locals.py)
    spec = check_file(write(tmp_path, LOCAL))
    with pytest.raises(Unsupported, match=r"^the local function x at Loc.asm:11:3 \(a location of one call "
                                          r"of its rule, which the native state has no slot for: a codomain Any, "
                                          r"a codomain Real over an infinite domain or more than 64 locations, "
                                          r"or extend in its initial rule\)$"):
        NativeExplorer(Machine(spec, {}))


def _split_cases(seed: int, n: int = 40):
    """``n`` regular expressions of the translated subset and texts to split, made from ``seed``
    (texts and expressions written as AsmetaL string literals allow them: no quote, and a
    backslash only before a backslash, n or t)."""
    import random
    import re
    rnd = random.Random(seed)
    atoms = ["a", "b", ",", " ", ".", "[ab]", "[^a]", "[a-c ]", "\\\\", "\\n", "\\t", "x", "^", "$", "\u00e9",
             "[^,]", "[\\\\a]"]
    quants = ["", "", "*", "+", "?", "{2}", "{1,3}", "{,2}", "*?", "??", "{2,}"]

    def pattern(depth=0):
        k = rnd.random()
        if depth < 2 and k < 0.15:
            return "(?:" + pattern(depth + 1) + "|" + pattern(depth + 1) + ")" + rnd.choice(["", "*", "+", "?", "{1,2}", "*?", "+?"])
        if depth < 2 and k < 0.25:
            return pattern(depth + 1) + "|" + pattern(depth + 1)
        return "".join(rnd.choice(atoms) + rnd.choice(quants) for _ in range(rnd.randint(0, 3)))
    cases = []
    while len(cases) < n:
        p = pattern()
        try:
            re.compile(p)
        except re.error:
            continue
        if regex_program(p) is None:
            continue
        text = "".join(rnd.choice(["a", "b", ",", " ", "x", ".", "1", "\u00e9", "\\\\", "\\n"])
                       for _ in range(rnd.randint(0, 9)))
        cases.append((p, text))
    return cases


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_split_by_generated_regular_expressions_gives_the_python_engines_parts(tmp_path, seed):
    cases = _split_cases(seed)
    sig = "\n".join(f"\tcontrolled s{i}: String\n\tcontrolled o{i}: Seq(String)" for i in range(len(cases)))
    body = "\n".join(f'\t\t\to{i} := split(s{i}, "{p}")' for i, (p, _) in enumerate(cases))
    init = "\n".join(f'\tfunction s{i} = "{t}"' for i, (_, t) in enumerate(cases))
    text = (f"asm Splits\nimport StandardLibrary\nsignature:\n{sig}\ndefinitions:\n\tmain rule r_main =\n"
            f"\t\tpar\n{body}\n\t\tendpar\ndefault init s0:\n{init}\n")
    m = Machine(check_file(write(tmp_path, text)), {})
    (want,) = [nxt for _, _, nxt, _ in m.successors(m.initial_state())]
    nat = NativeExplorer(m)
    try:
        assert nat.run().states == 2
        assert nat.state(1) == want
    finally:
        nat.close()
