"""The native explorer on rule forms beyond flat finite ranges: choose, forall and comprehensions
over sets and sequences computed in the state (met in the Python engine's order), rule values,
updates of macro parameters bound to locations, turbo calls and their return values.  Each spec
runs on both engines (pinned with --engine); the JSON reports must be equal apart from the
engine and the time, and the native run must not fall back.

Engines: both (python is the reference, native is checked)."""
import pytest

from helpers import both
from test_native_engine import ends_on_error

pytestmark = pytest.mark.engines("native")




def summary(out):
    return out["verdict"], out["states"], out["transitions"], out["depth"]


POOL = """\
asm Pool
import StandardLibrary
signature:
	enum domain Color = {RED | GREEN | BLUE}
	controlled pool: Powerset(Integer)
	controlled taken: Seq(Integer)
	controlled groups: Powerset(Powerset(Integer))
	controlled last: Integer
	controlled big: Integer
	controlled seen: Powerset(Color)
	controlled col: Color
definitions:
	invariant inv_big over big: big != 40
	main rule r_main =
		par
			if length(taken) < 4 then choose $x in pool with $x mod 2 = 0 or size(pool) < 3 do
				par
					pool := excluding(pool, $x)
					taken := append(taken, $x)
				endpar
			ifnone
				pool := {1, 2, 3, 4} endif
			choose $g in [[1, 5], [3, 2]], $y in $g with $y > last do last := $y
			choose $k in [$t in taken | $t > 1 : $t * 10] do big := $k
			choose $c in seen do par col := $c seen := excluding(seen, $c) endpar ifnone seen := {BLUE, RED}
		endpar
default init s0:
	function pool = {4, 1, 3, 2}
	function taken = []
	function groups = {{1, 5}, {2, 3}}
	function last = 0
	function big = 0
	function seen = {GREEN, BLUE}
	function col = RED
"""

UNDEF_RANGE = """
asm Undef
import StandardLibrary
signature:
	controlled s: Powerset(Integer)
	controlled n: Integer
definitions:
	main rule r_main =
		choose $x in s with $x > n do par n := $x s := if n < 2 then including(s, n + 3) else undef endif endpar
default init s0:
	function s = {1}
	function n = 0
"""

TWICE = """
asm Twice
import StandardLibrary
signature:
	domain Idx subsetof Integer
	controlled a: Idx -> Boolean
	controlled done: Boolean
definitions:
	domain Idx = {1 : 3}
	rule r_pick = choose $x in Idx with a($x) do a($x) := false ifnone done := true
	main rule r_main = seq r_pick[] r_pick[] endseq
default init s0:
	function a($i in Idx) = ($i = 1)
	function done = false
"""


def test_choose_over_sets_and_sequences_computed_in_the_state(tmp_path, capsys):
    # a set of integers, a set of enum values, a sequence built by a comprehension over a
    # state sequence, and a range bound to the variable before it: the first state with
    # big = 40 is reached by the same shortest trace (the choices are met in the same order)
    code, out = both(tmp_path, capsys, POOL)
    assert (code, *summary(out)) == (1, "violated", 49, 80, 3)
    (v,) = out["violations"]
    assert v["property"] == "inv_big"
    assert [[c["value"] for c in s["choices"]] for s in v["trace"]][1:] == [
        [{"$x": 4}, {"$g": {"seq": [1, 5]}, "$y": 1}, {"$c": "GREEN"}],
        [{"$g": {"seq": [1, 5]}, "$y": 5}]]
    assert v["trace"][-1]["state"]["taken"] == {"seq": [4, 2]}


def test_a_range_that_becomes_undef_is_the_python_engines_error(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, UNDEF_RANGE)
    assert (code, *summary(out)) == (1, "violated", 4, 3, 3)
    (v,) = out["violations"]
    assert (v["property"], v["message"]) == ("error", "the range of $x is undef")
    assert [s["state"] for s in v["trace"]][-1] == {"n": 4}


def test_a_choose_reached_twice_in_one_step_sees_the_second_working_state(tmp_path, capsys):
    # the second call of r_pick finds no candidate (the first one set a(1) to false): ifnone runs
    code, out = both(tmp_path, capsys, TWICE, "--deadlock")
    assert (code, *summary(out)) == (1, "violated", 2, 2, 1)
    (v,) = out["violations"]
    assert v["trace"][-1]["state"] == {"a(1)": False, "a(2)": False, "a(3)": False, "done": True}


HANDLERS = """\
asm Handlers
import StandardLibrary
signature:
	enum domain Chan = {CA | CB}
	controlled level: Chan -> Integer
	controlled handler: Chan -> Rule(Chan)
	controlled next: Rule
	controlled calls: Integer
definitions:
	rule r_up($c in Chan) = level($c) := (level($c) + 1) mod 3
	rule r_down($c in Chan) = level($c) := (level($c) + 2) mod 3
	rule r_swap = par handler(CA) := handler(CB) handler(CB) := handler(CA) endpar
	rule r_count = calls := (calls + 1) mod 2
	rule r_run($r in Rule) = $r
	invariant inv_levels over level: not (level(CA) = 2 and level(CB) = 2)
	main rule r_main =
		par
			choose $c in Chan with true do
				handler($c)[$c]
			r_run[next]
			if next = <<r_swap>> then next := <<r_count>> else next := <<r_swap>> endif
		endpar
default init s0:
	function level($c in Chan) = 0
	function handler($c in Chan) = if $c = CA then <<r_up(Chan)>> else <<r_down(Chan)>> endif
	function next = <<r_count>>
	function calls = 0
"""

BY_NAME = """\
asm ByName
import StandardLibrary
signature:
	domain Idx subsetof Integer
	controlled cell: Idx -> Integer
	controlled ptr: Idx
	controlled log: Seq(Integer)
	monitored bump: Boolean
definitions:
	domain Idx = {0 : 2}
	macro rule r_inc($x in Integer) = $x := ($x + 1) mod 3
	macro rule r_twice($x in Integer, $y in Integer) =
		seq
			r_inc[$x]
			log := append(log, $y)
			r_inc[$x]
			log := append(log, $y)
		endseq
	invariant inv_log over log: length(log) < 5
	main rule r_main =
		if bump then
			r_twice[cell(ptr), cell(ptr) * 10]
		else
			ptr := (ptr + 1) mod 3
		endif
default init s0:
	function cell($i in Idx) = 0
	function ptr = 0
	function log = []
"""


def test_rule_values_in_locations_parameters_and_calls_through_terms(tmp_path, capsys):
    # handler(c)[c] calls the rule stored in a location, $r in r_run a rule parameter, and
    # next = <<r_swap>> compares rule values
    code, out = both(tmp_path, capsys, HANDLERS)
    assert (code, *summary(out)) == (1, "violated", 12, 22, 5)
    (v,) = out["violations"]
    assert v["property"] == "inv_levels"
    assert v["trace"][-1]["state"] == {"calls": 0, "handler(CA)": {"rule": "r_up"}, "handler(CB)": {"rule": "r_down"},
                                       "level(CA)": 2, "level(CB)": 2, "next": {"rule": "r_count"}}


def test_a_location_argument_is_updated_through_the_parameter_and_read_by_name(tmp_path, capsys):
    # r_inc updates cell(ptr) through $x; in r_twice's seq block $y (cell(ptr) * 10) is read
    # after each increment: 10 and 20, then 0 (3 mod 3) and 10, 20, 0 again
    code, out = both(tmp_path, capsys, BY_NAME)
    assert (code, *summary(out)) == (1, "violated", 26, 28, 4)
    (v,) = out["violations"]
    assert v["property"] == "inv_log"
    assert v["trace"][-1]["state"] == {"cell(0)": 0, "cell(1)": 0, "cell(2)": 0,
                                       "log": {"seq": [10, 20, 0, 10, 20, 0]}, "ptr": 0}


TURBO = """\
asm Turbo
import StandardLibrary
signature:
	controlled n: Integer
	controlled fact: Integer
	controlled half: Integer
	controlled steps: Integer
	monitored pick: Boolean
definitions:
	turbo rule r_fact($k in Integer) in Integer =
		if $k <= 1 then
			result := 1
		else let ($p = 0) in seq
			$p <- r_fact($k - 1)
			result := $k * $p
		endseq endlet endif
	turbo rule r_half($k in Integer) in Integer =
		if $k mod 2 = 0 then result := idiv($k, 2) endif
	turbo rule r_tick($k in Integer) =
		if $k > 0 then seq
			steps := steps + 1
			r_tick($k - 1)
		endseq endif
	invariant inv_fact over fact: fact < 720
	main rule r_main =
		seq
			fact <- r_fact(n)
			half <- r_half(n)
			steps := 0
			r_tick(n)
			if pick then n := n + 1 else n := n + 2 endif
		endseq
default init s0:
	function n = 1
	function fact = 0
	function half = 0
	function steps = 0
"""


def test_turbo_calls_recursion_and_return_values(tmp_path, capsys):
    # r_fact returns through result (recursively, into a let variable), r_half gives no result
    # for an odd n (half becomes undef), r_tick recurses without a result; result itself is a
    # location of the state, as in the Python engine
    code, out = both(tmp_path, capsys, TURBO)
    assert (code, *summary(out)) == (1, "violated", 17, 24, 5)
    (v,) = out["violations"]
    assert v["property"] == "inv_fact"
    assert [s["state"] for s in v["trace"]][-1] == {"fact": 5040, "n": 9, "result": 5040, "steps": 7}


RESULT_READ = """\
asm ResultRead
import StandardLibrary
signature:
	domain Num subsetof Integer
	controlled x: Num
	controlled y: Num
definitions:
	domain Num = {0 : 3}
	turbo rule r_t($a in Num) in Num =
		seq
			result := $a
			if result = 2 then result := 0 endif
			if result > 0 then result := (result + 1) mod 4 endif
		endseq
	invariant inv_a over x: x != 3
	main rule r_main =
		choose $v in Num do seq
			y <- r_t($v)
			x := y
		endseq
default init s0:
	function x = 0
	function y = 0
"""


def test_a_turbo_rule_reads_and_compares_its_result(tmp_path, capsys):
    # result is read (result + 1) and compared (result = 2) after its update in the same call:
    # the native engine held result as a plain Integer but compared it as a tagged value of type
    # Any, so result = 2 never held (without the read of result + 1: 4 states, 12 transitions
    # against 3 and 8), and it refused to read it.  $v = 0 gives y = 0, 1 gives 2, 2 and 3 give 0.
    code, out = both(tmp_path, capsys, RESULT_READ)
    assert (code, *summary(out)) == (0, "holds", 3, 6, 1)


UNDEF_ARG_INIT = """\
asm UndefArgInit
import StandardLibrary
signature:
	enum domain Col = {AA | BB | CC}
	controlled gb: Col -> Boolean
	controlled sq: Seq(Col)
	controlled r: Boolean
	controlled k: Boolean
definitions:
	main rule r_main =
		par
			r := gb(first(sq))
			k := not(k)
			if k then sq := [AA] else sq := [] endif
		endpar
default init s0:
	function gb($e in Col) = if $e = undef then k else not(gb(AA)) endif
	function sq = []
	function k = false
"""


def test_a_location_read_at_an_undef_argument_has_the_init_terms_value(tmp_path, capsys):
    # gb(first(sq)) with sq = []: no location of gb's layout; the init term gives the value, in
    # the state of the read (k), as the Python step function computes it -- the native engine
    # read undef (r stayed undef: 2 states, not 4)
    code, out = both(tmp_path, capsys, UNDEF_ARG_INIT, "--graph", str(tmp_path / "g.dot"))
    assert (code, *summary(out)) == (0, "no property checked", 4, 4, 3)
    labels = sorted(ln.split('"')[1] for ln in (tmp_path / "g.dot").read_text().splitlines() if "[label=" in ln
                    and " -> " not in ln)
    assert labels == ["k = false\\lr = true\\lsq = [AA]\\l", "k = false\\lsq = []\\l",
                      "k = true\\lr = false\\lsq = []\\l", "k = true\\lsq = []\\l"]


LAZY = """\
asm Lazy
import StandardLibrary
signature:
	controlled g: Integer -> Integer
	controlled n: Integer
	controlled res: Integer
	monitored skip2: Boolean
definitions:
	invariant inv_out over res: res < 6
	main rule r_main =
		if n < 4 then
			seq
				res := g(n)
				if skip2 then n := n + 2 else n := n + 1 endif
				g(n) := g(n) + 1
			endseq
		endif
default init s0:
	function g($x in Integer) = $x * 2
	function n = 0
	function res = 0
"""


def test_a_lazily_initialised_function_keeps_the_locations_it_read(tmp_path, capsys):
    # g over the integers: a location first read keeps its initial value in the next state
    # (g(0) = 0 is read by res := g(0) and never updated)
    code, out = both(tmp_path, capsys, LAZY)
    assert (code, *summary(out)) == (1, "violated", 15, 17, 4)
    (v,) = out["violations"]
    assert v["property"] == "inv_out"
    assert v["trace"][-1]["state"] == {"g(0)": 0, "g(1)": 3, "g(3)": 7, "g(4)": 9, "n": 4, "res": 7}


PAIRS = """\
asm Pairs
import StandardLibrary
signature:
	enum domain Side = {LEFT | RIGHT}
	controlled pairs: Powerset(Prod(Integer, Side))
	controlled groups: Powerset(Powerset(Integer))
	controlled names: Powerset(String)
	controlled total: Integer
	controlled tag: String
definitions:
	invariant inv_total over total: total < 12
	main rule r_main =
		par
			choose $p in pairs with true do
				par
					pairs := excluding(pairs, $p)
					total := total + first($p)
				endpar
			ifnone pairs := {(3, LEFT), (1, RIGHT), (1, LEFT)}
			choose $g in groups, $x in $g with true do groups := excluding(groups, $g)
			ifnone groups := {{2, 3}, {4}, {1, 5, 6}}
			choose $n in names do par tag := $n names := excluding(names, $n) endpar
		endpar
default init s0:
	function pairs = {(2, RIGHT), (10, LEFT), (2, LEFT)}
	function groups = {{7, 1}, {2}}
	function names = {"b", "ab", "a"}
	function total = 0
	function tag = ""
"""


def test_choose_over_sets_of_tuples_sets_and_strings_in_vkey_order(tmp_path, capsys):
    # the elements of a set of composite values are met sorted as the Python engine sorts them:
    # (2, LEFT) before (2, RIGHT) and (10, LEFT); {2} before {1, 7}; "a" before "ab" and "b"
    code, out = both(tmp_path, capsys, PAIRS)
    assert (code, *summary(out)) == (1, "violated", 39, 93, 3)
    (v,) = out["violations"]
    assert v["property"] == "inv_total"
    assert [[c["value"] for c in s["choices"]] for s in v["trace"]] == [
        [],
        [{"$p": {"tuple": [2, "LEFT"]}}, {"$g": {"set": [2]}, "$x": 2}, {"$n": "a"}],
        [{"$p": {"tuple": [10, "LEFT"]}}, {"$n": "ab"}]]


RANGES = """\
asm Ranges
import StandardLibrary
signature:
	controlled hi: Integer
	controlled picked: Integer
	controlled evens: Seq(Integer)
	controlled st: Integer
definitions:
	invariant inv_picked over picked: picked != 7
	main rule r_main =
		par
			choose $i in {hi - 2 : hi} with $i mod 2 = 0 do picked := $i
			evens := [0 : hi, st]
			if hi < 6 then hi := hi + 1 endif
			if hi = 5 then st := 0 endif
		endpar
default init s0:
	function hi = 2
	function picked = 0
	function evens = []
	function st = 2
"""


def test_intervals_with_bounds_and_steps_computed_in_the_state(tmp_path, capsys):
    # {hi - 2 : hi} ranged over by a choose, [0 : hi, st] stored; a step of 0 is the Python
    # engine's run-time error
    code, out = ends_on_error(tmp_path, capsys, RANGES)
    assert (code, *summary(out)) == (1, "violated", 7, 8, 4)
    (v,) = out["violations"]
    assert (v["property"], v["message"]) == ("error", "the step of an interval must be positive, not 0")
    assert v["trace"][-1]["state"] == {"evens": {"seq": [0, 2, 4]}, "hi": 6, "picked": 4, "st": 0}


SLOTS = """\
asm Slots
import StandardLibrary
signature:
	controlled prog: Integer -> Rule
	controlled pc: Integer
	controlled acc: Integer
definitions:
	rule r_add = acc := acc + 3
	rule r_dbl = acc := acc * 2
	rule r_halt = skip
	invariant inv_acc over acc: pc != 4
	main rule r_main =
		if pc < 4 then
			par
				prog(pc)
				pc := pc + 1
				if acc > 5 then prog(pc + 1) := <<r_dbl>> endif
			endpar
		else
			r_halt[]
		endif
default init s0:
	function prog($i in Integer) = if $i mod 2 = 0 then <<r_add>> else <<r_halt>> endif
	function pc = 0
	function acc = 0
"""


def test_rules_stored_in_a_function_over_the_integers(tmp_path, capsys):
    # prog: Integer -> Rule, initialised lazily; each location read keeps its rule, prog(4) is
    # updated to <<r_dbl>> (pc + 1 when acc > 5)
    code, out = both(tmp_path, capsys, SLOTS)
    assert (code, *summary(out)) == (1, "violated", 5, 5, 4)
    (v,) = out["violations"]
    assert v["property"] == "inv_acc"
    assert v["trace"][-1]["state"] == {"acc": 6, "pc": 4, "prog(0)": {"rule": "r_add"}, "prog(1)": {"rule": "r_halt"},
                                       "prog(2)": {"rule": "r_add"}, "prog(3)": {"rule": "r_halt"},
                                       "prog(4)": {"rule": "r_dbl"}}


EACH = """\
asm Each
import StandardLibrary
signature:
	domain Cell subsetof Integer
	controlled jobs: Powerset(Prod(Cell, Cell))
	controlled load: Cell -> Integer
definitions:
	domain Cell = {0 : 2}
	invariant inv_load over load: load(2) < 2
	main rule r_main =
		if size(jobs) < 2 then
			jobs := including(jobs, if isEmpty(jobs) then (2, 1) else (0, 2) endif)
		else
			forall $j in jobs do
				choose $c in {first($j), second($j)} with load($c) < 3 do load($c) := load($c) + 1
		endif
default init s0:
	function jobs = {}
	function load($c in Cell) = 0
"""


def test_a_forall_whose_body_chooses_meets_a_set_of_tuples_in_vkey_order(tmp_path, capsys):
    # (2, 1) enters the value table before (0, 2); the Python engine walks (0, 2) first, so the
    # first choice of each step is between 0 and 2 (walked in the order of the codes, it was
    # between 2 and 1: another shortest trace)
    code, out = both(tmp_path, capsys, EACH)
    assert (code, *summary(out)) == (1, "violated", 29, 42, 5)
    (v,) = out["violations"]
    assert [[c["value"] for c in s["choices"]] for s in v["trace"]] == [
        [], [], [], [{"$c": 0}, {"$c": 2}], [{"$c": 0}, {"$c": 2}]]


MON_ARG = """\
asm MonArg
import StandardLibrary
signature:
	domain Idx subsetof Integer
	enum domain Mode = {IDLE | BUSY}
	controlled a: Integer
	controlled b: Integer
	controlled m: Mode
	monitored inp: Idx -> Boolean
	monitored go: Boolean
definitions:
	domain Idx = {0 : 3}
	macro rule r_take($p in Boolean, $q in Boolean) =
		choose $k in {1, 2, 3} with $k > a do
			par
				a := if $k = 3 then 0 else $k endif
				if $p then b := (b + $k) mod 4 endif
				if m = BUSY and $q then m := IDLE else m := BUSY endif
			endpar
	invariant inv_b over b: b != 2
	main rule r_main = r_take[inp(a), go]
default init s0:
	function a = 0
	function b = 0
	function m = IDLE
"""


def test_a_monitored_argument_is_read_where_the_body_uses_it(tmp_path, capsys):
    # inp(a) is read only when the chosen $k makes the body use $p, after the choice of $k, as
    # in the Python engine (read at the call, it gave 20 states and 42 transitions)
    code, out = both(tmp_path, capsys, MON_ARG)
    assert (code, *summary(out)) == (1, "violated", 18, 30, 2)
    (v,) = out["violations"]
    assert [s["state"] for s in v["trace"]] == [{"a": 0, "b": 0, "m": "IDLE"}, {"a": 2, "b": 2, "m": "BUSY"}]
