"""The hand-over of the temporal quotient the native search recorded (NativeExplorer.step_quotient,
native_bfs.c's asm_qf_give): each array is copied out and its C original freed before the next is
made, and the atom bits of a node come as one byte with at most 8 atoms that read monitored
functions, 8 bytes with more, none without.  Each gives the structure, verdicts and printed paths of
the route through the edges and of the Python engine."""
from __future__ import annotations

import pytest

from asmcheck import api
from asmcheck.explore.native import NativeExplorer
from asmcheck.explore.native_build import compiler

from helpers import write
from test_temporal_quotient import structure_arrays, temporal_rows

pytestmark = pytest.mark.engines("native")

needs_cc = pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")

# x = 0..5 counts when inc (5 wraps to 0); noise is read by the atoms only
HEAD = """asm {name}
import StandardLibrary
import CTLLibrary
signature:
	domain Cnt subsetof Integer
	domain Nz subsetof Integer
	controlled x: Cnt
	monitored inc: Boolean
	monitored noise: Nz
definitions:
	domain Cnt = {{0 : 5}}
	domain Nz = {{0 : 8}}
{props}
	main rule r_main =
		if inc then
			if x < 5 then x := x + 1 else x := 0 endif
		endif
default init s0:
	function x = 0
"""

# no atom reads noise: a node is (labels of the source, target); x = 0 and x = 5 are the labels:
# 2 (from 0) + 5 (from 1..4) + 2 (from 5) = 9 nodes
NONE = HEAD.format(name="NoAtoms", props="\tCTLSPEC ag(ef(x = 0))\n\tCTLSPEC ef(x = 5)\n\tCTLSPEC af(x = 5)")
# four atoms read noise (one byte a node; noise = 1 twice, in two formulas): each step comes with the
# 9 values of noise, which give 4 vectors (noise 0, 1, 2, other); x = 5 labels the source: nodes by
# (initial or not, x = 5 or not, vector, target): 4 x 2 (from 0) + 4 x 5 (from 1..4) + 4 x 2 (from 5)
# = 36
THREE = HEAD.format(name="ThreeAtoms", props="\n".join(
    f"\tCTLSPEC ag(ef(noise = {k}))" for k in range(3)) + "\n\tCTLSPEC ef(x = 5 and ex(noise = 1))")
# ten atoms read noise (8 bytes a node): noise = 0 .. 8 and not(noise = 8), 9 vectors; no label reads
# x: 9 x 2 (from 0, initial) + 9 x 6 (from 1..5: targets 0..5) = 72 nodes
NINE = HEAD.format(name="NineAtoms", props="\n".join(
    f"\tCTLSPEC ag(ef(noise = {k}))" for k in range(9)) + "\n\tCTLSPEC eg(not(noise = 8))")


@needs_cc
@pytest.mark.parametrize("text,atoms,code,nodes,verdicts", [
    (NONE, 0, "B", 9, ["holds", "holds", "violated"]),
    (THREE, 4, "B", 36, ["holds"] * 4),
    (NINE, 10, "q", 72, ["holds"] * 9 + ["violated"]),
], ids=["none", "three", "nine"])
def test_handover(tmp_path, monkeypatch, text, atoms, code, nodes, verdicts):
    got = []
    orig = NativeExplorer.step_quotient

    def spy(self, items, *a):
        res = orig(self, items, *a)
        if res is not None:
            got.append((len(items), res[2].typecode, len(res[2]), len(res[0])))
        return res
    monkeypatch.setattr(NativeExplorer, "step_quotient", spy)
    path = write(tmp_path, text)
    model = api.load(path)
    run = model.explore(engine="native")
    assert run.explorer.edge_src is None            # the recorded pairs, no edges
    assert got == [(atoms, code, nodes if atoms else 0, nodes)]
    K = run.temporal[0].K
    assert K.n == nodes
    rows = temporal_rows(model, run)
    assert [r[1] for r in rows] == verdicts
    # the route through the edges
    monkeypatch.setattr(api, "_quotient_plan", lambda *a: None)
    old_model = api.load(path)
    old = old_model.explore(engine="native")
    assert old.explorer.edge_src is not None
    assert structure_arrays(old.temporal[0].K) == structure_arrays(K)
    assert temporal_rows(old_model, old) == rows
    py_model = api.load(path)
    assert temporal_rows(py_model, py_model.explore(engine="python")) == rows
