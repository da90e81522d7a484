"""The bisimulation quotient of the CTL structure whose nodes are steps (asmcheck.temporal.kripke):
exact node counts on specs written for the test, the same verdicts and the same printed
counterexamples and witnesses as the structure with one node per step (on both engines), and
examples/parking.asm (86 million transitions) with NuSMV's verdicts."""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from asmcheck import api
from asmcheck.explore.native_build import compiler
from asmcheck.report.trace import temporal_text
from asmcheck.temporal import check_temporal
from asmcheck.temporal.formula import Atoms, Builder, atoms_of
from asmcheck.temporal.kripke import build_kripke

from helpers import write

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))
EXAMPLES = SHARED / "asmeta" / "asm_examples"

pytestmark = pytest.mark.engines("both")

needs_cc = pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")

# six states x = 0..5; from each, a step that stays (inc false) and one that counts (5 wraps to
# 0).  The atoms x = 0 and x = 5 read no monitored function: one node per step (12); the
# sources 1..4 have the same labels, so their steps are merged by target: 2 (from 0) + 5 (from
# 1..4, targets 1..5) + 2 (from 5) = 9 nodes
COUNT = """asm Count
import StandardLibrary
import CTLLibrary
signature:
	domain Cnt subsetof Integer
	controlled x: Cnt
	monitored inc: Boolean
definitions:
	domain Cnt = {0 : 5}
	CTLSPEC ag(ef(x = 0))
	CTLSPEC ef(x = 5)
	CTLSPEC ag(x = 0 implies ax(x = 0))
	CTLSPEC eg(not(x = 5))
	CTLSPEC ag(ef(x = 5 and ex(x = 0)))
	CTLSPEC af(x = 5)
	CTLSPEC ex(ex(ex(x = 5)))
	CTLSPEC ef(x = 5 and ex(x = 5))
	main rule r_main =
		if inc then
			if x < 5 then x := x + 1 else x := 0 endif
		endif
default init s0:
	function x = 0
"""

# the same counter with a second input, noise, that the rule does not read but an atom does:
# every step comes with both values (24 nodes); merged by (labels of the source, noise, target):
# 4 (from 0) + 10 (from 1..4: targets 1..5, both values) + 4 (from 5) = 18.  Its LTL properties read
# noise too: their structure is the same quotient
NOISE = COUNT.replace("asm Count", "asm Noise").replace(
    "\tmonitored inc: Boolean\n", "\tmonitored inc: Boolean\n\tmonitored noise: Boolean\n").replace(
    "\tCTLSPEC ag(ef(x = 0))\n", "\tCTLSPEC ag(ef(x = 0 and noise))\n\tCTLSPEC ag(noise implies ax(not(x = 5)))\n"
    "\tCTLSPEC ef(x = 5 and not noise and ex(x = 0 and noise))\n"
    "\tLTLSPEC g(noise implies x(not(x = 5)))\n\tLTLSPEC g(f(x = 0 and noise))\n").replace(
    "import CTLLibrary\n", "import CTLLibrary\nimport LTLLibrary\n")

# fairness as a label: JUSTICE x = 5 (every fair path counts to 5 again and again)
FAIR = COUNT.replace("asm Count", "asm FairCount").replace(
    "\tCTLSPEC ag(ef(x = 0))\n", "\tJUSTICE x = 5\n\tCTLSPEC ag(ef(x = 0))\n\tCTLSPEC af(x = 5)\n")


# an INVAR that reads the monitored input: the steps from 5 with noise are no nodes
INVAR = NOISE.replace("asm Noise", "asm InvarNoise").replace(
    "\tCTLSPEC ag(ef(x = 0 and noise))\n", "\tINVAR not(x = 5 and noise)\n\tCTLSPEC ag(ef(x = 0 and noise))\n")

# a step that fails (5 counts to 6, outside Cnt): the paths through it end in a halt node
HALT = COUNT.replace("asm Count", "asm HaltCount").replace("else x := 0 endif", "else x := x + 1 endif")


def structure(path: str, engine: str, quotient: bool):
    run = api.load(path).explore(engine=engine)
    assert run.result.engine == engine
    ex = run.explorer
    m = ex.m
    atoms = Atoms(m)
    builder = Builder(m, atoms, ex.state(0))
    used: set = set()
    for p in api.load(path).temporal:
        atoms_of(builder.build(p.body, p.kind), used)
    return build_kripke(ex, atoms, used, [], [], [], [], step=True, quotient=quotient)


def printed(path: str, engine: str, quotient: bool, fair=()):
    """(name, verdict, printed lines with the replayed path, Kripke nodes) of every property."""
    model = api.load(path)
    run = model.explore(engine=engine)
    assert run.result.engine == engine
    results = check_temporal(run.explorer, model.temporal, fair=list(fair), quotient=quotient)
    return [(r.name, r.verdict, temporal_text(r, model.machine), r.stats.get("kripke_nodes")) for r in results]


ENGINES = [pytest.param("native", marks=needs_cc), "python"]


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("text,unmerged,merged", [(COUNT, 12, 9), (NOISE, 24, 18)], ids=["count", "noise"])
def test_node_counts(tmp_path, engine, text, unmerged, merged):
    path = write(tmp_path, text)
    K1 = structure(path, engine, False)
    K2 = structure(path, engine, True)
    assert (K1.mode, K2.mode) == ("step", "step")
    assert (K1.n, K2.n) == (unmerged, merged)
    # every node of the quotient stands for steps to one target from sources with its labels
    assert sorted(set(K2.tgt)) == list(range(6))
    # the initial nodes: the steps from the initial state (x = 0), merged with nothing
    assert [(K2.sid[v], K2.tgt[v]) for v in K2.init] == [(K1.sid[v], K1.tgt[v]) for v in K1.init]
    assert len(K2.init) == (2 if text is COUNT else 4)


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("text", [COUNT, NOISE, FAIR, INVAR], ids=["count", "noise", "justice", "invar"])
def test_same_verdicts_and_paths(tmp_path, engine, text):
    path = write(tmp_path, text)
    merged = printed(path, engine, True)
    unmerged = printed(path, engine, False)
    assert [row[:3] for row in merged] == [row[:3] for row in unmerged]
    assert all(m[3] < u[3] for m, u in zip(merged, unmerged))
    verdicts = [row[1] for row in merged]
    if text is COUNT:
        assert verdicts == ["holds", "holds", "violated", "holds", "holds", "violated", "violated", "holds"]
    # a counterexample that is printed: ag(x = 0 implies ax(x = 0)) at the count from 0 to 1
    row = next(r for r in merged if r[0] == "ctl_3") if text is COUNT else None
    if row is not None:
        text_lines = "\n".join(row[2])
        assert "x = 1" in text_lines


def test_halt_nodes(tmp_path):
    """A step that fails (the Python engine explores around it): the halt node stays as it is, and
    the verdicts (relative to the error) and paths are those of one node per step."""
    path = write(tmp_path, HALT)
    merged = printed(path, "python", True)
    unmerged = printed(path, "python", False)
    assert [row[:3] for row in merged] == [row[:3] for row in unmerged]
    assert [row[1] for row in merged] == ["violated", "holds", "violated", "holds", "violated", "violated",
                                          "violated", "holds"]
    # 8 nodes of steps (from 5 only the step that stays is well defined) and one halt node; 11 + 1 unmerged
    assert (merged[0][3], unmerged[0][3]) == (9, 12)
    assert "relative to the run-time error" in merged[0][2][0]


def test_both_engines_agree(tmp_path):
    if compiler() is None:
        pytest.skip("no C compiler: the native engine is not built")
    path = write(tmp_path, NOISE)
    assert printed(path, "native", True) == printed(path, "python", True)


def test_agent_fairness_keeps_one_node_per_step(tmp_path):
    """With --fair the weak-fairness labels read the move of each step (source and target):
    nodes are not merged."""
    path = write(tmp_path, COUNT)
    rows = printed(path, "python", True, fair=["all"])
    assert {r[3] for r in rows} == {12}


@needs_cc
@pytest.mark.engines("native")
def test_corpus_swapboard_same_paths():
    p = EXAMPLES / "examples" / "swapBoard.asm"
    if not p.exists():
        pytest.skip(f"the ASMETA corpus is not in {SHARED} (ASMCHECK_SHARED)")
    merged = printed(str(p), "native", True)
    unmerged = printed(str(p), "native", False)
    assert [row[:3] for row in merged] == [row[:3] for row in unmerged]
    assert [row[1] for row in merged] == ["holds", "holds", "holds"]


@needs_cc
@pytest.mark.engines("native")      # (it names the native engine: once, not on each)
def test_parking_ctl():
    """examples/parking.asm: 32,768 states, 86,093,442 transitions; NuSMV: true, true, false.  The
    counterexample of the third: a car parks in (1, 3), then one in (1, 4)."""
    p = EXAMPLES / "examples" / "parking.asm"
    if not p.exists():
        pytest.skip(f"the ASMETA corpus is not in {SHARED} (ASMCHECK_SHARED)")
    model = api.load(str(p))
    run = model.explore(engine="native")
    assert (run.states, run.transitions) == (32768, 86093442)
    rows = [(r.name, r.verdict) for r in run.temporal]
    assert rows == [("ctl_1", "holds"), ("ctl_2", "holds"), ("ctl_3", "violated")]
    # the search recorded each state's distinct targets, not the 86 M edges: 98,320 nodes; and
    # only what the properties read (temporal/need.py: three whole properties, the lists of the
    # state where every place is free for eg, the first entry of every other): 19 nodes (every
    # list, 98,320 nodes, with the same report: test_edge_need_ef.py)
    assert run.explorer.edge_src is None
    assert {r.stats["kripke_nodes"] for r in run.temporal} == {19}
    bad = run.temporal[2]
    trace, loop, _ = bad.trace()
    # the shortest counterexample: from the first step that parks a car (not from the initial node
    # whose step leaves the state as it is)
    assert loop is None and len(trace.steps) == 3
    last = "\n".join(temporal_text(bad, model.machine))
    assert "step 1: r_Main chooses $r = 1, $c = 3; reads newCar = true" in last
    assert "step 2: r_Main chooses $r = 1, $c = 4, $p = 11; reads newCar = true" in last


@pytest.mark.parametrize("compiled", [pytest.param(True, marks=needs_cc), False], ids=["compiled", "python"])
def test_quotient_arrays(monkeypatch, compiled):
    """kernel.quotient on steps given out of source order and in order, a step recorded twice, two
    sources with the same signature (states 1 and 2) and atom values that keep steps apart."""
    from array import array
    from asmcheck.temporal import kernel
    monkeypatch.setattr(kernel, "ENABLED", compiled)
    sig = array("Q", [1, 0, 0])
    ok = bytearray(b"\x01\x01\x01")
    # out of order: nodes 1 and 4 are the same step (0 -> 1); 3 and 5 merge (sources 2 and 1)
    first, off, adj = kernel.quotient(3, array("I", [1, 0, 0, 2, 0, 1]), array("I", [2, 1, 2, 0, 1, 0]), None, sig, ok)
    assert (list(first), list(off), list(adj)) == ([0, 1, 2, 3], [0, 2, 4, 5], [1, 2, 0, 3, 3])
    # in order
    first, off, adj = kernel.quotient(3, array("I", [0, 0, 0, 1, 1, 2]), array("I", [1, 2, 1, 2, 0, 0]), None, sig, ok)
    assert (list(first), list(off), list(adj)) == ([0, 1, 3, 4], [0, 2, 4, 5], [0, 1, 2, 3, 3])
    # atom values: the steps 1 -> 0 and 2 -> 0 differ in them, state 2 is left out
    vec = array("B", [0, 0, 0, 1, 0, 0])
    first, off, adj = kernel.quotient(3, array("I", [0, 0, 0, 1, 1, 2]), array("I", [1, 2, 1, 2, 0, 0]), vec, sig,
                                      bytearray(b"\x01\x01\x00"))
    assert (list(first), list(off), list(adj)) == ([0, 1, 3, 4], [0, 2, 4, 4], [0, 1, 2, 3])
    vec = array("B", [0, 0, 0, 0, 1, 0])
    first, off, adj = kernel.quotient(3, array("I", [0, 0, 0, 1, 1, 2]), array("I", [1, 2, 1, 2, 0, 0]), vec, sig, ok)
    assert (list(first), list(off), list(adj)) == ([0, 1, 3, 4, 5], [0, 2, 4, 5], [0, 1, 2, 3, 4])


def test_without_compiled_kernel(tmp_path, monkeypatch):
    """The Python code of the quotient, the fixpoints and the paths gives what the compiled
    kernel gives."""
    from asmcheck.temporal import kernel
    path = write(tmp_path, NOISE)
    with_kernel = printed(path, "python", True)
    monkeypatch.setattr(kernel, "ENABLED", False)
    assert printed(path, "python", True) == with_kernel
    assert printed(path, "python", False) == [row[:3] + (24,) for row in with_kernel]


@needs_cc
def test_quotient_by_source_arrays():
    """The quotient of steps handed over source by source: the lists of kernel.quotient, and the
    source, target and bits of each node's first step; steps without the bits of ``need`` left out."""
    from array import array
    from asmcheck.temporal import kernel
    sig = array("Q", [1, 0, 0])
    src, dst, vec = [0, 0, 0, 1, 1, 2], [1, 2, 1, 2, 0, 0], [0, 0, 0, 1, 1, 1]
    by_source = [(s, sum(1 for x in src if x == s),
                  array("q", [y for i, x in enumerate(src) if x == s for y in (dst[i], vec[i])])) for s in range(3)]
    fsrc, fdst, fvec, off, adj = kernel.quotient_by_source(3, sig, iter(by_source))
    first, off2, adj2 = kernel.quotient(3, array("I", src), array("I", dst), array("B", vec), sig,
                                        bytearray(b"\x01\x01\x01"))
    assert (list(off), list(adj)) == (list(off2), list(adj2)) == ([0, 2, 4, 5], [0, 1, 2, 3, 3])
    assert [(fsrc[q], fdst[q], fvec[q]) for q in range(len(fsrc))] == [(src[i], dst[i], vec[i]) for i in first]
    fsrc, fdst, fvec, off, adj = kernel.quotient_by_source(3, sig, iter(by_source), need=1)
    assert (list(fsrc), list(fdst), list(off), list(adj)) == ([1, 1], [2, 0], [0, 0, 2, 3], [0, 1, 1])


@pytest.mark.parametrize("n", [1000, 70_000], ids=["16-bit classes", "32-bit classes"])
@pytest.mark.parametrize("compiled", [pytest.param(True, marks=needs_cc), False], ids=["compiled", "python"])
def test_backward_search_sizes(monkeypatch, n, compiled):
    """E[f U start] over a chain 0 -> 1 -> ... -> n-1 (which loops): the backward lists keep the
    classes in 16 bits below 65,536 classes, in 32 above."""
    from array import array
    from asmcheck.temporal import kernel
    from asmcheck.temporal.classes import Classes
    from asmcheck.temporal.ctl import CTL
    from asmcheck.temporal.kripke import Kripke
    monkeypatch.setattr(kernel, "ENABLED", compiled)
    monkeypatch.setattr(kernel, "EU_FORWARD_ENTRIES", 1 << 40)       # the backward lists at once
    K = Kripke()
    K.mode = "step"
    K.n = n
    K.cls = array("i", [min(v + 1, n - 1) for v in range(n)])      # node v's successors: class v + 1
    K.cls_succ = Classes(array("i", range(n + 1)), array("i", range(n)))
    K.init = [0]
    K.label = {0: bytearray(b"\x01") * n}
    K.label[0][n // 2] = 0
    start = bytearray(n)
    start[n - 1] = 1
    ctl = CTL(K)
    y = ctl._eu(K.label[0], start)
    assert y == bytearray(v > n // 2 for v in range(n))
    if compiled:
        assert K._kernel_rev[1].typecode == ("H" if n < 65536 else "i")


# ----------------------------------------------------------------- the steps recorded by the search
# With LTL/CTL whose structure is the quotient of the steps (no --graph, no --fair), the native search
# records each state's distinct (target, values of the atoms that read monitored functions) pairs as
# it expands the state, instead of the edges, and the quotient is merged from them: no edge array, no
# step run again.  It must give the structure, verdicts and paths of the edges' route.

def _old_route(monkeypatch):
    """Explorations that record the edges (the route before the steps were recorded)."""
    monkeypatch.setattr(api, "_quotient_plan", lambda *a: None)


def structure_arrays(K):
    """The arrays of the Kripke structure K, to compare two structures (test_native_qf_handover.py too)."""
    return (K.n, list(K.sid), list(K.tgt), list(K.vec), [list(c) for c in K.cls_succ], list(K.init),
            {i: bytes(lab) for i, lab in K.label.items()})


def temporal_rows(model, run):
    """Each temporal row of ``run``: name, verdict, its text and the structure's nodes."""
    return [(r.name, r.verdict, temporal_text(r, model.machine), r.stats.get("kripke_nodes")) for r in run.temporal]


@needs_cc
@pytest.mark.parametrize("text,nodes", [(COUNT, 9), (NOISE, 18), (INVAR, 16)], ids=["count", "noise", "invar"])
def test_recorded_steps_structure(tmp_path, monkeypatch, text, nodes):
    path = write(tmp_path, text)
    model = api.load(path)
    run = model.explore(engine="native")
    assert run.explorer.edge_src is None            # recorded: the pairs, no edges
    K = run.temporal[0].K
    assert K.n == nodes and {r.stats["kripke_nodes"] for r in run.temporal} == {nodes}
    rows = temporal_rows(model, run)
    with monkeypatch.context() as mp:
        _old_route(mp)
        old_model = api.load(path)
        old = old_model.explore(engine="native")
        assert old.explorer.edge_src is not None
        assert structure_arrays(old.temporal[0].K) == structure_arrays(K)
        assert temporal_rows(old_model, old) == rows
    py_model = api.load(path)
    assert temporal_rows(py_model, py_model.explore(engine="python")) == rows


@needs_cc
@pytest.mark.parametrize("text", [COUNT, NOISE, INVAR], ids=["count", "noise", "invar"])
def test_recorded_steps_merged_by_hashing(tmp_path, monkeypatch, text):
    """The nodes merged through the hash table (a spec with many keys and states) are those of the
    table with a row of states per key (small ones)."""
    from asmcheck.explore.native import NativeExplorer
    path = write(tmp_path, text)
    model = api.load(path)
    run = model.explore(engine="native")
    monkeypatch.setattr(NativeExplorer, "QF_TABLE", 0)
    model2 = api.load(path)
    run2 = model2.explore(engine="native")
    assert run2.explorer.edge_src is None
    assert structure_arrays(run2.temporal[0].K) == structure_arrays(run.temporal[0].K)
    assert temporal_rows(model2, run2) == temporal_rows(model, run)


@needs_cc
def test_recorded_steps_consumed_once(tmp_path):
    """The pairs are handed over once, merged; the structure of a second check (LTL and CTL both in
    step mode) comes from the same merge, and a check that needs the edges (one node per step) has
    the search run again, recording them: the same states, the same verdicts and paths."""
    path = write(tmp_path, NOISE)
    model = api.load(path)
    run = model.explore(engine="native")
    ex = run.explorer
    assert ex.edge_src is None and not ex.qf           # consumed by the run's own checks
    assert {r.stats["kripke_nodes"] for r in run.temporal} == {18}
    merged = [(r.name, r.verdict, temporal_text(r, model.machine)) for r in run.temporal]
    unmerged = check_temporal(ex, model.temporal, quotient=False)
    assert ex.edge_src is not None and len(ex.edge_src) == run.transitions
    assert [(r.name, r.verdict, temporal_text(r, model.machine)) for r in unmerged] == merged
    assert {r.stats["kripke_nodes"] for r in unmerged} == {24}


@needs_cc
def test_recorded_steps_past_a_failing_step(tmp_path, monkeypatch):
    """A step that fails where an atom reads a monitored function: the search records the pairs of
    the state's well-defined steps (a failing branch is no edge) and the structure, verdicts
    (relative to the error) and paths are those of the route that runs the steps again in Python,
    and of the Python engine."""
    text = NOISE.replace("asm Noise", "asm HaltNoise").replace("else x := 0 endif", "else x := x + 1 endif")
    path = write(tmp_path, text)
    model = api.load(path)
    run = model.explore(engine="native")
    assert run.explorer.edge_src is None                # recorded, not searched again
    rows = temporal_rows(model, run)
    assert any("relative to the run-time error" in r[2][0] for r in rows)
    assert {r[3] for r in rows} == {18}
    with monkeypatch.context() as mp:
        _old_route(mp)
        old_model = api.load(path)
        old = old_model.explore(engine="native")
        assert old.explorer.edge_src is not None
        assert structure_arrays(old.temporal[0].K) == structure_arrays(run.temporal[0].K)
        assert temporal_rows(old_model, old) == rows
    py_model = api.load(path)
    assert temporal_rows(py_model, py_model.explore(engine="python")) == rows


def test_quotient_plan(tmp_path):
    """Which checks the search can record the steps for: the atoms that read monitored functions, in
    build_kripke's order; none with --fair, --graph or LTL on the state graph."""
    from asmcheck.temporal import quotient_plan
    from asmcheck.temporal.formula import span_text
    model = api.load(write(tmp_path, NOISE))
    st = model.explore(engine="python").explorer.state(0)
    atoms = quotient_plan(model.machine, model.temporal)(st)
    # (one atom per occurrence in a formula: the LTL ones and the CTL ones are apart)
    assert [span_text(t.span) for t, env in atoms] == ["x = 0 and noise", "noise", "x = 5 and not noise",
                                                       "x = 0 and noise", "noise", "x = 0 and noise"]
    assert not quotient_plan(model.machine, model.temporal).edges_too
    # --fair and --graph read the edges too: the atoms' values are recorded beside them
    for opts in ({"fair": ["all"]}, {"graph": True}):
        plan = quotient_plan(model.machine, model.temporal, **opts)
        assert plan.edges_too and plan(st) == atoms
    # LTL without such atoms: the state graph itself (the edges)
    ltl = write(tmp_path, COUNT.replace("asm Count", "asm LtlCount").replace(
        "import CTLLibrary\n", "import CTLLibrary\nimport LTLLibrary\n").replace(
        "\tCTLSPEC ag(ef(x = 0))\n", "\tLTLSPEC g(f(x = 0))\n\tCTLSPEC ag(ef(x = 0))\n"))
    m2 = api.load(ltl)
    assert quotient_plan(m2.machine, m2.temporal)(st) is None
    m3 = api.load(write(tmp_path, COUNT))
    assert quotient_plan(m3.machine, m3.temporal)(st) == []
    # without such atoms the edges alone serve --graph
    assert quotient_plan(m3.machine, m3.temporal, graph=True)(st) is None


@needs_cc
@pytest.mark.parametrize("opts", [{"fair": ["all"]}, {"graph": True}], ids=["fair", "graph"])
def test_recorded_steps_beside_the_edges(tmp_path, monkeypatch, opts):
    """--fair (one node per step) and --graph read the edges: the search records them, and the
    atoms' values in each step beside them (the structure's steps come from those, no step runs
    again): the same structure, verdicts and paths as the route that runs the steps again."""
    from asmcheck.explore.native import NativeExplorer
    path = write(tmp_path, NOISE)
    model = api.load(path)
    with monkeypatch.context() as mp:
        # no step runs again for the atoms' values
        mp.setattr(NativeExplorer, "step_atoms_each", lambda *a: pytest.fail("the steps ran again"))
        run = model.explore(engine="native", **opts)
    ex = run.explorer
    assert ex.edge_src is not None and len(ex.edge_src) == run.transitions
    assert ex._qf_edges_too
    rows = temporal_rows(model, run)
    assert {r[3] for r in rows} == {24 if "fair" in opts else 18}
    with monkeypatch.context() as mp:
        _old_route(mp)
        old_model = api.load(path)
        old = old_model.explore(engine="native", **opts)
        assert not old.explorer._qf_edges_too
        assert structure_arrays(old.temporal[0].K) == structure_arrays(run.temporal[0].K)
        assert temporal_rows(old_model, old) == rows
    py_model = api.load(path)
    assert temporal_rows(py_model, py_model.explore(engine="python", **opts)) == rows
