"""The choices of a trace's steps from the native engine (NativeExplorer.guided_step, native_bfs.c
asm_first_choices): the native engine gives the choice vector of its first run from a stored
state to another, the Python step function runs once along it, and the trace is the one the
enumeration of every successor gives (the first step in the enumeration's order that reaches
the target).  Compared here with that enumeration (the native hint switched off) and with the
Python engine: every step between stored states, the printed traces (text and JSON), temporal
witnesses and counterexamples; and the enumeration is not run where the hint reads.

Engines: native (each case is compared with the Python engine's run or enumeration)."""
from __future__ import annotations

import json

import pytest

import asmcheck
from asmcheck.cli import main
from asmcheck.explore.native import NativeExplorer
from asmcheck.explore.native_build import compiler
from asmcheck.semantics.machine import Machine

from conftest import ROOT
from helpers import write
from test_symmetry import MUTEX, PHILS

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native explorer cannot run here")]

IGNORED_KEYS = ("seconds", "engine", "compile_seconds", "engine_note")

# a monitored input and one plain choose (the only choose of the step: not merged by effect); an
# invariant, a CTL witness (ef) and an LTL counterexample
MON = """asm MonChoose
import StandardLibrary
import CTLLibrary
import LTLLibrary
signature:
	domain Slot subsetof Integer
	domain Val subsetof Integer
	controlled v: Slot -> Val
	monitored go: Boolean
	monitored amount: Val
definitions:
	domain Slot = {1 : 3}
	domain Val = {0 : 3}
	invariant over v: v(1) + v(2) + v(3) < 7
	CTLSPEC ef(v(1) = 3 and v(2) = 2)
	LTLSPEC g(v(3) < 2)
	main rule r_main =
		if go then
			choose $s in Slot with v($s) < 3 do
				v($s) := v($s) + 1
		else
			if v(1) < amount then v(1) := amount endif
		endif
default init s0:
	function v($s in Slot) = 0
"""

# two chooses in a step (parking's form): one over the free places, one per taken place whose
# body makes no choice and has two effects from six candidates (merged by effect natively)
MERGED = """asm Merged
import StandardLibrary
import CTLLibrary
signature:
	domain Row subsetof Integer
	domain Prob subsetof Integer
	controlled free: Row -> Boolean
	monitored newCar: Boolean
definitions:
	domain Row = {1 : 3}
	domain Prob = {1 : 6}
	CTLSPEC ef((forall $r in Row with not(free($r))))
	CTLSPEC not(ef(not(free(1)) and not(free(3))))
	main rule r_Main =
		par
			if newCar then
				choose $r in Row with free($r) do
					free($r) := false
			endif
			forall $r1 in Row with not(free($r1)) do
				choose $p in Prob with true do
					if $p <= $r1 then free($r1) := true endif
		endpar
default init s0:
	function free($r in Row) = true
"""

# a choose in a choose's body (the outer one's alternatives are the pairs' effects in the Python
# step, a candidate and then the inner choose's in the native one)
NESTED = """asm Nested
import StandardLibrary
signature:
	domain A subsetof Integer
	controlled x: A -> A
definitions:
	domain A = {1 : 3}
	invariant over x: x(1) + x(2) + x(3) < 8
	main rule r_main =
		choose $a in A with true do
			choose $b in A with $b != $a do
				x($a) := $b
default init s0:
	function x($a in A) = 1
"""

# agents: the scheduler's choose runs a program that reads a monitored input (the choose's
# alternatives are (task, input) pairs in the Python step)
AGENTS = """asm Agents
import StandardLibrary
signature:
	domain Task subsetof Agent
	domain Cnt subsetof Integer
	static t1: Task
	static t2: Task
	controlled count: Task -> Cnt
	controlled last: Task
	monitored tick: Task -> Boolean
definitions:
	domain Cnt = {0 : 3}
	rule r_task =
		par
			last := self
			if tick(self) and count(self) < 3 then count(self) := count(self) + 1 endif
		endpar
	invariant over count: count(t1) + count(t2) < 5
	main rule r_main =
		choose $t in Task with true do
			program($t)
default init s0:
	function count($t in Task) = 0
	agent Task: r_task[]
"""

# fresh elements (extend), and a choose among them
FRESH = """asm Fresh
import StandardLibrary
signature:
	dynamic abstract domain Tok
	domain Small subsetof Integer
	controlled level: Tok -> Small
	controlled made: Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 2}
	invariant over level: not((exists $t in Tok with level($t) = 2))
	main rule r_main =
		if go and made < 2 then
			extend Tok with $t do
				par
					level($t) := 0
					made := made + 1
				endpar
		else
			choose $x in Tok with level($x) < 2 do
				level($x) := level($x) + 1
		endif
default init s0:
	function made = 0
"""

# a choose with a single candidate (no choice point in either engine) beside a monitored input
# and a second choose
SINGLE = """asm Single
import StandardLibrary
signature:
	domain Slot subsetof Integer
	controlled v: Slot -> Slot
	controlled cur: Slot
	monitored inc: Boolean
definitions:
	domain Slot = {1 : 3}
	invariant over v: v(3) < 3
	main rule r_main =
		par
			choose $s in Slot with $s = cur do
				if inc then v($s) := (v($s) mod 3) + 1 endif
			choose $n in Slot with $n != cur and $n <= cur + 1 do
				cur := $n
		endpar
default init s0:
	function v($s in Slot) = 1
	function cur = 1
"""

# chooses whose candidates share effects: the pairs of faces that give the same sum, with the
# monitored input read in the body (the alternatives are the distinct (sum, input) effects in the
# Python step, candidates and then the input in the native one), and a plain one over two dice
# without input (Mutex's, a choose among processes of which several do nothing, is another)
DICE = """asm Dice
import StandardLibrary
signature:
	domain Face subsetof Integer
	domain Sum subsetof Integer
	domain Roll subsetof Integer
	controlled total: Sum
	controlled rolls: Roll
	monitored bet: Face
definitions:
	domain Face = {1 : 3}
	domain Sum = {0 : 6}
	domain Roll = {0 : 3}
	invariant over total: total < 6 or rolls < 2
	main rule r_main =
		if rolls < 3 then
			choose $x in Face, $y in Face with true do
				par
					total := ($x + $y + bet) mod 7
					rolls := rolls + 1
				endpar
		else
			choose $a in Face, $b in Face with $a <= $b do
				par
					total := ($a * $b) mod 7
					rolls := 0
				endpar
		endif
default init s0:
	function total = 0
	function rolls = 0
"""

# temporal properties whose atoms read the monitored input: their steps are the first whose input
# gives the atoms' values (kripke._PicksOfSteps)
ATOMS = MON.replace("asm MonChoose", "asm MonAtoms").replace(
    "\tLTLSPEC g(v(3) < 2)\n", "\tLTLSPEC g(v(3) < 2)\n\tCTLSPEC ag(not(go and v(1) = 2))\n\tLTLSPEC g(not(go and v(2) = 2))\n")

SPECS = {"MON": MON, "ATOMS": ATOMS, "MERGED": MERGED, "NESTED": NESTED, "AGENTS": AGENTS, "FRESH": FRESH, "SINGLE": SINGLE, "DICE": DICE,
         "MUTEX": MUTEX, "PHILS": PHILS}


def _no_hint(monkeypatch):
    monkeypatch.setattr(NativeExplorer, "native_choices", lambda self, src, dst: None)


def _printed(path: str, engine: str, capsys, symmetry: bool = False) -> tuple:
    """(text report but its first line, JSON report but the timings) of ``asmcheck explore``."""
    extra = ["--symmetry"] if symmetry else []
    main(["explore", path, "--engine", engine] + extra)
    text = capsys.readouterr().out.splitlines()[1:]
    main(["explore", path, "--engine", engine, "--format", "json"] + extra)
    out = json.loads(capsys.readouterr().out)
    return text, {k: v for k, v in out.items() if k not in IGNORED_KEYS}


def _traces(run) -> list:
    """Every trace of a run (violations, temporal counterexamples and witnesses): its states and
    choices."""
    out = []
    for _, tr in run.traces():
        out.append([(s.state, [(c.kind, c.label, c.n, c.pick, c.value) for c in s.choices]) for s in tr.steps])
    for t in run.temporal:
        got = t.trace()
        if got is not None:
            out.append((t.name, t.witness, got[1],
                        [(s.state, [(c.kind, c.label, c.n, c.pick, c.value) for c in s.choices]) for s in got[0].steps]))
    return out


def _counting(monkeypatch) -> dict:
    """Counts the steps the native engine's choices gave (hit) and those it did not (miss)."""
    seen = {"hit": 0, "miss": 0}
    orig = NativeExplorer.guided_step

    def guided(self, *a, **k):
        got = orig(self, *a, **k)
        seen["hit" if got is not None else "miss"] += 1
        return got
    monkeypatch.setattr(NativeExplorer, "guided_step", guided)
    return seen


# (spec, symmetry, the steps between stored states (one per pair), how many of them the native
# engine's choices give (the others: a choose whose body makes a choose), the runs of the Python
# step that took (more than one a step: chooses whose candidates share effects))
EDGES = [("MON", False, 256, 256, 256), ("ATOMS", False, 256, 256, 256), ("MERGED", False, 54, 54, 54),
         ("NESTED", False, 52, 0, 52), ("AGENTS", False, 116, 116, 116), ("FRESH", False, 15, 15, 15),
         ("SINGLE", False, 270, 270, 270), ("DICE", False, 175, 175, 403), ("MUTEX", True, 16, 16, 16),
         ("PHILS", True, 22, 22, 22)]


@pytest.mark.parametrize("name,symmetry,edges,given,runs", EDGES, ids=[e[0] for e in EDGES])
def test_every_step_as_the_enumeration(tmp_path, monkeypatch, name, symmetry, edges, given, runs):
    """For every step between stored states (of the search's tree under symmetry reduction): the
    choices read from the native engine's are those of the first successor, in the enumeration's
    order, that is the target."""
    model = asmcheck.load(write(tmp_path, SPECS[name]))
    # (symmetry reduction keeps no graph: the steps of the search's tree there)
    run = model.explore(engine="native", graph=not symmetry, symmetry=symmetry)
    ex = run.explorer
    assert run.engine == "native"
    if symmetry:
        dst_a = [s for s in range(ex.n_states) if ex.parent[s] >= 0]
        src_a = [ex.parent[s] for s in dst_a]
    else:
        src_a, dst_a = ex.edge_arrays()
    with monkeypatch.context() as mp:
        _no_hint(mp)
        first = {(src, dst): ex.picks_between(src, dst) for src, dst in zip(src_a, dst_a)}
    made = []

    class Counted(NativeExplorer._Guide):
        def __init__(self, *a):
            made.append(1)
            super().__init__(*a)
    monkeypatch.setattr(NativeExplorer, "_Guide", Counted)
    n = 0
    for src, dst in zip(src_a, dst_a):
        got = ex.guided_step(src, dst)
        if got is not None:
            n += 1
            assert tuple(c.pick for c in got[1]) == first[(src, dst)], (src, dst)
    assert (len(src_a), n, len(made)) == (edges, given, runs)


@pytest.mark.parametrize("name,symmetry", [(e[0], e[1]) for e in EDGES], ids=[e[0] for e in EDGES])
def test_printed_traces_as_before(tmp_path, capsys, monkeypatch, name, symmetry):
    """The text and JSON reports with the native engine's choices, without them, and the Python
    engine's: the same."""
    path = write(tmp_path, SPECS[name])
    now = _printed(path, "native", capsys, symmetry)
    py = _printed(path, "python", capsys, symmetry)
    with monkeypatch.context() as mp:
        _no_hint(mp)
        before = _printed(path, "native", capsys, symmetry)
    assert now == before
    assert now == py
    assert any("step 1" in line for line in now[0])


# (visual_servoing's: its Python run takes 10 s)
BUGGY = sorted(p.name for p in (ROOT / "specs" / "buggy").glob("*.asm") if not p.name.startswith("visual_servoing"))


@pytest.mark.parametrize("name", BUGGY)
def test_seeded_bugs_as_before(capsys, monkeypatch, name):
    """specs/buggy (agents scheduled by a choose whose programs read monitored inputs; invariants,
    step properties and LTL properties of properties/): the reports with the native engine's
    choices, without them, and the Python engine's, the same."""
    path = str(ROOT / "specs" / "buggy" / name)
    seen = _counting(monkeypatch)
    now = _printed(path, "native", capsys)
    assert seen["hit"] > 0 and seen["miss"] == 0
    py = _printed(path, "python", capsys)
    with monkeypatch.context() as mp:
        _no_hint(mp)
        before = _printed(path, "native", capsys)
    assert now == before == py
    assert now[1]["verdict"] == "violated"


# (spec, symmetry, traces, steps the native engine's choices give, steps they do not)
TRACES = [("MON", False, 3, 12, 0), ("ATOMS", False, 5, 19, 0), ("MERGED", False, 2, 5, 0), ("NESTED", False, 1, 0, 3), ("AGENTS", False, 1, 5, 0),
          ("FRESH", False, 1, 3, 0), ("SINGLE", False, 1, 5, 0), ("DICE", False, 1, 2, 0), ("MUTEX", True, 3, 15, 0), ("PHILS", True, 1, 4, 0)]


@pytest.mark.parametrize("name,symmetry,traces,hit,miss", TRACES, ids=[e[0] for e in TRACES])
def test_witnesses_and_counterexamples_as_before(tmp_path, monkeypatch, name, symmetry, traces, hit, miss):
    """Every trace of the API's run (the witnesses of the properties that hold too), with and
    without the native engine's choices, and the Python engine's: the same."""
    path = write(tmp_path, SPECS[name])
    seen = _counting(monkeypatch)
    now = _traces(asmcheck.load(path).explore(engine="native", symmetry=symmetry))
    py = _traces(asmcheck.load(path).explore(engine="python", symmetry=symmetry))
    assert (len(now), seen["hit"], seen["miss"]) == (traces, hit, miss)
    with monkeypatch.context() as mp:
        _no_hint(mp)
        before = _traces(asmcheck.load(path).explore(engine="native", symmetry=symmetry))
    assert now == before == py


def test_the_enumeration_is_not_run(tmp_path, monkeypatch):
    """Where the native engine's choices read as the Python step's, no trace enumerates the
    successors of a state: the witness of Merged's first property, the counterexample of its
    second, and MonChoose's invariant, CTL witness and LTL counterexample."""
    runs = [asmcheck.load(write(tmp_path, text)).explore(engine="native") for text in (MERGED, MON)]
    calls = []
    real = Machine.successors

    def successors(self, *a, **k):
        calls.append(1)
        return real(self, *a, **k)
    monkeypatch.setattr(Machine, "successors", successors)
    traces = [_traces(r) for r in runs]
    assert calls == []
    monkeypatch.setattr(Machine, "successors", real)
    _no_hint(monkeypatch)
    again = [asmcheck.load(write(tmp_path, text)).explore(engine="native") for text in (MERGED, MON)]
    assert [_traces(r) for r in again] == traces
    assert [[t.verdict for t in r.temporal] for r in runs] == [["holds", "violated"], ["holds", "violated"]]
    assert [len(t) for t in traces] == [2, 3]
