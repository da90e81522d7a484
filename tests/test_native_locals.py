"""The native engine on local functions and on the order of a step's choices.

- The order of the choices: the Python engine makes a step's choices (the monitored values it
  reads) in the order it reads them, left to right, and that order is the order of the
  successors, so of the state numbers and of the shortest traces.  C leaves the order in which a
  call's arguments are evaluated open: the arguments that may make a choice (read a monitored
  function, also through a derived function) are evaluated first, in order, when two or more may
  (a derived function, a location read or updated, a library function).
- Local functions (``local x : D [init] body``, asmcheck's own semantics, see the README): with
  arguments, without an initial update of their own, and in specs that use ``extend``.
- A choose merged by effect (two chooses in a step) whose body fails for some candidates: each
  error is an alternative, as in the Python engine; choosing it is a failing branch.

Each spec is written for the test; the native engine must give the Python engine's states (in
their order), transitions, edges, verdicts and traces.

Engines: both (python is the reference, native is checked)."""
from __future__ import annotations

import pytest

from asmcheck.explore.bfs import Explorer
from asmcheck.explore.native import NativeExplorer
from asmcheck.explore.native_build import compiler
from asmcheck.props import spec_properties
from asmcheck.props.load import load_machine
from conftest import ASMETA, need_asmeta
from helpers import both, write

pytestmark = pytest.mark.engines("native")


@pytest.fixture(autouse=True)
def _need_compiler():
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")


def engines(path, **kw):
    """(Python explorer and result, native explorer and result) on the spec at ``path``."""
    _, m = load_machine(str(path))
    sp, stp = spec_properties(m)
    py = Explorer(m, state_props=sp, step_props=stp, **kw)
    pres = py.run()
    nat = NativeExplorer(m, state_props=sp, step_props=stp, **kw)
    nres = nat.run()
    assert nres.engine == "native"
    return py, pres, nat, nres


def same_search(py, pres, nat, nres):
    """The same states in the same order, parents, counts and violations."""
    assert (nres.verdict, nres.states, nres.transitions, nres.depth, nres.reason) == \
        (pres.verdict, pres.states, pres.transitions, pres.depth, pres.reason)
    assert [nat.state(s) for s in range(nres.states)] == [py.state(s) for s in range(pres.states)]
    assert list(nat.parent) == list(py.parent)
    assert [(v.prop.name, v.state, v.source, v.picks, v.message) for v in nres.violations] == \
        [(v.prop.name, v.state, v.source, v.picks, v.message) for v in pres.violations]


def trace_choices(report, k=0):
    return [[(c["at"], c["value"]) for c in st["choices"]] for st in report["violations"][k]["trace"]]


# ----------------------------------------------------------------- the order of the choices
# s grows by 2 with (m1, m2) = (2, NN) or (0, EE): the Python engine reads m1 first, so it meets
# (0, EE) before (2, NN) and its shortest trace to s = 4 takes (0, EE) twice.  The first read is
# seen(m1, m2), the arguments of an update: evaluated m2 first, the native search met (2, NN)
# first and printed a trace through it.
ORDER_UPDATE = """asm Order
import StandardLibrary
signature:
	domain Small subsetof Integer
	domain Step subsetof Integer
	enum domain Dir = {NN | SS | EE}
	monitored m1: Step
	monitored m2: Dir
	controlled s: Small
	controlled seen: Prod(Step, Dir) -> Boolean
definitions:
	domain Small = {0 : 4}
	domain Step = {0 : 2}
	invariant inv_s over s: s < 4
	main rule r_main =
		par
			seen(m1, m2) := true
			if (m1 = 2 and m2 = NN or m1 = 0 and m2 = EE) and s < 4 then s := s + 2 endif
		endpar
default init s0:
	function s = 0
"""

# the same through a derived function of the two monitored values (RushHourMon's
# isMovePermitted(carMon, dirMon))
ORDER_DERIVED = """asm Order
import StandardLibrary
signature:
	domain Small subsetof Integer
	domain Step subsetof Integer
	enum domain Dir = {NN | SS | EE}
	monitored m1: Step
	monitored m2: Dir
	controlled s: Small
	controlled last: Step
	derived jump: Prod(Step, Dir) -> Boolean
definitions:
	domain Small = {0 : 4}
	domain Step = {0 : 2}
	function jump($a in Step, $d in Dir) = ($a = 2 and $d = NN or $a = 0 and $d = EE) and s < 4
	invariant inv_s over s: s < 4
	main rule r_main =
		if jump(m1, m2) then par s := s + 2 last := m1 endpar endif
default init s0:
	function s = 0
	function last = 1
"""

# a location read at two monitored arguments, and = between two terms that read monitored values
ORDER_READ = """asm Order
import StandardLibrary
signature:
	domain Step subsetof Integer
	enum domain Dir = {NN | SS | EE}
	monitored m1: Step
	monitored m2: Dir
	controlled x: Step
	controlled y: Dir
	controlled g: Prod(Step, Dir) -> Boolean
definitions:
	domain Step = {0 : 2}
	main rule r_main =
		par
			if g(m1, m2) = undef then par x := m1 y := m2 endpar endif
			if (m2 = EE) = (m1 = 1) then g(m1, m2) := true endif
		endpar
default init s0:
	function x = 0
	function y = NN
"""


# the arguments of a turbo call (passed by value)
ORDER_TURBO = """asm Order
import StandardLibrary
signature:
	domain Step subsetof Integer
	enum domain Dir = {NN | SS | EE}
	monitored m1: Step
	monitored m2: Dir
	controlled x: Step
	controlled y: Dir
definitions:
	domain Step = {0 : 2}
	turbo rule r_set($a in Step, $b in Dir) = par x := $a y := $b endpar
	main rule r_main = r_set(m1, m2)
default init s0:
	function x = 0
	function y = NN
"""


# a function over Integer (a map value) updated at two monitored arguments (GCC happens to evaluate
# the key's parts in order; C does not promise it)
ORDER_MAP = """asm Order
import StandardLibrary
signature:
	domain Small subsetof Integer
	monitored m1: Small
	monitored m2: Small
	controlled h: Prod(Integer, Integer) -> Boolean
	controlled x: Integer
definitions:
	domain Small = {0 : 2}
	main rule r_main = if x < 3 then par h(m1, m2 + 10) := true x := x + 1 endpar endif
default init s0:
	function x = 0
"""


@pytest.mark.parametrize("text", [ORDER_UPDATE, ORDER_DERIVED], ids=["update", "derived"])
def test_the_shortest_trace_takes_the_choices_in_the_python_engines_order(tmp_path, capsys, text):
    code, out = both(tmp_path, capsys, text)
    assert code == 1 and out["verdict"] == "violated"
    assert (out["states"], out["transitions"]) == ((106, 223) if text is ORDER_UPDATE else (5, 10))
    assert trace_choices(out) == [[], [("m1", 0), ("m2", "EE")], [("m1", 0), ("m2", "EE")]]


@pytest.mark.parametrize("text", [ORDER_UPDATE, ORDER_DERIVED, ORDER_READ, ORDER_TURBO, ORDER_MAP],
                         ids=["update", "derived", "read", "turbo", "map"])
def test_the_states_are_numbered_in_the_python_engines_order(tmp_path, text):
    py, pres, nat, nres = engines(write(tmp_path, text), keep_graph=True)
    same_search(py, pres, nat, nres)
    counts = {ORDER_UPDATE: (768, 4477), ORDER_DERIVED: (5, 11), ORDER_READ: (209, 1401), ORDER_TURBO: (9, 81),
              ORDER_MAP: (184, 588)}[text]
    assert (nres.states, nres.transitions) == counts
    assert list(zip(*nat.edge_arrays())) == list(dict.fromkeys((a, b) for a, b, _ in py.edges))


@pytest.mark.corpus
def test_rush_hour_with_deadlock_gives_the_python_engines_trace():
    need_asmeta()
    path = ASMETA / "asm_examples/examples/RushHour/RushHourMon.asm"
    py, pres, nat, nres = engines(path, deadlock=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.verdict) == (838, 5714, "violated")
    (v,) = [v for v in nres.violations if v.prop.name == "deadlock"]
    assert (v.state, v.message) == (816, "the only successor is the state itself")
    assert len(nat.path_to(816)) == 34


# ----------------------------------------------------------------- local functions
def state_views(m, ex, n):
    names = {f.index: f.name for f in m.spec.functions}
    out = []
    for i in range(n):
        st = {}
        for k, v in ex.state(i).items():
            if type(k) is int:
                st[names[k]] = v
            elif type(k[0]) is int:
                st[f"{names[k[0]]}{tuple(k[1])}"] = v
        out.append(st)
    return out


# a local function over a finite domain with arguments in a recursive turbo rule (one acc per
# call: the caller's acc(0) and acc(1) stay while the callee sets its own), and one with an
# initial rule that updates nothing (skip): read undef at w(2), set by seq steps
LOCAL_ARGS = """asm LocalArgs
import StandardLibrary
signature:
	domain Small subsetof Integer
	domain Idx subsetof Integer
	controlled n: Small
	controlled total: Integer
	controlled z: Integer
	monitored go: Boolean
definitions:
	domain Small = {1 : 4}
	domain Idx = {0 : 2}
	turbo rule r_sum($k in Integer) in Integer =
		local acc : Idx -> Integer [ par acc(0) := $k acc(1) := z endpar ]
		if $k <= 1 then result := acc(0) + acc(1)
		else seq
			acc(2) <- r_sum($k - 1)
			result := acc(0) + acc(2)
		endseq endif
	rule r_skip =
		local w : Idx -> Small [ skip ]
		seq
			w(0) := n
			if go then w(1) := w(0) else w(1) := 1 endif
			z := w(0) + w(1) + (if w(2) = undef then 0 else 100 endif)
		endseq
	main rule r_main =
		par
			total <- r_sum(n)
			r_skip[]
			if n < 4 then n := n + 1 else n := 1 endif
		endpar
default init s0:
	function n = 1
	function total = 0
	function z = 0
"""

# an initial rule that updates another location (y, seen updated by the body, not made) and
# not x; its clash (bad in y = 2) is a failing branch with the Python engine's message
LOCAL_INIT = """asm LocalInit
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled y: Small
	controlled c1: Integer
	controlled c2: Integer
	monitored bad: Boolean
definitions:
	domain Small = {0 : 3}
	rule r_shadow =
		local x : Small [ par y := (y + 1) mod 4 if bad and y = 2 then par x := 1 x := 2 endpar endif endpar ]
		par
			c1 := y
			if x = undef then c2 := 1 else c2 := 2 endif
			if y = 3 then y := 0 endif
		endpar
	main rule r_main =
		seq
			r_shadow[]
			if y < 3 then y := y + 1 endif
		endseq
default init s0:
	function y = 0
	function c1 = 0
	function c2 = 0
"""

# a local function over Integer (a map value): memo(k) is set by the caller in a seq step, then by
# the callee's initial rule at the same argument (k - 1 of the caller is k of the callee), and the
# caller still reads its own
LOCAL_MAP = """asm LocalMap
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	controlled fib: Integer
	monitored twice: Boolean
definitions:
	domain Small = {0 : 5}
	turbo rule r_fib($k in Integer) in Integer =
		local memo : Integer -> Integer [ memo($k) := $k ]
		if $k <= 1 then result := memo($k)
		else seq
			memo($k) := 0
			memo($k - 1) <- r_fib($k - 1)
			memo($k - 2) <- r_fib($k - 2)
			result := memo($k - 1) + memo($k - 2) + memo($k)
		endseq endif
	main rule r_main =
		par
			fib <- r_fib(n)
			if twice then n := (n + 2) mod 6 else n := (n + 1) mod 6 endif
		endpar
default init s0:
	function n = 0
	function fib = 0
"""

# local functions in a spec that uses extend: tmp holds elements made by extend within the rule
# (the one made in this step, the one before), k counts
LOCAL_EXTEND = """asm LocalExt
import StandardLibrary
signature:
	dynamic abstract domain Token
	domain Small subsetof Integer
	controlled owner: Token -> Small
	controlled made: Small
	controlled last: Token
	monitored pick: Small
definitions:
	domain Small = {0 : 2}
	rule r_make =
		local tmp : Small -> Token [ tmp(0) := last ]
		seq
			extend Token with $t do par owner($t) := pick last := $t endpar
			tmp(pick) := last
			if tmp(0) != undef and tmp(0) != last then owner(tmp(0)) := undef endif
		endseq
	rule r_count =
		local k : Small [ k := made ]
		seq
			if k < 2 then k := k + 1 endif
			made := k
		endseq
	main rule r_main =
		if made < 2 then par r_make[] r_count[] endpar endif
default init s0:
	function made = 0
"""


# local functions of codomain Real over a finite domain, and 0-ary
LOCAL_REAL = """asm LocReal
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled y: Small
	controlled r: Real
	monitored half: Boolean
definitions:
	domain Small = {0 : 3}
	turbo rule r_t =
		local x : Small -> Real [ x(0) := 1.5 ]
		local w : Real [ skip ]
		seq
			x(0) := x(0) + 1.0
			if half then x(1) := x(0) / 2.0 else x(1) := x(0) * 2.0 endif
			w := x(1) - 0.25
			r := w
			y := (y + rtoi(x(0))) mod 4
		endseq
	main rule r_main =
		r_t[]
default init s0:
	function y = 0
	function r = 0.0
"""


def test_local_functions_of_codomain_real(tmp_path):
    path = write(tmp_path, LOCAL_REAL)
    py, pres, nat, nres = engines(path, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.verdict) == (5, 10, "holds")
    assert [(s["y"], s["r"]) for s in state_views(nat.m, nat, 5)] == [
        (0, 0.0), (2, 4.75), (2, 1.0), (0, 4.75), (0, 1.0)]

# a local function of more locations than a local function's slots (100): one map value
LOCAL_BIG = """asm LocBig
import StandardLibrary
signature:
	domain Ten subsetof Integer
	controlled k: Ten
	controlled s: Integer
	monitored go: Boolean
definitions:
	domain Ten = {0 : 9}
	rule r_grid =
		local g : Prod(Ten, Ten) -> Integer [ forall $i in Ten do g($i, k) := $i ]
		seq
			if go then g(k, k) := 9 endif
			s := g(3, k) + g(k, k) + (if g(k, 3) = undef then 100 else 0 endif)
		endseq
	main rule r_main =
		par
			r_grid[]
			k := (k + 1) mod 10
		endpar
default init s0:
	function k = 0
	function s = 0
"""


def test_a_local_function_of_many_locations(tmp_path):
    path = write(tmp_path, LOCAL_BIG)
    py, pres, nat, nres = engines(path, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.verdict) == (20, 38, "holds")
    assert [(s["k"], s["s"]) for s in state_views(nat.m, nat, 5)] == [(0, 0), (1, 103), (1, 112), (2, 104), (2, 112)]

def test_a_local_function_with_arguments_and_one_without_an_initial_update(tmp_path):
    path = write(tmp_path, LOCAL_ARGS)
    py, pres, nat, nres = engines(path, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.depth, nres.verdict) == (14, 23, 5, "holds")
    assert list(zip(*nat.edge_arrays())) == list(dict.fromkeys((a, b) for a, b, _ in py.edges))
    got = state_views(nat.m, nat, nres.states)
    # total is n + (n-1) + ... + 2 + 1 + z; z is 2n with go, n + 1 without
    assert [(s["n"], s["total"], s["z"]) for s in got] == [
        (1, 0, 0), (2, 1, 2), (3, 5, 3), (3, 5, 4), (4, 9, 4), (4, 9, 6), (4, 10, 4), (4, 10, 6),
        (1, 14, 5), (1, 14, 8), (1, 16, 5), (1, 16, 8), (2, 6, 2), (2, 9, 2)]
    # no location of the local functions in any state
    assert all(set(s) <= {"n", "total", "z", "result"} for s in got)


def test_an_initial_rule_that_updates_another_location(tmp_path):
    path = write(tmp_path, LOCAL_INIT)
    py, pres, nat, nres = engines(path, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.verdict) == (4, 4, "violated")
    assert [(s["y"], s["c1"], s["c2"]) for s in state_views(nat.m, nat, 4)] == [
        (0, 0, 0), (1, 1, 1), (2, 2, 1), (1, 3, 1)]
    at = f"{tmp_path / 'LocalInit.asm'}:12:77"
    assert [(s, p, e.message, str(e.span)) for s, p, e in nat.error_edges] == [
        (2, (1,), "inconsistent update of x: 1 and 2", at)] == \
        [(s, p, e.message, str(e.span)) for s, p, e in py.error_edges]


def test_a_local_function_over_integer_in_a_recursive_rule(tmp_path):
    path = write(tmp_path, LOCAL_MAP)
    py, pres, nat, nres = engines(path, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.verdict) == (12, 24, "holds")
    # fib is the Fibonacci number of the n before
    assert [(s["n"], s["fib"]) for s in state_views(nat.m, nat, 12)] == [
        (0, 0), (1, 0), (2, 0), (2, 1), (3, 1), (4, 1), (4, 2), (5, 2), (5, 3), (0, 3), (0, 5), (1, 5)]


def test_local_functions_in_a_spec_that_uses_extend(tmp_path):
    path = write(tmp_path, LOCAL_EXTEND)
    py, pres, nat, nres = engines(path, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.verdict) == (9, 17, "holds")
    assert [len(nat.state(i).get(("#dom", "Token"), ())) for i in range(9)] == [0, 1, 1, 1, 2, 1, 1, 2, 2]


@pytest.mark.parametrize("text", [LOCAL_ARGS, LOCAL_INIT, LOCAL_MAP, LOCAL_EXTEND],
                         ids=["args", "init", "map", "extend"])
def test_the_reports_of_the_two_engines_are_equal(tmp_path, capsys, text):
    code, out = both(tmp_path, capsys, text, "--deadlock")
    assert (out["states"], out["transitions"]) == {
        LOCAL_ARGS: (14, 23), LOCAL_INIT: (4, 4), LOCAL_MAP: (12, 24), LOCAL_EXTEND: (9, 13)}[text]


# ----------------------------------------------------------------- a merged choose whose body fails
# two chooses in a step, so each is merged by effect; $x = 2 clashes on n where n = 1
MERGE_CLASH = """asm MergeFail
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	controlled m: Small
definitions:
	domain Small = {0 : 4}
	main rule r_main =
		par
			choose $x in {0, 1, 2, 3} with true do
				par
					n := ($x + n) mod 5
					if $x = 2 and n = 1 then n := 0 endif
				endpar
			choose $y in {1, 2} with true do
				m := ($y * m + 1) mod 5
		endpar
default init s0:
	function n = 0
	function m = 0
"""

# the last choose of the step fails: a clash on seen(2), and n out of its domain
MERGE_LAST = """asm MergeLast
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	controlled m: Small
	controlled seen: Small -> Boolean
definitions:
	domain Small = {0 : 4}
	main rule r_main =
		par
			choose $y in {1, 2} with true do
				m := ($y * m + 1) mod 5
			choose $x in {0, 1, 2, 3} with $x != m do
				par
					n := $x + n
					seen($x) := true
					if $x = 2 and n = 1 then seen($x) := false endif
				endpar
		endpar
default init s0:
	function n = 0
	function m = 0
"""

# flag(2) is undef at first, and again after $y = 3 in m = 3: the guard of the first choose's body
MERGE_UNDEF = """asm MergeUndef
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	controlled m: Small
	controlled flag: Small -> Boolean
definitions:
	domain Small = {0 : 4}
	main rule r_main =
		par
			choose $x in {0, 1, 2} with true do
				if flag($x) then n := (n + $x) mod 5 else flag($x) := true endif
			choose $y in {1, 2, 3} with true do
				par
					m := ($y + m) mod 5
					if $y = 3 and m = 3 then flag(2) := undef endif
				endpar
		endpar
default init s0:
	function n = 0
	function m = 0
	function flag($i in Small) = if $i = 2 then undef else false endif
"""

MERGE_COUNTS = {MERGE_CLASH: (25, 171, 5), MERGE_LAST: (55, 154, 51), MERGE_UNDEF: (56, 336, 56)}


@pytest.mark.parametrize("text", [MERGE_CLASH, MERGE_LAST, MERGE_UNDEF], ids=["clash", "last", "undef"])
def test_a_merged_choose_whose_body_fails_for_some_candidates(tmp_path, text):
    path = write(tmp_path, text)
    py, pres, nat, nres = engines(path, keep_graph=True)
    same_search(py, pres, nat, nres)
    states, transitions, failing_states = MERGE_COUNTS[text]
    assert (nres.states, nres.transitions, nres.verdict) == (states, transitions, "violated")
    assert list(zip(*nat.edge_arrays())) == list(dict.fromkeys((a, b) for a, b, _ in py.edges))
    errs = [(s, p, e.message, str(e.span)) for s, p, e in nat.error_edges]
    assert errs == [(s, p, e.message, str(e.span)) for s, p, e in py.error_edges]
    assert len({s for s, *_ in errs}) == failing_states
    first = {MERGE_CLASH: (2, (2,), "inconsistent update of n: 3 and 0"),
             MERGE_LAST: (1, (0, 1), "inconsistent update of seen(2): true and false"),
             MERGE_UNDEF: (0, (2,), "the guard is undef")}[text]
    assert errs[0][:3] == first


@pytest.mark.parametrize("text", [MERGE_CLASH, MERGE_LAST, MERGE_UNDEF], ids=["clash", "last", "undef"])
def test_a_merged_choose_whose_body_fails_the_reports_are_equal(tmp_path, capsys, text):
    code, out = both(tmp_path, capsys, text, "--deadlock")
    assert code == 1
    assert out["violations"][0]["property"] == "error"
