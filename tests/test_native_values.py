"""The native explorer's values beyond booleans, enums and integers: Reals (Java doubles, with
the Python engine's -0.0, NaN, infinities, rtoi/floor/round and decimal intervals); monitored
locations the initial state gives a value; INVAR constraints and invariants over monitored
functions (every choice of the monitored values the step did not read); functions of codomain
Undef nobody uses; a quantifier over an infinite domain; values of every kind in locations of
type Any; functions held as maps; initial values outside their codomain.  Each spec runs on
both engines (pinned with --engine) and the JSON reports must be equal apart from the engine
and the times; the exact counts and values are checked too."""
import json

import pytest

from asmcheck.cli import main
from asmcheck.explore.native_build import compiler
from helpers import both, write
from test_native_engine import ends_on_error

pytestmark = pytest.mark.engines("native")

REALS = """asm Reals
import StandardLibrary
signature:
	domain Half subsetof Real
	controlled x: Real
	controlled s: Half
	controlled i1: Integer
	controlled i2: Integer
	controlled i3: Integer
	controlled i4: Integer
	controlled i5: Integer
	controlled i6: Integer
	controlled i7: Integer
	controlled i8: Integer
	controlled b1: Boolean
	controlled b2: Boolean
	controlled b3: Boolean
	controlled b4: Boolean
	controlled b5: Boolean
	controlled b6: Boolean
	controlled r1: Real
	controlled r2: Real
	controlled r3: Real
	controlled r4: Real
	controlled r5: Real
	controlled r6: Real
	controlled r7: Real
	controlled r8: Real
	controlled t: Prod(Real, Integer)
definitions:
	domain Half = {0.5 : 2.0, 0.5}
	invariant inv_x over x: x < 0.4
	main rule r_main =
		par
			if x < 0.5 then x := x + 0.1 endif
			if s < 2.0 then s := s + 0.5 endif
			i1 := rtoi(1.0 / 0.0)
			i2 := rtoi(0.0 / 0.0)
			i3 := floor(-2.5)
			i4 := round(-2.5)
			i5 := round(2.5)
			i6 := floor(1000000000000.0)
			i7 := rtoi(-7.9)
			i8 := rtoi(max(-0.0, 0.0) + min(1.0, 0.0 / 0.0))
			b1 := 0.0 = -0.0
			b2 := (0.0 / 0.0) = (0.0 / 0.0)
			b3 := 2.0 = 2
			b4 := 0 = -0.0
			b5 := -0.0 = 0
			b6 := (0.0 / 0.0) < 1.0
			r1 := sqrt(2.0)
			r2 := pwr(2.0, 0.5)
			r3 := abs(-3.25)
			r4 := itor(7) / 2.0
			r5 := 7 / 2
			r6 := 0.1 + 0.2
			r7 := pwr(10.0, 400.0)
			r8 := -(1.0 / 0.0)
			t := (x * 2.0, rtoi(s))
		endpar
default init s0:
	function x = 0.0
	function s = 0.5
"""

# -0.0 is a state of its own for the native encoding but equals 0.0 in the Python engine's
# states: the native search stops at the first such value and the Python engine explores
NEG_ZERO = """asm NegZero
import StandardLibrary
signature:
	controlled x: Real
	controlled n: Integer
definitions:
	main rule r_main =
		if n < 2 then
			par
				n := n + 1
				x := x * -1.0
			endpar
		endif
default init s0:
	function x = 0.0
	function n = 0
"""

# an initial value outside its Real subset domain, a Real choice over a finite subset, and an
# update outside the subset (a run-time error)
SUBSET = """asm RealSubset
import StandardLibrary
signature:
	domain Tenth subsetof Real
	controlled v: Tenth
	controlled w: Real
definitions:
	domain Tenth = {0.6 : 0.9, 0.1}
	main rule r_main =
		choose $d in Tenth with $d > w do
			par
				w := $d
				if $d = 0.9 and w = 0.8 then v := 1.0 else v := $d endif
			endpar
default init s0:
	function v = 1.6
	function w = 0.0
"""

# INVAR constraints over monitored functions (one reads a monitored location the step never
# reads), an invariant over monitored functions beside them, a monitored location initialised
INVAR_MON = """asm InvarMon
import StandardLibrary
signature:
	enum domain Cmd = {GO | STOP | WAIT}
	monitored cmd: Cmd
	monitored urgent: Boolean
	monitored spare: Boolean
	controlled n: Integer
	controlled last: Cmd
definitions:
	INVAR not (n >= 2 and cmd = GO)
	INVAR urgent or last != WAIT or spare
	invariant inv_wait over cmd, last: not (last = WAIT and cmd = STOP and n > 2)
	main rule r_main =
		if n < 4 then
			par
				last := cmd
				if urgent then n := n + 2 else n := n + 1 endif
			endpar
		endif
default init s0:
	function n = 0
	function last = GO
	function spare = false
"""

# a monitored location with an initial value stays in every state; an invariant over monitored
# functions the step does not read holds only when every value satisfies it; two functions of
# codomain Undef that nothing uses
MON_INIT = """asm MonInit
import StandardLibrary
signature:
	domain State subsetof Natural
	controlled ctl: State
	monitored high: Boolean
	monitored low: Boolean
	controlled g: Integer -> Undef
	controlled h: Boolean -> Undef
definitions:
	domain State = {0n, 1n}
	invariant inv_hl over high, low: not (high and low) or ctl = 0n
	main rule r_main = if ctl = 0n then ctl := 1n else ctl := 0n endif
default init s0:
	function ctl = 0n
	function high = false
"""

# a quantifier over Integer: the native search hands the spec over when it is reached (the
# Python engine then reports that the domain cannot be enumerated)
INFINITE_EXISTS = """asm InfiniteExists
import StandardLibrary
signature:
	controlled n: Integer
	controlled ok: Boolean
definitions:
	main rule r_main =
		if n < 2 then n := n + 1 else ok := (exists $x in Integer with $x > n) endif
default init s0:
	function n = 0
"""

# functions over String and to String, held as maps
STRING_MAPS = """asm StringMaps
import StandardLibrary
signature:
	enum domain Key = {KA | KB}
	controlled cnt: String -> Integer
	controlled name: Integer -> String
	controlled k: Key
definitions:
	invariant inv_name over name: isUndef(name(3))
	main rule r_main =
		par
			if k = KA then k := KB else k := KA endif
			if isUndef(cnt("a")) then cnt("a") := 0 else if cnt("a") < 3 then cnt("a") := cnt("a") + 1 endif endif
			if k = KB then name(cnt("a")) := "x" endif
		endpar
default init s0:
	function k = KA
"""

# strings, an enum value, an abstract element and an integer in locations of type Any (and a
# subset of Any), compared and copied between them
ANY_VALUES = """asm AnyValues
import StandardLibrary
signature:
	abstract domain Film
	enum domain Msg = {NAK | ACK}
	domain Kind subsetof Any
	controlled outv: Any
	controlled prev: Any
	controlled kind: Kind
	controlled n: Integer
	controlled who: Film -> Integer
	static f1: Film
	static f2: Film
definitions:
	invariant inv_out over outv: outv != "done" or prev = 3
	main rule r_main =
		par
			n := (n + 1) mod 5
			prev := outv
			switch n
				case 0: outv := "start"
				case 1: outv := NAK
				case 2: outv := f1
				case 3: outv := n - 1
				case 4: outv := "done"
			endswitch
			if outv = NAK then kind := ACK else kind := outv endif
			who(f1) := n
		endpar
default init s0:
	function n = 0
	function outv = "init"
"""

# holder(undef) := undef changes nothing; holder(u1) := undef beside holder(u1) := b1 is a clash
UNDEF_ARGUMENT = """asm UndefArgument
import StandardLibrary
signature:
	abstract domain User
	abstract domain Book
	controlled holder: User -> Book
	controlled who: User
	controlled n: Integer
	static u1: User
	static b1: Book
definitions:
	main rule r_main =
		if n < 3 then
			par
				n := n + 1
				holder(who) := undef
				if n = 1 then who := u1 endif
				if n = 2 then holder(u1) := b1 endif
			endpar
		endif
default init s0:
	function n = 0
"""

# true and 1 are one key of the Python engine's states: refused
MIXED_ANY = """asm MixedAny
import StandardLibrary
signature:
	controlled a: Any
	controlled n: Integer
definitions:
	main rule r_main =
		if n < 2 then
			par
				n := n + 1
				if n = 0 then a := true else a := 1 endif
			endpar
		endif
default init s0:
	function n = 0
"""

# a rule run by agents of two domains updates ready(self) of a function over one of them: the
# Python engine keeps ready(r1) too (the native engine holds the function as a map); the LTL
# check finds the states by value, maps made by the search included
SHARED_RULE = """asm SharedRule
import StandardLibrary
import LTLLibrary
signature:
	domain Left subsetof Agent
	domain Right subsetof Agent
	controlled ready: Left -> Boolean
	controlled turn: Integer
	static l1: Left
	static r1: Right
definitions:
	rule r_mark = if isUndef(ready(self)) then ready(self) := true else ready(self) := not ready(self) endif
	LTLSPEC ltlSpec_turn: g(f(turn = 0))
	LTLSPEC ltlSpec_r1: g(isUndef(ready(r1)))
	main rule r_main =
		par
			turn := (turn + 1) mod 2
			if turn = 0 then program(l1) else program(r1) endif
		endpar
default init s0:
	function turn = 0
	function ready($l in Left) = false
	agent Left: r_mark[]
	agent Right: r_mark[]
"""

# functions over sets of tuples and to sequences, held as maps of interned values
COMPOSITE_MAPS = """asm CompositeMaps
import StandardLibrary
signature:
	domain Point subsetof Prod(Integer, Integer)
	controlled seen: Powerset(Point) -> Integer
	controlled path: Integer -> Seq(Integer)
	controlled n: Integer
definitions:
	invariant inv_n over path: isUndef(path(3)) or length(path(3)) < 3
	main rule r_main =
		if n < 4 then
			seq
				n := n + 1
				path(n) := if n = 1 then [0] else append(path(n - 1), n) endif
				seen({(n, n), (0, 0)}) := n
				if isUndef(seen({(0, 0)})) then seen({(0, 0)}) := 0 else seen({(0, 0)}) := seen({(0, 0)}) + 1 endif
			endseq
		endif
default init s0:
	function n = 0
"""

SHARED_RULE_STEPS = """step stp_l1_by_l1: not updated(ready(l1)) or updatedBy(l1, ready(l1))
step stp_r1_changes: not updated(ready(r1)) or changed(ready(r1))
step stp_r1_never: not updatedBy(r1, ready(r1))
"""

# a subset of Any given by its elements is a finite codomain: a value outside it is an error
ANY_SUBSET = """asm AnySubset
import StandardLibrary
signature:
	domain Payload subsetof Any
	enum domain Identity = {ID_C | ID_S | ID_A}
	controlled p: Payload
	controlled n: Integer
definitions:
	domain Payload = {ID_C, ID_S}
	main rule r_main =
		par
			n := n + 1
			if n = 0 then p := ID_S else p := ID_A endif
		endpar
default init s0:
	function n = 0
	function p = ID_C
"""

# a monitored Real over a decimal interval, an INVAR constraint over it
MONITORED_REAL = """asm MonitoredReal
import StandardLibrary
signature:
	domain Temp subsetof Real
	monitored temp: Temp
	controlled peak: Real
	controlled alarm: Boolean
definitions:
	domain Temp = {36.5 : 38.0, 0.5}
	INVAR temp < 38.0 or peak >= 37.0
	invariant inv_alarm over alarm: not alarm
	main rule r_main =
		par
			if temp > peak then peak := temp endif
			alarm := temp - peak > 1.0 or peak * 2.0 > 75.5
		endpar
default init s0:
	function peak = 36.0
	function alarm = false
"""

# initial values outside their codomains (kept, as the Python engine keeps them); an update
# outside the codomain is still an error
INITIAL_OUTSIDE = """asm InitialOutside
import StandardLibrary
signature:
	domain Unit subsetof Integer
	enum domain Col = {RED | GREEN}
	domain Warm subsetof Col
	controlled pos: Unit
	controlled col: Warm
	controlled n: Integer
definitions:
	domain Unit = {1 : 3}
	domain Warm = {RED}
	main rule r_main =
		if n < 4 then
			par
				n := n + 1
				if n = 1 then pos := 2 endif
				if n = 2 then pos := undef endif
				if n = 3 then pos := 5 endif
				if n = 0 then col := RED endif
			endpar
		endif
default init s0:
	function n = 0
	function pos = 0
	function col = GREEN
"""

# a turbo rule's result written to an initialised monitored location (kept in the state by the
# Python engine, while steps read the monitored inputs)
MONITORED_UPDATED = """asm MonitoredUpdated
import StandardLibrary
signature:
	domain State subsetof Natural
	controlled ctl: State
	monitored high: Boolean
	monitored low: Boolean
definitions:
	domain State = {0n, 1n}
	turbo rule r_next in Boolean =
		if ctl = 0n then result := true else result := false endif
	invariant inv_hl over high, low: not (high and low)
	main rule r_main =
		par
			high <- r_next()
			if ctl = 0n then ctl := 1n else ctl := 0n endif
		endpar
default init s0:
	function ctl = 0n
	function high = false
	function low = false
"""




def test_real_arithmetic_and_java_double_edge_cases(tmp_path, capsys):
    code, out = both(tmp_path, capsys, REALS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 6, 5, 5)
    (v,) = out["violations"]
    assert v["property"] == "inv_x"
    trace = [s["state"] for s in v["trace"]]
    assert [s["x"] for s in trace] == [0.0, 0.1, 0.2, 0.30000000000000004, 0.4]
    assert [s["s"] for s in trace] == [0.5, 1.0, 1.5, 2.0, 2.0]
    last = trace[-1]
    assert {k: last[k] for k in ("i1", "i2", "i3", "i4", "i5", "i6", "i7", "i8")} == {
        "i1": 9223372036854775807, "i2": 0, "i3": -3, "i4": -2, "i5": 3, "i6": 2147483647, "i7": -7, "i8": 1}
    assert {k: last[k] for k in ("b1", "b2", "b3", "b4", "b5", "b6")} == {
        "b1": False, "b2": True, "b3": True, "b4": True, "b5": False, "b6": False}
    assert {k: last[k] for k in ("r1", "r2", "r3", "r4", "r5", "r6")} == {
        "r1": 1.4142135623730951, "r2": 1.4142135623730951, "r3": 3.25, "r4": 3.5, "r5": 3.5,
        "r6": 0.30000000000000004}
    assert (last["r7"], last["r8"]) == (float("inf"), float("-inf"))
    assert [s.get("t") for s in trace] == [None, {"tuple": [0.0, 0]}, {"tuple": [0.2, 1]}, {"tuple": [0.4, 1]},
                                           {"tuple": [0.6000000000000001, 2]}]


def test_negative_zero_in_a_location_falls_back_to_the_python_engine(tmp_path, capsys):
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    path = write(tmp_path, NEG_ZERO)
    code = main(["explore", path, "--format", "json", "--engine", "auto"])
    out = json.loads(capsys.readouterr().out)
    assert (code, out["engine"], out["states"], out["transitions"]) == (0, "python", 3, 3)
    assert out["engine_note"] == "native engine not used: a value outside the native encoding at run time"


def test_real_subset_domain_choice_and_an_update_outside_it(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, SUBSET)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 5, 10, 1)
    (v,) = out["violations"]
    assert (v["property"], v["message"]) == ("error", "value out of domain: 1.0 is not in Tenth (the codomain of v)")
    assert [s["state"] for s in v["trace"]] == [{"v": 1.6, "w": 0.0}, {"v": 0.8, "w": 0.8}]


def test_invar_constraints_and_an_invariant_over_monitored_functions(tmp_path, capsys):
    code, out = both(tmp_path, capsys, INVAR_MON)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 14, 48, 3)
    (v,) = out["violations"]
    assert v["property"] == "inv_wait"
    assert [s["state"] for s in v["trace"]] == [
        {"last": "GO", "n": 0, "spare": False}, {"last": "GO", "n": 1, "spare": False},
        {"last": "WAIT", "n": 3, "spare": False}, {"last": "STOP", "n": 4, "spare": False}]


def test_an_initialised_monitored_location_and_an_invariant_over_unread_inputs(tmp_path, capsys):
    code, out = both(tmp_path, capsys, MON_INIT)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 2, 2, 1)
    (v,) = out["violations"]
    assert v["property"] == "inv_hl"
    assert [s["state"] for s in v["trace"]] == [
        {"ctl": 0, "high": False}, {"ctl": 1, "high": False}, {"ctl": 0, "high": False}]


def test_a_quantifier_over_integer_reached_hands_the_spec_over(tmp_path, capsys):
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    path = write(tmp_path, INFINITE_EXISTS)
    assert main(["explore", path, "--engine", "native"]) == 2
    err = capsys.readouterr().err
    assert "the native explorer cannot run InfiniteExists.asm: the infinite domain Integer, reached at run time" in err
    assert main(["explore", path, "--engine", "python"]) == 2
    assert ":8:53: the domain Integer is infinite" in capsys.readouterr().err
    # bounded, both engines agree
    code, out = both(tmp_path, capsys, INFINITE_EXISTS, "--int-range", "0..5")
    assert (code, out["verdict"], out["states"], out["transitions"]) == (0, "no property checked", 4, 4)


def test_functions_over_strings_held_as_maps(tmp_path, capsys):
    code, out = both(tmp_path, capsys, STRING_MAPS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 8, 7, 7)
    (v,) = out["violations"]
    trace = [s["state"] for s in v["trace"]]
    assert len(trace) == 7
    assert trace[1] == {'cnt("a")': 0, "k": "KB"}
    assert trace[-1] == {'cnt("a")': 3, "k": "KA", "name(0)": "x", "name(2)": "x", "name(3)": "x"}


def test_values_of_several_kinds_in_locations_of_type_any(tmp_path, capsys):
    code, out = both(tmp_path, capsys, ANY_VALUES)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 7, 6, 6)
    (v,) = out["violations"]
    trace = [s["state"] for s in v["trace"]]
    assert [s["outv"] for s in trace] == ["init", "start", "NAK", "f1", 2, "done"]
    assert [s.get("kind") for s in trace] == [None, "init", "start", "ACK", "f1", 2]


def test_an_update_to_undef_at_an_undef_argument(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, UNDEF_ARGUMENT)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 3, 2, 2)
    (v,) = out["violations"]
    assert (v["property"], v["message"]) == ("error", "inconsistent update of holder(u1): undef and b1")
    assert [s["state"] for s in v["trace"]] == [{"n": 0}, {"n": 1}, {"n": 2, "who": "u1"}]


def test_booleans_and_integers_in_one_location_of_type_any_are_left_to_the_python_engine(tmp_path, capsys):
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    path = write(tmp_path, MIXED_ANY)
    assert main(["explore", path, "--format", "json", "--engine", "auto"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["engine"], out["states"], out["transitions"]) == ("python", 3, 3)
    assert out["engine_note"] == "native engine not used: Booleans, Integers or Reals mixed in locations of type Any"


def test_a_location_at_an_agent_outside_the_domain_and_an_ltl_trace(tmp_path, capsys):
    code, out = both(tmp_path, capsys, SHARED_RULE)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 6, 6, 5)
    (v,) = out["violations"]
    assert v["property"] == "ltlSpec_r1"
    assert [s["state"] for s in v["trace"]][:3] == [
        {"ready(l1)": False, "turn": 0}, {"ready(l1)": True, "turn": 1},
        {"ready(l1)": True, "ready(r1)": True, "turn": 0}]
    assert len(v["trace"]) == 8


def test_functions_over_and_to_composite_values_held_as_maps(tmp_path, capsys):
    code, out = both(tmp_path, capsys, COMPOSITE_MAPS)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 5, 4, 4)
    (v,) = out["violations"]
    last = v["trace"][-1]["state"]
    assert last == {"n": 3, "path(1)": {"seq": [0]}, "path(2)": {"seq": [0, 2]}, "path(3)": {"seq": [0, 2, 3]},
                    "seen({(0, 0), (1, 1)})": 1, "seen({(0, 0), (2, 2)})": 2, "seen({(0, 0), (3, 3)})": 3,
                    "seen({(0, 0)})": 2}


def test_step_properties_over_a_function_held_as_a_map(tmp_path, capsys):
    prop = tmp_path / "steps.prop"
    prop.write_text(SHARED_RULE_STEPS)
    code, out = both(tmp_path, capsys, SHARED_RULE, "--properties", str(prop))
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 6, 6, 5)
    assert [v["property"] for v in out["violations"]] == ["stp_r1_never", "ltlSpec_r1"]
    assert [s["state"] for s in out["violations"][0]["trace"]] == [
        {"ready(l1)": False, "turn": 0}, {"ready(l1)": True, "turn": 1},
        {"ready(l1)": True, "ready(r1)": True, "turn": 0}]


def test_a_subset_of_any_given_by_its_elements(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, ANY_SUBSET)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 2, 1, 1)
    (v,) = out["violations"]
    assert v["property"] == "error"
    assert [s["state"] for s in v["trace"]] == [{"n": 0, "p": "ID_C"}, {"n": 1, "p": "ID_S"}]


def test_a_monitored_real_and_an_invar_over_it(tmp_path, capsys):
    code, out = both(tmp_path, capsys, MONITORED_REAL)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 6, 11, 2)
    (v,) = out["violations"]
    assert v["property"] == "inv_alarm"
    assert [s["state"] for s in v["trace"]] == [{"alarm": False, "peak": 36.0}, {"alarm": True, "peak": 37.5}]
    assert v["trace"][1]["choices"] == [{"kind": "monitored", "at": "temp", "value": 37.5}]


def test_initial_values_outside_their_codomain(tmp_path, capsys):
    code, out = ends_on_error(tmp_path, capsys, INITIAL_OUTSIDE)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 4, 3, 3)
    (v,) = out["violations"]
    assert v["message"] == "value out of domain: 5 is not in Unit (the codomain of pos)"
    assert [s["state"] for s in v["trace"]] == [
        {"col": "GREEN", "n": 0, "pos": 0}, {"col": "RED", "n": 1, "pos": 0}, {"col": "RED", "n": 2, "pos": 2},
        {"col": "RED", "n": 3}]


def test_an_initialised_monitored_location_updated_by_a_turbo_rule(tmp_path, capsys):
    code, out = both(tmp_path, capsys, MONITORED_UPDATED)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 2, 1, 1)
    (v,) = out["violations"]
    assert v["property"] == "inv_hl"
    assert [s["state"] for s in v["trace"]] == [
        {"ctl": 0, "high": False, "low": False}, {"ctl": 1, "high": True, "low": False, "result": True}]
