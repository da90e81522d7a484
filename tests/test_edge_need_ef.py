"""A whole property ``ef(b)`` or ``ag(p)`` with one initial state (asmcheck.temporal.need): the native
search records only the lists b or p reads, ``ef(b)`` is shown from the edges it keeps (the search
tree's, the first entry of each list) or searched again with its lists, and the path (the witness of
``ef(b)``, the counterexample of ``ag(p)``) is the search tree's.  States, transitions, verdicts and
every trace are those of the Python engine, which keeps every list."""
from __future__ import annotations

import pytest

from asmcheck import api
from asmcheck.explore.native_build import compiler
from asmcheck.report.trace import temporal_text

from helpers import write

pytestmark = pytest.mark.engines("native")

needs_cc = pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")

# a walk on a 4 x 4 grid: each step moves right, up or not at all (an input, in the order of DIRS),
# modulo 4 (WRAP) or stopping at the edge; ``start`` true makes a second initial state (x = 1)
GRID = """asm Grid
import StandardLibrary
import CTLLibrary
signature:
	domain Coord subsetof Integer
	enum domain Dir = {DIRS}
	controlled x: Coord
	controlled y: Coord
	monitored d: Dir
	monitored start: Boolean
definitions:
	domain Coord = {0 : 3}
{props}
	main rule r_main = if d = RIGHT then x := {xstep} else if d = UP then y := {ystep} endif endif
default init s0:
	function x = {x0}
	function y = 0
"""

WRAP = "RIGHT | UP | STAY"


def _grid(tmp_path, props, dirs=WRAP, wrap=True, two=False) -> str:
    text = GRID.replace("{props}", "\n".join(f"\tCTLSPEC {p}" for p in props)).replace("{DIRS}", "{" + dirs + "}")
    step = "({v} + 1) mod 4" if wrap else "min({v} + 1, 3)"
    text = text.replace("{xstep}", step.format(v="x")).replace("{ystep}", step.format(v="y"))
    return write(tmp_path, text.replace("{x0}", "if start then 1 else 0 endif" if two else "0"))


def _run(path, engine: str):
    model = api.load(path)
    run = model.explore(engine=engine)
    rows = [(r.name, r.verdict, temporal_text(r, model.machine)) for r in run.temporal]
    return run, rows


def _cells(r) -> list:
    """The (x, y) of each state of a property's path, and its loop index."""
    tr, loop, _ = r.trace()
    out = []
    for s in tr.steps:
        vals = {k.name if hasattr(k, "name") else k: v for k, v in s.state.items()}
        out.append(tuple(v for _, v in sorted(vals.items(), key=lambda kv: str(kv[0]))))
    return out, loop


def _entries(run) -> int:
    K = next(r.K for r in run.temporal if r.K is not None)
    return K.cls_succ.off[-1]


@pytest.fixture
def again(monkeypatch):
    """The searches run again to record more lists (lists_again), counted."""
    from asmcheck.explore import native as N
    calls = []
    orig = N.NativeExplorer.lists_again
    monkeypatch.setattr(N.NativeExplorer, "lists_again", lambda self, *a: calls.append(1) or orig(self, *a))
    watched = N.NativeExplorer._watched_broken
    monkeypatch.setattr(N.NativeExplorer, "_watched_broken", lambda self, sid: calls.append(2) or watched(self, sid))
    monkeypatch.delenv("ASMCHECK_EDGE_NEED", raising=False)
    return calls


def _same_as_python(path, again, kept, entries, runs_again, verdicts, transitions=48):
    run, rows = _run(path, "native")
    assert run.engine == "native"
    assert (run.states, run.transitions) == (16, transitions)
    assert run.explorer.lists_kept == kept
    assert again == runs_again
    assert _entries(run) == entries
    assert [r[1] for r in rows] == verdicts
    py, py_rows = _run(path, "python")
    assert (py.states, py.transitions) == (run.states, run.transitions)
    assert py_rows == rows
    return run, py


@needs_cc
@pytest.mark.parametrize("dirs,b,cells", [
    # (2, 2) at depth 4, six shortest paths: the first in the search's order (right before up)
    (WRAP, "x = 2 and y = 2", [(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)]),
    # (1, 2) and (2, 1) both at depth 3: (2, 1) is found first (x moves first)
    (WRAP, "(x = 1 and y = 2) or (x = 2 and y = 1)", [(0, 0), (1, 0), (2, 0), (2, 1)]),
    # up before right: (1, 2) first, through (0, 1), (0, 2)
    ("UP | RIGHT | STAY", "(x = 1 and y = 2) or (x = 2 and y = 1)", [(0, 0), (0, 1), (0, 2), (1, 2)]),
    ("UP | RIGHT | STAY", "x = 2 and y = 2", [(0, 0), (0, 1), (0, 2), (1, 2), (2, 2)]),
])
def test_ef_witness_is_the_search_trees_path(tmp_path, again, dirs, b, cells):
    """Decided from the edges kept (each list keeps its first entry), no search again; the witness
    is the path of the breadth-first tree to the first state in the search's order that satisfies
    b, state for state the one the Python engine finds with every list."""
    path = _grid(tmp_path, [f"ef({b})"], dirs)
    run, py = _same_as_python(path, again, "none", 16, [], ["holds"])
    assert run.temporal[0].witness and py.temporal[0].witness
    assert _cells(run.temporal[0]) == _cells(py.temporal[0]) == (cells, None)


@needs_cc
def test_not_ef_counterexample_is_the_search_trees_path(tmp_path, again):
    """A whole ag(p) broken (not(ef(b))): the counterexample is the tree's path, the search neither
    watches p nor runs again."""
    path = _grid(tmp_path, ["not(ef(x = 2 and y = 2))", "ag(x < 4)"])
    run, py = _same_as_python(path, again, "none", 16, [], ["violated", "holds"])
    assert _cells(run.temporal[0]) == _cells(py.temporal[0]) == ([(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)], None)


@needs_cc
@pytest.mark.parametrize("wrap,entries,cells,loop", [
    # eg(x = 3) reads the lists of the x = 3 states (4 x 3 entries), the others keep one; the lasso's
    # loop is one node of the quotient (x = 3 to (3, 1): from (3, 0) up, from (3, 1) staying)
    (True, 12 * 1 + 4 * 3, [(0, 0), (1, 0), (2, 0), (3, 0), (3, 1)], 3),
    # stopping at the edge: (3, 3) has two steps to itself (right, stay), one node; the lasso stays
    (False, 12 * 1 + 4 * 2 - 1, [(0, 0), (1, 0), (2, 0), (3, 0), (3, 0)], 3),
])
def test_ef_of_eg(tmp_path, again, wrap, entries, cells, loop):
    """ef(eg(p)): only the lists eg(p) reads (those of the p states); the witness is the tree's path
    to the first state whose list has an eg(p) node, then eg(p)'s lasso."""
    path = _grid(tmp_path, ["ef(eg(x = 3))"], wrap=wrap)
    run, py = _same_as_python(path, again, "some", entries, [], ["holds"], 48 if wrap else 40)
    assert _cells(run.temporal[0]) == _cells(py.temporal[0]) == (cells, loop)


@needs_cc
def test_ef_holding_where_the_edges_kept_do_not_show_it(tmp_path, again):
    """Every first entry is the step that stays (STAY first): the tree shows (2, 2) reached from one
    successor of the initial state only, so the search runs again with the lists ef(b) reads."""
    path = _grid(tmp_path, ["ef(x = 2 and y = 2)"], "STAY | RIGHT | UP")
    run, py = _same_as_python(path, again, "some", 15 * 3 + 1, [1], ["holds"])
    assert _cells(run.temporal[0]) == _cells(py.temporal[0]) == ([(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)], None)


@needs_cc
@pytest.mark.parametrize("b,wrap,entries,transitions", [
    # no state satisfies b: its lasso reads every list (the search again with them)
    ("x > 3", True, 48, 48),
    # (3, 0) is a state, but after a first step up no path comes back to y = 0: violated, the
    # lists of the states outside b again
    ("x = 3 and y = 0", False, 40 - 1, 40),
])
def test_violated_ef_searches_again_with_its_lists(tmp_path, again, b, wrap, entries, transitions):
    path = _grid(tmp_path, [f"ef({b})"], wrap=wrap)
    run, py = _same_as_python(path, again, "some", entries, [1], ["violated"], transitions)
    assert _cells(run.temporal[0]) == _cells(py.temporal[0])
    assert _cells(run.temporal[0])[1] is not None            # a lasso


@needs_cc
def test_two_initial_states_are_not_deferred(tmp_path, again):
    """Two initial states (x = 0 and x = 1): ef(b) reads the lists of the states outside b, as
    before; the same witness."""
    path = _grid(tmp_path, ["ef(x = 2 and y = 2)"], two=True)
    run, py = _same_as_python(path, again, "some", 15 * 3 + 1, [], ["holds"])
    assert _cells(run.temporal[0]) == _cells(py.temporal[0]) == ([(1, 0), (2, 0), (2, 1), (2, 2)], None)


@needs_cc
@pytest.mark.parametrize("prop,verdict,runs_again", [
    # a conjunct: ef(b) reads the lists of the states outside b, ag(x < 4) is decided by the states
    ("ef(x = 2 and y = 2) and ag(x < 4)", "holds", []),
    # ag(x < 3) broken: watched, the search stops there and runs again with its lists
    ("ef(x = 2 and y = 2) and ag(x < 3)", "violated", [2]),
])
def test_ef_and_ag(tmp_path, again, prop, verdict, runs_again):
    path = _grid(tmp_path, [prop])
    run, rows = _run(path, "native")
    assert again == runs_again
    assert run.explorer.lists_kept == "some"
    assert [r[1] for r in rows] == [verdict]
    py, py_rows = _run(path, "python")
    assert (py.states, py.transitions) == (run.states, run.transitions) == (16, 48)
    assert py_rows == rows


def test_fork_ef_is_not_decided_by_the_set_of_states(tmp_path, again):
    """ef(b) must hold after every first step: x = 2 is a state, but the first step to x = 1 stays
    there for ever (violated, on both engines)."""
    path = write(tmp_path, """asm Fork
import StandardLibrary
import CTLLibrary
signature:
	domain Val subsetof Integer
	controlled x: Val
	monitored d: Boolean
definitions:
	domain Val = {0 : 2}
	CTLSPEC ef(x = 2)
	main rule r_main = if x = 0 then if d then x := 1 else x := 2 endif endif
default init s0:
	function x = 0
""")
    engines = ["python"] + (["native"] if compiler() is not None else [])
    got = [_run(path, e) for e in engines]
    assert all([r[1] for r in rows] == ["violated"] for _, rows in got)
    assert all(rows == got[0][1] for _, rows in got)
    assert all((run.states, run.transitions) == (3, 4) for run, _ in got)


@needs_cc
def test_a_search_again_records_every_deferred_propertys_lists(tmp_path, again):
    """ef(x = 3 and y = 0) violated makes the search run again: then the lists of the whole ag(p)
    broken (not(ef(..))) and of the ef(b) that the edges kept showed are recorded too (the search
    again leaves nothing to decide after it), and every path is the one found on the lists."""
    path = _grid(tmp_path, ["ef(x = 3 and y = 0)", "not(ef(x = 2 and y = 2))", "ef(x = 1 and y = 3)"],
                 wrap=False)
    run, py = _same_as_python(path, again, "some", 40, [1], ["violated", "violated", "holds"], 40)
    for r, q in zip(run.temporal, py.temporal):
        assert _cells(r) == _cells(q)


@needs_cc
@pytest.mark.slow
def test_parking_same_report_as_every_list(monkeypatch):
    """examples/parking.asm (86,093,442 transitions): its three properties are whole; the search keeps
    32,783 list entries (the initial state's 16, one of every other state) instead of the 98,320
    nodes' lists, and prints the same verdicts, witnesses and counterexample."""
    import os
    from pathlib import Path
    shared = Path(os.environ.get("ASMCHECK_SHARED", Path(__file__).resolve().parents[2] / "shared"))
    p = shared / "asmeta" / "asm_examples" / "examples" / "parking.asm"
    if not p.exists():
        pytest.skip(f"the ASMETA corpus is not in {shared} (ASMCHECK_SHARED)")
    got = []
    for lists in ("", "all"):
        monkeypatch.setenv("ASMCHECK_EDGE_NEED", lists)
        model = api.load(str(p))
        run = model.explore(engine="native")
        got.append((run.states, run.transitions, _entries(run), [r.verdict for r in run.temporal],
                    {r.stats["kripke_nodes"] for r in run.temporal}, [_path_states(r) for r in run.temporal]))
        if lists == "":
            # (the replayed text once: replaying ctl_1's witness looks for each step among a
            # state's 2,627 through the Python step function, some 8 s; the same states give the
            # same text)
            texts = [temporal_text(r, model.machine) for r in run.temporal]
    assert got[0][:5] == (32768, 86093442, 32783, ["holds", "holds", "violated"], {19})
    assert got[1][:2] == got[0][:2] and got[1][3:5] == (got[0][3], {98320})
    assert got[0][5] == got[1][5]
    assert len(got[0][5][0][0]) == 16             # ctl_1's witness: 15 cars parked, one a step
    assert "step 2: r_Main chooses $r = 1, $c = 4, $p = 11; reads newCar = true" in "\n".join(texts[2])


def _path_states(r):
    """The states of a property's path (the source of its first node, then the target of each node
    but the last, as the replay takes them) and its loop index: what the replay shows, state for
    state."""
    K, nodes = r.K, r.nodes
    if not nodes:
        return [], r.loop
    return [K.sid[nodes[0]]] + [K.tgt[v] for v in nodes[:-1]], r.loop
