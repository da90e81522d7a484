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
def test_corpus_swapboard_same_paths():
    p = EXAMPLES / "examples" / "swapBoard.asm"
    if not p.exists():
        pytest.skip(f"the ASMETA corpus is not in {SHARED} (ASMCHECK_SHARED)")
    merged = printed(str(p), "native", True)
    unmerged = printed(str(p), "native", False)
    assert [row[:3] for row in merged] == [row[:3] for row in unmerged]
    assert [row[1] for row in merged] == ["holds", "holds", "holds"]


@needs_cc
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
    bad = run.temporal[2]
    trace, loop, _ = bad.trace()
    assert loop is None and len(trace.steps) == 4
    last = "\n".join(temporal_text(bad, model.machine))
    assert "step 2: r_Main chooses $r = 1, $c = 3; reads newCar = true" in last
    assert "step 3: r_Main chooses $r = 1, $c = 4, $p = 11; reads newCar = true" in last


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
