"""The memory layouts of the temporal structure's successor lists (asmcheck.temporal.classes.Classes,
kernel.c's kn_layout): 32-bit nodes, 16-bit nodes, and 16-bit targets read through a table of
nodes; the search's 16-bit lists made 32-bit when an entry no longer fits; E[f U g] by passes over
the forward lists (no backward lists).  Every layout gives the structure, verdicts and printed paths
of the route through the edges."""
from __future__ import annotations

from array import array

import pytest

from asmcheck import api
from asmcheck.explore.native_build import compiler
from asmcheck.report.trace import temporal_text
from asmcheck.temporal import kernel
from asmcheck.temporal.classes import Classes
from asmcheck.temporal.ctl import CTL
from asmcheck.temporal.kripke import Kripke

from helpers import write

pytestmark = pytest.mark.engines("native")

needs_cc = pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")

# 13 bits, all false at first; a step flips bit fi and, when fj differs, bit fj (fi, fj monitored):
# 8,192 states, 91 successors each (13 single flips, 78 double ones).  No atom reads a monitored
# function, so a node is (the atom values of the source, target); a target's 91 sources differ from
# it in one or two bits, and their atom values (over b(0), b(1), b(2), b(3), b(12)) in many ways:
# 100,437 nodes over 8,192 states, so that a list of nodes does not fit 16 bits, its targets do.
FLIP = """asm Flip
import StandardLibrary
import CTLLibrary
signature:
	domain Bit subsetof Integer
	controlled b: Bit -> Boolean
	monitored fi: Bit
	monitored fj: Bit
definitions:
	domain Bit = {0 : 12}
	CTLSPEC ag(ef(b(0) and b(1)))
	CTLSPEC ag(not(b(0) and b(1) and b(2)))
	CTLSPEC ef(eg(b(12) and not b(3)))
	CTLSPEC ag(b(0) implies ex(not b(0) and b(2)))
	CTLSPEC eg(not b(12))
	CTLSPEC af(b(3))
	main rule r_main =
		par
			b(fi) := not b(fi)
			if fj != fi then b(fj) := not b(fj) endif
		endpar
default init s0:
	function b($x in Bit) = false
"""

# the same with an input that the rule does not read but an atom does: every step comes with both
# values; the search's pairs (target, value) fit in 16 bits (16,384), the nodes do not
NOISE = FLIP.replace("asm Flip", "asm FlipNoise").replace(
    "\tmonitored fj: Bit\n", "\tmonitored fj: Bit\n\tmonitored noise: Boolean\n").replace(
    "\tCTLSPEC ag(ef(b(0) and b(1)))\n", "\tCTLSPEC ag(ef(b(0) and b(1) and noise))\n"
    "\tCTLSPEC ag(noise implies ex(b(0) and not noise))\n")

# 17 bits, one flip a step: 131,072 states, so the search's 16-bit lists of targets go 32-bit half
# way
WIDE = """asm Wide
import StandardLibrary
import CTLLibrary
signature:
	domain Bit subsetof Integer
	controlled b: Bit -> Boolean
	monitored fi: Bit
definitions:
	domain Bit = {0 : 16}
	CTLSPEC ag(ef(b(0) and b(1)))
	CTLSPEC ag(not(b(0) and b(1)))
	CTLSPEC ef(eg(b(1)))
	main rule r_main = b(fi) := not b(fi)
default init s0:
	function b($x in Bit) = false
"""


# the next state is the input: every state has the same 10 successors.  One atom, x = 0, holds in
# the initial state only, so a node is (initial or not, target): 20 nodes; the nine states other
# than the initial one have the same list, 11 states share 2 lists
RESET = """asm Reset
import StandardLibrary
import CTLLibrary
signature:
	domain Val subsetof Integer
	controlled x: Val
	monitored inp: Val
definitions:
	domain Val = {0 : 9}
	CTLSPEC ag(ef(x = 0))
	CTLSPEC ag(not(x = 0) implies ax(not(x = 0)))
	CTLSPEC eg(not(x = 0))
	main rule r_main = x := inp
default init s0:
	function x = 0
"""


def _old_route(monkeypatch):
    """Explorations that record the edges (the route before the search recorded the steps)."""
    monkeypatch.setattr(api, "_quotient_plan", lambda *a: None)


def _arrays(K):
    return (K.n, list(K.sid), list(K.tgt), list(K.vec), [list(c) for c in K.cls_succ], list(K.init),
            {i: bytes(lab) for i, lab in K.label.items()})


def _rows(model, run):
    return [(r.name, r.verdict, temporal_text(r, model.machine), r.stats.get("kripke_nodes")) for r in run.temporal]


def _layout(K):
    lay = K.cls_succ.layout()
    return lay[2], lay[1].typecode


@needs_cc
# (entries: of all the states' lists, a step per transition and value of noise; lists: how many
# different lists)
@pytest.mark.parametrize("text,states,transitions,nodes,entries,lists,layout,verdicts", [
    (RESET, 10, 100, 20, 100, 2, (1, "H"), ["holds", "violated", "violated"]),
    (FLIP, 8192, 745472, 100437, 745472, 8192, (2, "H"),
     ["holds", "violated", "holds", "violated", "violated", "violated"]),
    (NOISE, 8192, 745472, 187562, 2 * 745472, 8192, (0, "i"),
     ["holds", "violated", "violated", "holds", "violated", "violated", "violated"]),
    (WIDE, 131072, 2228224, 327696, 2228224, 131072, (0, "i"), ["holds", "violated", "holds"]),
], ids=["shared-lists", "targets-through-table", "nodes-32-bit", "widened"])
def test_layout_same_as_edges(tmp_path, monkeypatch, text, states, transitions, nodes, entries, lists, layout,
                              verdicts):
    path = write(tmp_path, text)
    model = api.load(path)
    run = model.explore(engine="native")
    assert (run.states, run.transitions) == (states, transitions)
    assert run.explorer.edge_src is None                 # recorded: the lists, no edges
    K = run.temporal[0].K
    assert K.n == nodes
    assert K.cls_succ.off[-1] == entries
    assert len({tuple(c) for c in K.cls_succ}) == lists
    assert _layout(K) == layout
    assert [r.verdict for r in run.temporal] == verdicts
    rows = _rows(model, run)
    arrays = _arrays(K)
    # the route through the edges (kn_quotient, 32-bit lists): the same structure and printed rows
    with monkeypatch.context() as mp:
        _old_route(mp)
        old_model = api.load(path)
        old = old_model.explore(engine="native")
        assert old.explorer.edge_src is not None
        assert _layout(old.temporal[0].K) == (0, "i")
        assert _arrays(old.temporal[0].K) == arrays
        assert _rows(old_model, old) == rows
    # E[f U g] by passes over the forward lists (above), by the backward lists, and by one pass
    # finished by the backward lists: the same
    assert getattr(K, "_kernel_rev", None) is None
    for entries, passes in ((1 << 40, 8), (0, 1)):
        monkeypatch.setattr(kernel, "EU_FORWARD_ENTRIES", entries)
        monkeypatch.setattr(kernel, "EU_FORWARD_PASSES", passes)
        again_model = api.load(path)
        again = again_model.explore(engine="native")
        assert _rows(again_model, again) == rows


def _structure(off, adj, cls, key=None, tab=None, nstates=0):
    K = Kripke()
    K.mode = "step"
    K.n = len(cls)
    K.cls = array("i", cls)
    K.cls_succ = Classes(array("i", off), adj, key, tab, nstates)
    K.init = [0]
    return K


# six nodes over three states (classes); node v's class is its target.  Lists: state 0 -> nodes
# 1, 2; state 1 -> 3, 4; state 2 -> 5, 0.  The same lists in the three layouts: 32-bit nodes,
# 16-bit nodes, 16-bit targets through a table (node of (key, target): keys 0 and 1)
OFF = [0, 2, 4, 6]
CLS = [0, 1, 2, 1, 2, 0]
LISTS = [[1, 2], [3, 4], [5, 0]]
TAB = array("i", [-1, 1, 2, 0, 3, 4])       # key 0: targets 1, 2 -> nodes 1, 2; key 1: 0 -> 0, 1 -> 3, 2 -> 4
# state 0's list has key 0 (targets 1, 2); state 1's key 1 (targets 1 -> 3, 2 -> 4); state 2's list
# (5, 0) is not made of one key's targets: given as 32-bit nodes only
LAYOUTS = {
    "32": dict(adj=array("i", [1, 2, 3, 4, 5, 0])),
    "16": dict(adj=array("H", [1, 2, 3, 4, 5, 0])),
}


@needs_cc
@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_kernel_reads_each_layout(name):
    K = _structure(OFF, cls=CLS, **LAYOUTS[name])
    assert [K.succ(v) for v in range(6)] == [LISTS[c] for c in CLS]
    assert K.cls_succ.arrays() == (array("i", OFF), array("i", [1, 2, 3, 4, 5, 0]))
    g = bytearray([0, 0, 0, 0, 1, 0])
    assert kernel.ex(K, g) == bytearray([0, 1, 0, 1, 0, 0])
    f = bytearray([1, 1, 1, 1, 0, 1])
    for entries, passes in ((0, 8), (1 << 40, 8), (0, 1)):
        keep = kernel.EU_FORWARD_ENTRIES, kernel.EU_FORWARD_PASSES
        kernel.EU_FORWARD_ENTRIES, kernel.EU_FORWARD_PASSES = entries, passes
        try:
            K2 = _structure(OFF, cls=CLS, **LAYOUTS[name])
            # 4 is in class 1's list (nodes 1, 3 join), 1 in class 0's (0, 5), 5 in class 2's (2; 4
            # is not an f node but is where the paths end)
            assert kernel.eu(K2, f, g) == bytearray([1, 1, 1, 1, 1, 1])
            assert kernel.eu(K2, bytearray([1, 1, 0, 1, 0, 0]), g) == bytearray([1, 1, 0, 1, 1, 0])
        finally:
            kernel.EU_FORWARD_ENTRIES, kernel.EU_FORWARD_PASSES = keep
    assert kernel.bfs(K, [0], bytearray([0, 0, 0, 0, 1, 0])) == [0, 1, 4]
    assert CTL(K).fair == bytearray(b"\x01" * 6)


@needs_cc
def test_kernel_reads_targets_through_table():
    # two states whose lists are targets with one key each: state 0 (key 0) -> targets 1, 2 = nodes
    # 1, 2; state 1 (key 1) -> targets 1, 2 = nodes 3, 4; state 2 (key 1) -> target 0 = node 0
    K = _structure([0, 2, 4, 5], array("H", [1, 2, 1, 2, 0]), [0, 1, 2, 1, 2], array("i", [0, 1, 1]), TAB, 3)
    assert [list(c) for c in K.cls_succ] == [[1, 2], [3, 4], [0]]
    assert K.cls_succ.arrays() == (array("i", [0, 2, 4, 5]), array("i", [1, 2, 3, 4, 0]))
    assert kernel.ex(K, bytearray([0, 0, 0, 0, 1])) == bytearray([0, 1, 0, 1, 0])
    f = bytearray(b"\x01" * 5)
    for entries, passes in ((0, 8), (1 << 40, 8), (0, 1)):
        keep = kernel.EU_FORWARD_ENTRIES, kernel.EU_FORWARD_PASSES
        kernel.EU_FORWARD_ENTRIES, kernel.EU_FORWARD_PASSES = entries, passes
        try:
            K2 = _structure([0, 2, 4, 5], array("H", [1, 2, 1, 2, 0]), [0, 1, 2, 1, 2], array("i", [0, 1, 1]), TAB, 3)
            # node 4 from nodes of class 1 (1, 3), from those of class 0 (0), from those of class 2 (2, 4)
            assert kernel.eu(K2, f, bytearray([0, 0, 0, 0, 1])) == bytearray([1, 1, 1, 1, 1])
        finally:
            kernel.EU_FORWARD_ENTRIES, kernel.EU_FORWARD_PASSES = keep
    assert kernel.bfs(K, [0], bytearray([0, 0, 0, 0, 1])) == [0, 1, 4]
    # a replaced list (a halt node): the kernel reads 32-bit arrays made from the decoded lists
    K.cls_succ[2] = [0, 4]
    assert K.cls_succ.layout() is None
    assert K.cls_succ.arrays() == (array("i", [0, 2, 4, 6]), array("i", [1, 2, 3, 4, 0, 4]))


# ----------------------------------------------------------------- the memory bound
@needs_cc
def test_memory_bound_counts_the_canonical_forms(tmp_path):
    """A spec that extends a domain: the search's memory count holds the canonical forms' tables
    (the memo of texts, the kept forms), as allocated; a spec without extend has none."""
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.props.load import load_machine
    from test_native_extend import QUEUE
    _, m = load_machine(write(tmp_path, QUEUE))
    ex = NativeExplorer(m)
    ex.run()
    canon = ex.dll.asm_canon_bytes()
    # one search context's tables: more than its fixed part (some 450 KB of location tables)
    assert canon > 400_000
    assert ex.dll.asm_memory_bytes() > canon
    _, m2 = load_machine(write(tmp_path, WIDE))
    ex2 = NativeExplorer(m2)
    ex2.run()
    assert ex2.dll.asm_canon_bytes() == 0


@needs_cc
@pytest.mark.parametrize("down", [False, True], ids=["chain-up", "chain-down"])
@pytest.mark.parametrize("passes", [8, 100_000], ids=["then-backward", "forward-only"])
def test_forward_passes(monkeypatch, down, passes):
    """E[f U start] on a chain of 5,000 nodes, each node's class its successor: passes over the forward
    lists walk the classes from the last, so a chain whose edges go up (v -> v + 1) is done in one
    pass (and one more to see nothing change); a chain going down (v -> v - 1) takes a pass a node,
    and after EU_FORWARD_PASSES of them a backward search from what was found finishes it.  The
    backward lists are made only then."""
    n = 5000
    monkeypatch.setattr(kernel, "EU_FORWARD_PASSES", passes)
    nxt = [max(v - 1, 0) for v in range(n)] if down else [min(v + 1, n - 1) for v in range(n)]
    K = _structure(list(range(n + 1)), array("i", range(n)), nxt)
    f = bytearray(b"\x01") * n
    f[n // 2] = 0
    start = bytearray(n)
    start[0 if down else n - 1] = 1
    y = kernel.eu(K, f, start)
    assert y == bytearray((v < n // 2) if down else (v > n // 2) for v in range(n))
    made = getattr(K, "_kernel_rev", None) is not None
    assert made == (down and passes == 8)


@needs_cc
def test_pairs_coded_then_numbered(tmp_path, monkeypatch):
    """With few atoms that read monitored functions the search records a step's (target, values) pair
    as one code (target << atoms | values), without a table of pairs; a code that does not fit (here
    made to overflow at 2^12, half way through the search) turns the entries recorded so far into pair
    numbers: the same structure, verdicts and paths."""
    from asmcheck.explore.native import NativeExplorer
    path = write(tmp_path, NOISE)
    model = api.load(path)
    run = model.explore(engine="native")
    K = run.temporal[0].K
    assert len(K.mon_atoms) == 3 and run.explorer.qf_direct
    monkeypatch.setattr(NativeExplorer, "QF_DIRECT_BITS", 12)
    model2 = api.load(path)
    run2 = model2.explore(engine="native")
    assert run2.explorer.edge_src is None and not run2.explorer.qf_direct
    assert _arrays(run2.temporal[0].K) == _arrays(K)
    assert _rows(model2, run2) == _rows(model, run)
