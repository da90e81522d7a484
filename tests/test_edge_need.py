"""The successor lists the CTL check reads (asmcheck.temporal.need): the native search records the
list of a state only where a fixpoint step or a path of the check reads it (elsewhere its first entry),
decides ``ag(p)`` from its p and ``ef(p)`` from the initial states, and searches again
with the lists an ``ag(p)`` broken reads.  Verdicts, traces and counts are those of the search that
records every list (``ASMCHECK_EDGE_NEED=all``)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from asmcheck import api
from asmcheck.explore.native_build import compiler
from asmcheck.report.trace import temporal_text
from asmcheck.temporal import formulas
from asmcheck.temporal.formula import FALSE, TRUE, And, Not, Or
from asmcheck.temporal.need import ALL, deferred, edge_need, reads

from helpers import write

pytestmark = pytest.mark.engines("native")

needs_cc = pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")

# x moves by 0..3 (an input) modulo 16: 16 states, 4 successors each (x + 0 is the state itself)
WALK = """asm Walk
import StandardLibrary
import CTLLibrary
signature:
	domain Val subsetof Integer
	domain Step subsetof Integer
	controlled x: Val
	monitored d: Step
definitions:
	domain Val = {0 : 15}
	domain Step = {0 : 3}
{props}
	main rule r_main = x := (x + d) mod 16
default init s0:
	function x = 0
"""


def _spec(tmp_path, props: list[str], name="Walk") -> str:
    text = WALK.replace("{props}", "\n".join(f"\tCTLSPEC {p}" for p in props)).replace("asm Walk", f"asm {name}")
    return write(tmp_path, text)


def _run(path, monkeypatch, every: bool):
    with monkeypatch.context() as mp:
        if every:
            mp.setenv("ASMCHECK_EDGE_NEED", "all")
        else:
            mp.delenv("ASMCHECK_EDGE_NEED", raising=False)
        model = api.load(path)
        run = model.explore(engine="native")
        rows = [(r.name, r.verdict, temporal_text(r, model.machine)) for r in run.temporal]
        return run, rows


def _entries(run) -> int:
    K = next(r.K for r in run.temporal if r.K is not None)
    return K.cls_succ.off[-1]


# ------------------------------------------------------------------ the analysis
A, B = ("ap", 0), ("ap", 1)


def test_reads_of_each_operator():
    assert reads(A) == FALSE
    assert reads(("EU", A, B)) == And(A, Not(B))
    assert reads(("EG", A)) == A
    assert reads(("EX", A)) == ALL
    assert reads(("EU", A, ("EG", B))) == Or(A, B)
    assert reads(("EU", ("EG", A), B)) == ALL
    assert reads(("EG", ("EX", A))) == ALL
    assert reads(("not", ("and", ("EG", A), ("EU", TRUE, B)))) == Or(A, Not(B))
    # ag(p): not E[true U not p]; ef(p)
    assert deferred(Not(("EU", TRUE, Not(A)))) == ("ag", A)
    assert deferred(("EU", TRUE, A)) == ("ef", A)
    assert deferred(("EU", A, B)) is None


@pytest.mark.parametrize("props,want", [
    (["ag(x < 16)", "not(ef(x = 20))"], ("FALSE", 2)),
    (["ef(x = 0)"], ("FALSE", 0)),              # holds in the initial state
    (["ef(x = 5)"], ("FALSE", 1)),             # the whole property, one initial state: after the search
    (["eg(x < 4)"], ("x < 4", 0)),
    (["eu(x < 3, x = 3)", "ag(x < 16)"], ("x < 3 & !x = 3", 1)),
    (["ag(ef(x = 0))"], ("!x = 0", 1)),          # ef(x = 0) at every node: the lists it reads
    (["ag(ef(x = 0)) and ef(x = 3)"], ("!x = 0 | !x = 3", 1)),   # top-level conjuncts, each on its own
    (["ag(ef(x = 0)) or ef(x = 3)"], None),      # E[true U ..] not at the top: every list
    (["ag(x < 3 implies ax(x < 7))"], None),
    (["ef(eg(x = 1))"], ("x = 1", 1)),         # (what eg(x = 1) reads)
    (["ef(eg(x = 1)) and ag(x < 16)"], None),
])
def test_need_of_properties(tmp_path, props, want):
    from asmcheck.temporal.formula import show_formula
    model = api.load(_spec(tmp_path, props))
    m = model.machine
    st = m.initial_state()
    atoms, checks, justice, compassion, _, errors, invars, used = formulas(m, list(model.temporal), [], st)
    need = edge_need(checks, atoms, justice, compassion, invars, used, machine=m, initial=[st])
    if want is None:
        assert need == ALL
    else:
        assert (show_formula(need.cond, atoms), len(need.later)) == want


def test_fairness_ltl_graph_and_invar_need_every_list(tmp_path):
    model = api.load(_spec(tmp_path, ["ag(x < 16)"]))
    m = model.machine
    st = m.initial_state()
    atoms, checks, justice, compassion, _, errors, invars, used = formulas(m, list(model.temporal), [], st)
    assert edge_need(checks, atoms, justice, compassion, invars, used) != ALL
    assert edge_need(checks, atoms, justice, compassion, invars, used, graph=True) == ALL
    assert edge_need(checks, atoms, justice, compassion, invars, used, fair=["all"]) == ALL
    assert edge_need(checks, atoms, [("J", 0)], compassion, invars, used) == ALL
    assert edge_need(checks, atoms, justice, compassion, [0], used) == ALL
    ltl = [(p, "ltl", f, e) for p, _, f, e in checks]
    assert edge_need(ltl, atoms, justice, compassion, invars, used) == ALL


# ------------------------------------------------------------------ the search and the check
@needs_cc
@pytest.mark.parametrize("props,kept,entries,again,verdicts", [
    # every list is one entry: 16 entries for 16 states (64 with every list)
    (["ag(x < 16)", "not(ef(x = 20))", "ef(x = 0)"], "none", 16, False, ["holds", "holds", "holds"]),
    # x < 3 and not x = 3: states 0, 1, 2 keep their 4 successors
    (["eu(x < 3, x = 3)"], "some", 13 + 3 * 4, False, ["holds"]),
    # ef(x = 5) the whole property: decided from the edges kept, its witness the search tree's path
    (["eg(x < 4)", "ef(x = 5)"], "some", 4 * 4 + 12, False, ["holds", "holds"]),
    # ag(x < 9) the whole property, broken at x = 9: its path is the search tree's (no search again)
    (["ag(x < 9)", "ag(x < 16)"], "none", 16, False, ["violated", "holds"]),
    (["not(ef(x = 11))"], "none", 16, False, ["violated"]),
    # ef(x = 0) at every node: read where x is not 0
    (["ag(ef(x = 0))"], "some", 15 * 4 + 1, False, ["holds"]),
    # conjuncts: ag(x < 16) holds, ag(x < 9) is broken (watched: the lists of x < 9 read again)
    (["(forall $v in Step with ag(x < 16 + $v))"], "none", 16, False, ["holds"]),
    (["ag(x < 16) and ag(x < 9)"], "some", 9 * 4 + 7, True, ["violated"]),
    (["ag(x < 9)", "ag(x < 5)"], "none", 16, False, ["violated", "violated"]),
    (["ag(x < 9) and ag(x < 16)", "ag(x < 5) and ag(x < 16)"], "some", 9 * 4 + 7, 2, ["violated", "violated"]),
])
def test_same_report_as_every_list(tmp_path, monkeypatch, props, kept, entries, again, verdicts):
    from asmcheck.explore import native as N
    path = _spec(tmp_path, props)
    calls = []
    orig = N.NativeExplorer._watched_broken
    monkeypatch.setattr(N.NativeExplorer, "_watched_broken", lambda self, sid: calls.append(1) or orig(self, sid))
    after = N.NativeExplorer.lists_again
    monkeypatch.setattr(N.NativeExplorer, "lists_again", lambda self, *a: calls.append(2) or after(self, *a))
    run, rows = _run(path, monkeypatch, every=False)
    assert (run.states, run.transitions) == (16, 64)
    assert run.explorer.lists_kept == kept
    # an ag(p) broken: the search stops at the first state that breaks p and runs again, once for
    # each property broken (at x = 5, then at x = 9 for the two below)
    assert calls == ([1] * again if again else [])
    assert _entries(run) == entries
    assert [r[1] for r in rows] == verdicts
    old, old_rows = _run(path, monkeypatch, every=True)
    assert old.explorer.lists_kept == "all"
    assert _entries(old) == 64
    assert (old.states, old.transitions) == (run.states, run.transitions)
    assert old_rows == rows


@needs_cc
def test_a_violated_ag_prints_the_shortest_path(tmp_path, monkeypatch):
    run, rows = _run(_spec(tmp_path, ["ag(x < 9)"]), monkeypatch, every=False)
    r = run.temporal[0]
    tr, loop, _ = r.trace()
    # 0 -> 3 -> 6 -> 9: the breadth-first path from the initial nodes that break the property to
    # the first state that breaks x < 9 (not from the first initial node, the initial state's step
    # d = 0 that leaves x at 0; as with every list: test_same_report_as_every_list)
    assert [next(iter(s.state.values())) for s in tr.steps] == [0, 3, 6, 9]
    assert [len(s.state) for s in tr.steps] == [1, 1, 1, 1]
    assert loop is None

@needs_cc
def test_bounded_search_keeps_every_list(tmp_path, monkeypatch):
    """The check of a partial state space (temporal.partial) reads every list."""
    path = _spec(tmp_path, ["ag(x < 16)"])
    model = api.load(path)
    run = model.explore(engine="native", max_states=10)
    assert run.explorer.lists_kept == "all"
    run = model.explore(engine="native", max_depth=2)
    assert run.explorer.lists_kept == "all"


# a step fails at x = 14 (out of Val when d = 3 is chosen at 13 ..): halt nodes
HALT = WALK.replace("x := (x + d) mod 16", "if x < 13 then x := x + d else x := x + d endif").replace(
    "asm Walk", "asm WalkHalt")


VERDICTS_HALT = ["holds", "holds", "holds", "violated"]


@needs_cc
def test_failing_steps_give_the_same_verdicts(tmp_path, monkeypatch):
    text = HALT.replace("{props}", "\tCTLSPEC ag(x < 20)\n\tCTLSPEC ef(x = 15)\n\tCTLSPEC eg(x < 14)\n"
                        "\tCTLSPEC not(ef(x = 14))")
    path = write(tmp_path, text)
    run, rows = _run(path, monkeypatch, every=False)
    old, old_rows = _run(path, monkeypatch, every=True)
    assert run.explorer.lists_kept == "some"
    assert (run.states, run.transitions) == (old.states, old.transitions) == (16, 58)
    # the steps out of Val fail: halt nodes, verdicts relative to the first error
    assert all(r.relative_to is not None for r in run.temporal)
    assert [r.verdict for r in run.temporal] == VERDICTS_HALT
    assert rows == old_rows


SHARED = Path(os.environ.get("ASMCHECK_SHARED", Path(__file__).resolve().parents[2] / "shared"))
CORPUS = ["asm_examples/examples/battleship.asm", "asm_examples/examples/carController.asm",
          "asm_examples/examples/ticTacToe/ticTacToe_simulator.asm",
          "asm_examples/examples/RushHour/emptyCellAs0/RushHourSimplForAsmetaSMV.asm",
          "asm_examples/examples/petriNets/forAsmetaSMV/petriNet_forNuSMV_withDeadlock.asm",
          "asm_examples/examples/filosofiEciliegie/filosofiEciliegie.asm",
          "asm_examples/examples/simpleMinesweeper.asm",
          "asm_examples/examples/coffeeVendingMachine/coffeeVendingMachine.asm",
          "asm_examples/examples/petriNets/forAsmetaSMV/petriNet_forNuSMV_notLive_bound1_deadlockFree.asm",
          "asm_examples/stereoacuity/certifierGround.asm"]


@needs_cc
@pytest.mark.slow
@pytest.mark.skipif(not (SHARED / "asmeta").is_dir(), reason="needs ../shared/asmeta (the ASMETA corpus)")
@pytest.mark.parametrize("rel", CORPUS)
def test_corpus_same_json_report(rel):
    sys.path.insert(0, str(Path(__file__).parent))
    from edge_need_diff import compare
    what, kept = compare(SHARED / "asmeta" / rel, seconds=30.0)
    assert what == "same", (rel, what)


# an init that reads the input: four initial states (x = 0 .. 3)
MULTI = WALK.replace("function x = 0", "function x = d").replace("asm Walk", "asm WalkMulti")


@needs_cc
@pytest.mark.parametrize("props,kept,verdicts", [
    (["ag(x < 16)", "ef(x < 4)"], "none", ["holds", "holds"]),
    # ef(x = 0): three initial states miss it; the nodes leaving them keep their lists
    (["ef(x = 0)", "eg(x > 1)"], "some", ["holds", "violated"]),
    (["ag(x < 2)", "not(ef(x = 7))"], "some", ["violated", "violated"]),
])
def test_several_initial_states(tmp_path, monkeypatch, props, kept, verdicts):
    path = write(tmp_path, MULTI.replace("{props}", "\n".join(f"\tCTLSPEC {p}" for p in props)))
    run, rows = _run(path, monkeypatch, every=False)
    old, old_rows = _run(path, monkeypatch, every=True)
    assert (run.states, run.transitions) == (old.states, old.transitions) == (16, 64)
    assert run.explorer.lists_kept == kept
    assert [r[1] for r in rows] == verdicts
    assert rows == old_rows


@needs_cc
def test_memory_limit_says_how_to_decide_on_the_states_explored(tmp_path):
    """A search stopped by the memory bound kept only the lists the complete check reads: the check
    of the states explored is not tried (it reads every list), and the reason says how to have it."""
    model = api.load(_spec(tmp_path, ["ag(x < 16)", "ef(x = 0)"]))
    run = model.explore(engine="native", max_memory=2**20)
    assert run.explorer.lists_kept == "none"
    assert run.result.verdict == "incomplete"
    assert run.result.reason == ("memory limit 1 MB reached; LTL/CTL properties are decided on the states "
                                 "explored only when --max-states or --max-depth bounds the search")
    assert [r["verdict"] for r in run.rows] == ["incomplete", "incomplete"]


@needs_cc
def test_a_broken_ag_of_a_temporal_formula_searches_again_with_every_list(tmp_path, monkeypatch):
    """ag(ef(x = 0)) is broken where a step failed (the run stays there): the path to that node is
    read through E[true U not ef(x = 0)], which reads every list."""
    from asmcheck.explore import native as N
    path = write(tmp_path, HALT.replace("{props}", "\tCTLSPEC ag(ef(x = 0))"))
    calls = []
    after = N.NativeExplorer.lists_again
    monkeypatch.setattr(N.NativeExplorer, "lists_again", lambda self, *a: calls.append(2) or after(self, *a))
    run, rows = _run(path, monkeypatch, every=False)
    # (ef(x = 0) is not watched by the search: the check finds it broken, then the search again)
    assert calls == [2]
    old, old_rows = _run(path, monkeypatch, every=True)
    assert run.explorer.lists_kept == "all"
    assert [r[1] for r in rows] == ["violated"]
    assert rows == old_rows


@needs_cc
def test_a_search_run_again_has_only_the_time_left(tmp_path, monkeypatch):
    """The search that runs again after an ag(p) broke has what is left of the call's time, not the
    whole of it again: here the time is up when ag(x < 600) breaks, so the property is not decided
    (it was violated, on a fresh 60 s).  The search looks at the clock every 256 states: the walk
    has 1,024.  (A conjunction: the whole property ag(p) is not watched, its path is the search tree's.)"""
    from asmcheck.explore import native as N
    import time
    text = WALK.replace("{0 : 15}", "{0 : 1023}").replace("mod 16", "mod 1024").replace(
        "{props}", "\tCTLSPEC ag(x < 600) and ag(x < 2000)")
    path = write(tmp_path, text)
    orig = N.NativeExplorer._watched_broken

    def late(self, sid):
        self.check_deadline = time.monotonic() - 1.0       # the call's time ran out meanwhile
        return orig(self, sid)

    monkeypatch.setattr(N.NativeExplorer, "_watched_broken", late)
    model = api.load(path)
    run = model.explore(engine="native", max_seconds=60)
    assert run.rows == [{"property": "ctl_1", "kind": "ctl", "verdict": "incomplete"}]
    assert (run.stop, run.reason, run.states) == ("time", "time limit 60 s reached", 259)
    # and without the clock moved, the same search decides it
    monkeypatch.setattr(N.NativeExplorer, "_watched_broken", orig)
    run = model.explore(engine="native", max_seconds=60)
    assert run.rows == [{"property": "ctl_1", "kind": "ctl", "verdict": "violated"}]
    assert (run.stop, run.states) == ("", 1024)
