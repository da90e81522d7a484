"""``explore --graph`` on the native engine labels every step from the one enumeration of its
state's steps (``NativeExplorer.graph_made``): no step is run again to label its edge, and the
files are byte for byte the Python engine's.  Engines pinned: native, compared with python."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from asmcheck import api
from asmcheck.cli import main
from asmcheck.explore.native_build import compiler
from asmcheck.report import graph as graph_report

from helpers import write

ROOT = Path(__file__).resolve().parent.parent
SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))
SWAP = SHARED / "asmeta" / "asm_examples" / "examples" / "swapBoard.asm"

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")]

# a choose inside a choose, a monitored function with arguments read in the guard, an INVAR over
# the monitored values: 18 states, 72 transitions; each step is in the graph once per sequence of
# monitored values that leads to it (144 edges), two steps of equal choices differ by what they read
PICK = """asm Pick
import StandardLibrary
signature:
	domain Slot subsetof Integer
	enum domain Col = {RED | BLUE | GREEN}
	controlled a: Slot -> Col
	controlled n: Slot
	monitored sensor: Slot -> Boolean
definitions:
	domain Slot = {1 : 2}
	INVAR sensor(1) or sensor(2)
	main rule r_main =
		choose $s in Slot with sensor($s) do
			choose $c in Col with $c != a($s) do
				par
					a($s) := $c
					n := $s
				endpar
default init s0:
	function a($s in Slot) = RED
	function n = 1
"""

# a step that reads nothing, one that reads a value, and one that fails (no edge)
STEPS = """asm Steps
import StandardLibrary
signature:
	domain Cnt subsetof Integer
	controlled x: Cnt
	monitored up: Boolean
definitions:
	domain Cnt = {0 : 3}
	main rule r_main =
		if x = 0 then
			x := 1
		else
			if up then x := x + 1 else x := 0 endif
		endif
default init s0:
	function x = 0
"""


def _files(path, tmp_path, capsys, engine):
    out = []
    for suffix in ("dot", "graphml"):
        g = tmp_path / f"{engine}.{suffix}"
        main(["explore", path, "--engine", engine, "--graph", str(g)])
        capsys.readouterr()
        out.append(g.read_bytes())
    return out


@pytest.mark.parametrize("text", [PICK, STEPS], ids=["pick", "steps"])
def test_graph_files_equal_and_no_step_run_again(tmp_path, capsys, monkeypatch, text):
    path = write(tmp_path, text)
    python = _files(path, tmp_path, capsys, "python")

    def refuse(*a, **k):
        raise AssertionError("a step was run again to label its edge")
    # the native engine's graph never labels an edge by running its step again
    monkeypatch.setattr(graph_report, "edge_label", refuse)
    native = _files(path, tmp_path, capsys, "native")
    assert native == python


def test_pick_edges_and_labels(tmp_path):
    path = write(tmp_path, PICK)
    run = api.load(path).explore(engine="native", graph=True)
    ex = run.explorer
    assert (run.engine, run.states, run.transitions) == ("native", 18, 72)
    steps, made = ex.graph_edges(), ex.graph_made()
    assert len(steps) == len(made) == 144
    # the steps from the initial state: a is RED everywhere, so $c is BLUE or GREEN
    g = graph_report.state_graph(ex)
    first = [(v, d["choices"]) for u, v, d in g.edges(data=True) if u == 0]
    assert first == [
        (1, "r_main chooses $s = 2, $c = BLUE; reads sensor(1) = false, sensor(2) = true"),
        (1, "r_main chooses $s = 2, $c = BLUE; reads sensor(1) = true, sensor(2) = true"),
        (2, "r_main chooses $s = 2, $c = GREEN; reads sensor(1) = false, sensor(2) = true"),
        (2, "r_main chooses $s = 2, $c = GREEN; reads sensor(1) = true, sensor(2) = true"),
        (3, "r_main chooses $s = 1, $c = BLUE; reads sensor(1) = true, sensor(2) = false"),
        (3, "r_main chooses $s = 1, $c = BLUE; reads sensor(1) = true, sensor(2) = true"),
        (4, "r_main chooses $s = 1, $c = GREEN; reads sensor(1) = true, sensor(2) = false"),
        (4, "r_main chooses $s = 1, $c = GREEN; reads sensor(1) = true, sensor(2) = true")]
    # one object per printed label: as many as the graph has distinct labels
    labels = {d["choices"] for _, _, d in g.edges(data=True)}
    assert len({id(x) for x in made}) == len(labels) == 12


@pytest.mark.slow
def test_swapboard_graph_counts(tmp_path):
    """swapBoard: 15,120 states, 498,192 transitions; the graph has every sequence of choices of
    every state (559,440 edges: 36 swaps of two cells whose effects differ, and the swap of rows)."""
    if not SWAP.exists():
        pytest.skip(f"the ASMETA corpus is not in {SHARED} (ASMCHECK_SHARED)")
    out = tmp_path / "swap.dot"
    code = main(["explore", str(SWAP), "--engine", "native", "--graph", str(out)])
    assert code == 0
    lines = out.read_text().splitlines()
    edges = [ln for ln in lines if " -> " in ln]
    nodes = [ln for ln in lines if ln.startswith("  s") and " -> " not in ln]
    assert (len(nodes), len(edges)) == (15120, 559440)
    assert edges[0] == ('  s0 -> s0 [label="r_randomlySwapCells chooses $r1 = 1, $c1 = 2, $r2 = 2, $c2 = 1; '
                        'reads swap = CELL"];')
    labels = {ln.split('[label="', 1)[1] for ln in edges}
    # 36 unordered pairs of cells (each printed as the first ordered pair of its effect, in some
    # state) with swap = CELL, and the swap of rows
    assert sum(1 for x in labels if "swap = ROW" in x) == 1


def test_ctrl_c_while_the_graph_is_made(tmp_path, capsys, monkeypatch):
    """Ctrl-C while the steps of the graph are enumerated: the run is incomplete and the graph
    holds the steps found so far; writing it does not enumerate every step again (it did, so a
    Ctrl-C did not stop swapBoard)."""
    from asmcheck.explore import native
    path = write(tmp_path, PICK)
    calls = []
    real = native._made_step

    def counted(*a):
        calls.append(1)
        if len(calls) == 10:
            raise KeyboardInterrupt
        return real(*a)
    monkeypatch.setattr(native, "_made_step", counted)
    out = tmp_path / "pick.dot"
    code = main(["explore", path, "--engine", "native", "--graph", str(out)])
    text = capsys.readouterr().out
    assert code == 3
    assert "incomplete" in text
    assert len(calls) == 10
    assert sum(1 for ln in out.read_text().splitlines() if " -> " in ln) == 9
