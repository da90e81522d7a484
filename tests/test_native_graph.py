"""The state graph on the native engine: ``explore --graph`` (DOT and GraphML) written from the
native search's edge arrays is byte for byte the Python engine's file; the Kripke structures the
LTL/CTL checks build from the native explorer (kept as arrays) have the same nodes, successors,
labels and initial nodes as those built from the Python explorer; verdicts and lasso traces are
equal.  Engines pinned: native, compared with python."""
from __future__ import annotations

import json
import os
from array import array
from pathlib import Path

import pytest

from asmcheck import api
from asmcheck.cli import main
from asmcheck.explore.native_build import compiler
from asmcheck.temporal import kernel
from asmcheck.temporal.formula import Atoms, Builder, atoms_of
from asmcheck.temporal.kripke import Classes, Vectors, build_kripke

from helpers import both, engine_free, write

ROOT = Path(__file__).resolve().parent.parent
SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))
EXAMPLES = SHARED / "asmeta" / "asm_examples"

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")]

# two monitored inputs and a choose: several steps lead from one state to the same successor
# (their edges are apart in the graph, each with its own label)
LIGHTS = """asm Lights
import StandardLibrary
import CTLLibrary
import LTLLibrary
signature:
	enum domain Col = {RED | GREEN | BLUE}
	domain Cnt subsetof Integer
	controlled light: Col
	controlled n: Cnt
	monitored go: Boolean
	monitored fast: Boolean
definitions:
	domain Cnt = {0 : 3}
	CTLSPEC ag(ef(light = RED))
	CTLSPEC ef(go and light = BLUE)
	LTLSPEC g(f(n = 0))
	LTLSPEC g(light = RED implies x(light != BLUE))
	main rule r_main =
		if go then
			choose $c in Col with $c != light do
				par
					light := $c
					if n < 3 then n := n + 1 else n := 0 endif
				endpar
		else
			if fast then n := 0 else skip endif
		endif
default init s0:
	function light = RED
	function n = 0
"""

# elements made by extend: the graph's states name them as the canonical form does
QUEUE = """asm Queue
import StandardLibrary
signature:
	dynamic abstract domain Job
	enum domain Phase = {IDLE | RUN | DONE}
	controlled phase: Job -> Phase
	controlled queue: Seq(Job)
	controlled made: Integer
definitions:
	main rule r_main =
		par
			if made < 2 then
				extend Job with $j do
					par
						phase($j) := IDLE
						queue := append(queue, $j)
						made := made + 1
					endpar
			endif
			if made >= 2 and length(queue) > 0 then
				let ($x = first(queue)) in
					if phase($x) = IDLE then phase($x) := RUN
					else
						par
							phase($x) := DONE
							queue := excluding(queue, $x)
						endpar
					endif
				endlet
			endif
		endpar
default init s0:
	function queue = []
	function made = 0
"""

# INVAR constraints over monitored functions: the steps they exclude are in neither graph
INVAR_MON = """asm InvarMon
import StandardLibrary
import CTLLibrary
import LTLLibrary
signature:
	enum domain Cmd = {GO | STOP | WAIT}
	monitored cmd: Cmd
	monitored urgent: Boolean
	controlled n: Integer
	controlled last: Cmd
definitions:
	INVAR not (n >= 2 and cmd = GO)
	CTLSPEC ag(n <= 4)
	LTLSPEC f(last = STOP)
	main rule r_main =
		if n < 4 then
			par
				last := cmd
				if urgent then n := n + 2 else n := n + 1 endif
			endpar
		endif
default init s0:
	function n = 0
	function last = GO
"""

# a violated invariant: the counterexample's states and steps are drawn red in both files
BAD = """asm Bad
import StandardLibrary
signature:
	domain Lvl subsetof Integer
	controlled x: Lvl
	monitored up: Boolean
definitions:
	domain Lvl = {0 : 3}
	invariant inv_low over x: x < 3
	main rule r_main = if up and x < 3 then x := x + 1 else x := 0 endif
default init s0:
	function x = 0
"""


def graphs(path: str, tmp_path: Path, capsys, *extra) -> dict:
    """engine -> (the JSON report's engine, the DOT file, the GraphML file)."""
    out = {}
    for engine in ("native", "python"):
        files = []
        for suffix in ("dot", "graphml"):
            g = tmp_path / f"{engine}.{suffix}"
            main(["explore", path, "--format", "json", "--engine", engine, "--graph", str(g), *extra])
            rep = json.loads(capsys.readouterr().out)
            files.append(g.read_bytes())
        out[engine] = (rep["engine"], *files)
    return out


@pytest.mark.parametrize("text", [LIGHTS, QUEUE, INVAR_MON, BAD], ids=["lights", "queue", "invar", "bad"])
def test_graph_files_equal(tmp_path, capsys, text):
    g = graphs(write(tmp_path, text), tmp_path, capsys)
    assert g["native"][0] == "native"
    assert g["python"][0] == "python"
    assert g["native"][1] == g["python"][1]
    assert g["native"][2] == g["python"][2]


def test_graph_keeps_every_step(tmp_path, capsys):
    """Lights: from the initial state, go = false gives two steps to the same state (fast true or
    false) and go = true two more per colour; the native edges hold each pair once, the graph each
    step."""
    path = write(tmp_path, LIGHTS)
    run = api.load(path).explore(engine="native", graph=True)
    ex = run.explorer
    assert ex.engine == "native"
    src, dst = ex.edge_arrays()
    assert src.typecode == dst.typecode == "I"
    steps = ex.graph_edges()
    pairs = sorted(set(zip(src.tolist(), dst.tolist())))
    assert sorted({(a, b) for a, b, _ in steps}) == pairs
    assert len(steps) > len(pairs)
    first = [(b, p) for a, b, p in steps if a == 0]
    # go = false: fast = true (n := 0) and fast = false (skip) stay; go = true: GREEN, BLUE
    assert [b for b, _ in first] == [0, 0, 1, 2]
    assert len(set(p for _, p in first)) == 4
    py = api.load(path).explore(engine="python", graph=True).explorer
    assert [(a, b, tuple(p)) for a, b, p in py.edges] == [(a, b, tuple(p)) for a, b, p in steps]
    assert list(py.depth_of) == list(ex.depth_of)


def test_graph_text(tmp_path, capsys):
    """The DOT file of BAD, in full (the labels the trace renderer gives the steps)."""
    path = write(tmp_path, BAD)
    out = tmp_path / "bad.dot"
    main(["explore", path, "--engine", "native", "--graph", str(out)])
    capsys.readouterr()
    assert out.read_text().splitlines() == [
        "digraph states {",
        "  node [shape=box, fontname=monospace];",
        '  s0 [label="x = 0\\l", penwidth=2, color=red, fontcolor=red];',
        '  s1 [label="x = 1\\l", color=red, fontcolor=red];',
        '  s2 [label="x = 2\\l", color=red, fontcolor=red];',
        '  s3 [label="x = 3\\l", color=red, fontcolor=red];',
        '  s0 -> s0 [label="r_main; reads up = false"];',
        '  s0 -> s1 [label="r_main; reads up = true", color=red, fontcolor=red, penwidth=2];',
        '  s1 -> s0 [label="r_main; reads up = false"];',
        '  s1 -> s2 [label="r_main; reads up = true", color=red, fontcolor=red, penwidth=2];',
        '  s2 -> s0 [label="r_main; reads up = false"];',
        '  s2 -> s3 [label="r_main; reads up = true", color=red, fontcolor=red, penwidth=2];',
        '  s3 -> s0 [label="r_main; reads up = false"];',
        '  s3 -> s0 [label="r_main; reads up = true"];',
        "}",
    ]


def test_graph_of_stopped_search_falls_back(tmp_path, capsys):
    """A search cut by --max-states: the Python engine writes the graph, and says why."""
    path = write(tmp_path, LIGHTS)
    run = api.load(path).explore(engine="auto", graph=True, max_states=3)
    assert run.result.engine == "python"
    assert "stopped before its end" in run.result.native_refused


@pytest.mark.parametrize("name", ["producer_consumer.asm", "temporal/counter.asm", "temporal/peterson.asm"])
def test_graph_repository_specs(tmp_path, capsys, name):
    g = graphs(str(ROOT / "specs" / name), tmp_path, capsys)
    assert g["native"][0] == "native"
    assert g["native"][1:] == g["python"][1:]


# m2.asm: two functions named f (its own and its module's), printed in the order of the functions
CORPUS = ["examples/darts.asm", "examples/slotMachine.asm", "examples/cards.asm", "stereoacuity/certifierRaff1.asm",
          "stereoacuity/certifierRaff4.asm", "test/simulator/domains/test04/m2.asm",
          "examples/filosofiEciliegie/filosofiEciliegieAgentsJustLeft.asm"]


@pytest.mark.parametrize("rel", CORPUS)
def test_graph_corpus_specs(tmp_path, capsys, rel):
    if not (EXAMPLES / rel).exists():
        pytest.skip(f"the ASMETA corpus is not in {SHARED} (ASMCHECK_SHARED)")
    g = graphs(str(EXAMPLES / rel), tmp_path, capsys)
    assert g["native"][0] == "native"
    assert g["native"][1:] == g["python"][1:]


# ----------------------------------------------------------------- the temporal structures
def structures(path: str, step: bool):
    """engine -> the Kripke structure of the spec's LTL/CTL properties (``step``: CTL's)."""
    out = {}
    for engine in ("native", "python"):
        model = api.load(path)
        run = model.explore(engine=engine)
        ex = run.explorer
        assert run.result.engine == engine
        m = ex.m
        atoms = Atoms(m)
        builder = Builder(m, atoms, ex.state(0))
        used: set = set()
        for p in model.temporal:
            if p.kind in ("ltl", "ctl"):
                atoms_of(builder.build(p.body, p.kind), used)
        invars = [atoms.add(p.body, {}) for p in m.spec.properties if p.kind == "invar"]
        out[engine] = build_kripke(ex, atoms, used, invars, [], [], [], step=step)
    return out


def shape(K) -> dict:
    return {"mode": K.mode, "n": K.n, "sid": list(K.sid), "tgt": None if K.tgt is None else list(K.tgt),
            "vec": None if K.vec is None else list(K.vec), "init": list(K.init),
            "succ": [K.succ(v) for v in range(K.n)], "labels": {i: bytes(b) for i, b in K.label.items()}}


@pytest.mark.parametrize("text,step,mode", [(LIGHTS, True, "step"), (LIGHTS, False, "step"), (QUEUE, False, "state"),
                                            (INVAR_MON, True, "step")],
                         ids=["lights-ctl", "lights-ltl", "queue-ltl", "invar-ctl"])
def test_kripke_equal(tmp_path, text, step, mode):
    if "LTLSPEC" not in text:
        text = text.replace("import StandardLibrary\n", "import StandardLibrary\nimport LTLLibrary\n")
        text = text.replace("definitions:\n", "definitions:\n\tLTLSPEC g(f(made = 2))\n")
    path = write(tmp_path, text)
    ks = structures(path, step)
    nat, py = shape(ks["native"]), shape(ks["python"])
    assert nat["mode"] == mode
    assert nat == py
    assert isinstance(ks["native"].cls_succ, Classes)
    if mode == "step":
        assert isinstance(ks["native"].sid, array) and isinstance(ks["native"].vec, Vectors)


def test_kripke_numbers(tmp_path):
    """Lights, CTL: 12 states; a node per (source, target, value of the atom that reads a monitored
    function, ``go and light = BLUE``), 45 of them; from the initial state: go = false (two steps,
    one node: both stay), go = true to GREEN and to BLUE (the atom false: the light is red)."""
    ks = structures(write(tmp_path, LIGHTS), True)
    K = ks["native"]
    assert (K.n, len(set(K.sid)), K.init, K.mode) == (45, 12, [0, 1, 2], "step")
    assert [(K.sid[v], K.tgt[v], K.vec[v]) for v in K.init] == [(0, 0, (False,)), (0, 1, (False,)), (0, 2, (False,))]
    assert (ks["python"].n, ks["python"].init) == (45, [0, 1, 2])


@pytest.mark.parametrize("text", [LIGHTS, INVAR_MON, BAD], ids=["lights", "invar", "bad"])
def test_verdicts_and_traces_equal(tmp_path, capsys, text):
    code, rep = both(tmp_path, capsys, text)
    kinds = {p["kind"] for p in rep["properties"]}
    assert kinds & {"ltl", "ctl", "invariant"}


@pytest.mark.parametrize("name,extra", [("temporal/peterson.asm", ["--properties", "specs/temporal/peterson_fair.prop"]),
                                        ("temporal/grid.asm", ["--properties", "specs/temporal/grid_fair.prop"]),
                                        ("temporal/request_ack.asm", []), ("temporal/spinlock.asm", [])])
def test_temporal_repository_specs(capsys, name, extra):
    """The temporal example specs (fairness, lassos): the JSON reports are equal."""
    reps = []
    for engine in ("native", "python"):
        main(["explore", str(ROOT / "specs" / name), "--format", "json", "--engine", engine,
              *[str(ROOT / x) if x.endswith(".prop") else x for x in extra]])
        reps.append(engine_free(json.loads(capsys.readouterr().out), engine))
    assert reps[0] == reps[1]
    assert any(p["kind"] in ("ltl", "ctl") for p in reps[0]["properties"])


@pytest.mark.parametrize("rel", ["examples/cards.asm", "examples/slotMachine.asm", "stereoacuity/certifierRaff4.asm"])
def test_temporal_corpus_specs(capsys, rel):
    if not (EXAMPLES / rel).exists():
        pytest.skip(f"the ASMETA corpus is not in {SHARED} (ASMCHECK_SHARED)")
    reps = []
    for engine in ("native", "python"):
        main(["explore", str(EXAMPLES / rel), "--format", "json", "--engine", engine])
        reps.append(engine_free(json.loads(capsys.readouterr().out), engine))
    assert reps[0] == reps[1]


# ----------------------------------------------------------------- the array helpers
@pytest.mark.parametrize("compiled", [True, False])
def test_kernel_arrays(compiled, monkeypatch):
    monkeypatch.setattr(kernel, "ENABLED", compiled)
    src = array("I", [0, 0, 0, 1, 2, 2, 3])
    dst = array("I", [2, 1, 2, 0, 3, 1, 3])
    off, adj = kernel.csr(4, src, dst, bytearray(b"\x01\x01\x01\x01"))
    assert (off.tolist(), adj.tolist()) == ([0, 2, 3, 5, 6], [1, 2, 0, 1, 3, 3])
    off, adj = kernel.csr(4, src, dst, bytearray(b"\x01\x00\x01\x01"))
    assert (off.tolist(), adj.tolist()) == ([0, 1, 1, 2, 3], [2, 3, 3])
    off, adj = kernel.group(4, array("I", [2, 0, 2, 3, 0]))
    assert (off.tolist(), adj.tolist()) == ([0, 2, 2, 4, 5], [1, 4, 0, 2, 3])
    assert kernel.gather(array("I", [3, 0, 3, 1]), bytearray(b"\x00\x01\x00\x01")) == bytearray(b"\x01\x00\x01\x01")
    assert kernel.bit(array("B", [1, 2, 3, 0]), 1) == bytearray(b"\x00\x01\x01\x00")
    assert kernel.bit(array("q", [1, 2, 3, -1]), 0) == bytearray(b"\x01\x00\x01\x01")
    c = Classes(array("i", [0, 2, 3]), array("i", [1, 0, 1]))
    assert list(c) == [[1, 0], [1]]
    c[1] = [1, 2]
    c.append([2])
    assert list(c) == [[1, 0], [1, 2], [2]]
    off, adj = c.arrays()
    assert (off.tolist(), adj.tolist()) == ([0, 2, 4, 5], [1, 0, 1, 2, 2])
    v = Vectors(array("B", [0, 3, 2]), 2)
    v.append((True, False))
    assert list(v) == [(False, False), (True, True), (False, True), (True, False)]


# ----------------------------------------------------------------- the state layout
# rule values in locations of extended-domain elements: each slot holds the number of one of the
# rules written as values (narrow), not the rule's 64-bit code
PHASES = """asm Phases
import StandardLibrary
import CTLLibrary
signature:
	dynamic abstract domain Phase
	enum domain Mode = {IDLE | BUSY}
	controlled act: Phase -> Rule
	controlled mode: Mode
	controlled made: Integer
	controlled cur: Phase
definitions:
	rule r_work = mode := BUSY
	rule r_rest = mode := IDLE
	CTLSPEC ag(ef(mode = IDLE))
	main rule r_main =
		if made < 2 then
			extend Phase with $p do
				par
					choose $w in Boolean with true do
						if $w then act($p) := <<r_work>> else act($p) := <<r_rest>> endif
					cur := $p
					made := made + 1
				endpar
		else
			if cur != undef then
				par
					act(cur)
					act(cur) := undef
					cur := undef
				endpar
			else
				if mode = BUSY then mode := IDLE else mode := BUSY endif
			endif
		endif
default init s0:
	function made = 0
	function mode = IDLE
"""


def test_rule_slots_are_narrow(tmp_path, capsys):
    from asmcheck.explore.native import NativeExplorer
    path = write(tmp_path, PHASES)
    model = api.load(path)
    ex = NativeExplorer(model.machine)
    ex.run()
    g = ex.gen
    rule_slots = [s for s, key in enumerate(g.slots)
                  if type(key) is tuple and type(key[0]) is int and g.spec.functions[key[0]].name == "act"]
    assert rule_slots and all(g.bits[s] == 2 for s in rule_slots)     # two rules and undef
    assert [str(v) for v in g.slot_values[rule_slots[0]]] == ["<<r_rest>>", "<<r_work>>"]
    code, rep = both(tmp_path, capsys, PHASES)
    assert (rep["states"], rep["transitions"], ex.n_states) == (11, 14, 11)
    g2 = graphs(path, tmp_path, capsys)
    assert g2["native"][0] == "native" and g2["native"][1:] == g2["python"][1:]


# ----------------------------------------------------------------- CTL with fairness, kernel on and off
@pytest.mark.parametrize("engine", ["native", "python"])
def test_ctl_fair_components_kernel_equals_python(tmp_path, engine, monkeypatch):
    """CTL under compassion and justice (the fair components refined by the compiled kernel, its
    roots every node of the set without a copy of them) and under --fair Proc: the verdicts and
    the explained paths equal those of the Python code."""
    text = (ROOT / "specs" / "temporal" / "spinlock.asm").read_text()
    text = text.replace("import LTLLibrary\n", "import LTLLibrary\nimport CTLLibrary\n")
    text = text.replace("\tmain rule r_main", "\tCTLSPEC ctlSpec_eg_wait: eg(pc(p1) != CRIT)\n"
                        "\tCTLSPEC ctlSpec_af_crit: ag(pc(p1) = WAIT implies af(pc(p1) = CRIT))\n"
                        "\tCTLSPEC ctlSpec_ef: ef(pc(p2) = CRIT and pc(p1) = WAIT)\n\tmain rule r_main")
    path = write(tmp_path, text)
    prop = str(ROOT / "specs" / "temporal" / "spinlock_strong.prop")

    def rows(enabled, props, fair):
        monkeypatch.setattr(kernel, "ENABLED", enabled)
        run = api.load(path, properties=props).explore(engine=engine, fair=fair)
        assert run.result.engine == engine
        return [(r.name, r.holds, list(r.nodes), r.loop) for r in run.temporal if r.kind == "ctl"]
    for props, fair in ((None, ()), ([prop], ()), (None, ("Proc",))):
        on, off = rows(True, props, fair), rows(False, props, fair)
        assert on == off
        assert [r[0] for r in on] == ["ctlSpec_eg_wait", "ctlSpec_af_crit", "ctlSpec_ef"]
    # with both constraints, a run whose first step makes p1 wait cannot keep p1 out of its critical
    # section for ever (p2 leaves its own infinitely often, then p1 waits with the lock free)
    assert [r[1] for r in rows(True, [prop], ())] == [False, True, True]
