"""The native engine on local functions and on the order of a step's choices.

- The order of the choices: the Python engine makes a step's choices (the monitored values it
  reads) in the order it reads them, left to right, and that order is the order of the
  successors, so of the state numbers and of the shortest traces.  C leaves the order in which a
  call's arguments are evaluated open: the arguments that may make a choice (read a monitored
  function, also through a derived function) are evaluated first, in order, when two or more may
  (a derived function, a location read or updated, a library function).
- Local functions (``local x : D [init] body``, asmcheck's own semantics, see the README): with
  arguments, without an initial update of their own, and in specs that use ``extend``.

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


@pytest.mark.parametrize("text", [ORDER_UPDATE, ORDER_DERIVED], ids=["update", "derived"])
def test_the_shortest_trace_takes_the_choices_in_the_python_engines_order(tmp_path, capsys, text):
    code, out = both(tmp_path, capsys, text)
    assert code == 1 and out["verdict"] == "violated"
    assert (out["states"], out["transitions"]) == ((106, 223) if text is ORDER_UPDATE else (5, 10))
    assert trace_choices(out) == [[], [("m1", 0), ("m2", "EE")], [("m1", 0), ("m2", "EE")]]


@pytest.mark.parametrize("text", [ORDER_UPDATE, ORDER_DERIVED, ORDER_READ], ids=["update", "derived", "read"])
def test_the_states_are_numbered_in_the_python_engines_order(tmp_path, text):
    py, pres, nat, nres = engines(write(tmp_path, text), keep_graph=True)
    same_search(py, pres, nat, nres)
    counts = {ORDER_UPDATE: (768, 4477), ORDER_DERIVED: (5, 11), ORDER_READ: (209, 1401)}[text]
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
