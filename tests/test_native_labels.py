"""The native explorer's ``state_labels``: the state atoms of the temporal properties are
translated to C with the model and evaluated for every stored state at once; the result equals
the Python evaluation atom by atom and state by state, and an atom that was not translated gives
None (the temporal layer then evaluates in Python).  Engines pinned: native, compared with python."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from asmcheck import api
from asmcheck.explore.native_build import compiler
from asmcheck.semantics.machine import Chooser, Ctx
from asmcheck.temporal import label_atoms
from asmcheck.temporal.formula import Atoms, Builder

ROOT = Path(__file__).resolve().parent.parent

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the native engine is not built")]

SPEC = """asm labels

import StandardLibrary
import CTLLibrary
import LTLLibrary

signature:
	enum domain Proc = {PA | PB | PC}
	domain Lvl subsetof Integer
	dynamic controlled lvl: Proc -> Lvl
	dynamic controlled turn: Proc
	derived total: Integer

definitions:
	domain Lvl = {0 : 2}

	function total = lvl(PA) + lvl(PB) + lvl(PC)

	LTLSPEC ltlSpec_bound: g(total <= 5)
	LTLSPEC ltlSpec_each: (forall $p in Proc with g(f(lvl($p) = 0)))
	LTLSPEC ltlSpec_turn: g(turn = PA implies x(turn != PA or lvl(PA) != 1))
	CTLSPEC ctlSpec_some: ef((exists $p in Proc with lvl($p) = 2))
	CTLSPEC ctlSpec_undef: ag(turn = PB or turn != PB)

	main rule r_main =
		choose $p in Proc with true do
			par
				if lvl($p) < 2 then lvl($p) := lvl($p) + 1 else lvl($p) := 0 endif
				turn := $p
			endpar

default init s0:
	function lvl($p in Proc) = 0
"""


@pytest.fixture
def spec(tmp_path):
    p = tmp_path / "labels.asm"
    p.write_text(SPEC)
    return p


def _explored(path):
    from asmcheck.explore.native import NativeExplorer
    model = api.load(str(path))
    ex = NativeExplorer(model.machine, keep_graph=True, label_atoms=lambda st: label_atoms(model.machine, list(model.temporal), st))
    res = ex.run()
    return model, ex, res


def _atoms(model, ex):
    atoms = Atoms(model.machine)
    builder = Builder(model.machine, atoms, ex.state(0))
    for p in model.temporal:
        builder.build(p.body, "ltl" if p.kind == "ltl" else "ctl")
    return atoms


def test_labels_equal_python_evaluation(spec):
    model, ex, res = _explored(spec)
    assert (res.states, res.transitions) == (82, 246)
    atoms = _atoms(model, ex)
    items = [a for a in atoms.items if not a.monitored]
    assert [a.text for a in items] == [
        "total <= 5", "lvl($p) = 0 [$p = PA]", "lvl($p) = 0 [$p = PB]", "lvl($p) = 0 [$p = PC]",
        "turn = PA", "turn != PA or lvl(PA) != 1", "(exists $p in Proc with lvl($p) = 2)",
        "turn = PB or turn != PB"]
    labs = ex.state_labels(items)
    assert labs is not None and len(labs) == len(items)
    for a, lab in zip(items, labs):
        assert len(lab) == 82
        want = bytearray(82)
        for sid in range(82):
            ctx = Ctx(model.machine, ex.state(sid), Chooser())
            ctx.env = dict(a.env)
            want[sid] = 1 if a.fn(ctx) is True else 0
        assert lab == want, a.text
    counts = {a.text: lab.count(1) for a, lab in zip(items, labs)}
    # turn is undef in the initial state only (undef != PB is true there); total is 6 in the
    # three states with every level at 2 (one per value of turn)
    assert counts == {"total <= 5": 79, "lvl($p) = 0 [$p = PA]": 28, "lvl($p) = 0 [$p = PB]": 28,
                      "lvl($p) = 0 [$p = PC]": 28, "turn = PA": 27, "turn != PA or lvl(PA) != 1": 73,
                      "(exists $p in Proc with lvl($p) = 2)": 57, "turn = PB or turn != PB": 82}


def test_atom_not_translated_gives_none(spec):
    model, ex, _ = _explored(spec)
    atoms = _atoms(model, ex)
    assert ex.state_labels(atoms.items[:2]) is not None
    # the same term under a binding no property makes: not among the translated atoms
    other = Atoms(model.machine)
    other.add(atoms.items[0].term, {-1: 1})
    assert ex.state_labels([other.items[0]]) is None
    assert ex.state_labels([atoms.items[0], other.items[0]]) is None


def test_label_atoms_lists_the_state_atoms(spec):
    model = api.load(str(spec))
    st0 = model.machine.initial_states()[0][1]
    got = label_atoms(model.machine, list(model.temporal), st0)
    assert len(got) == 8
    assert sum(1 for _, env in got if env) == 3


def test_verdicts_and_traces_equal_python_engine(spec):
    runs = {}
    for engine in ("native", "python"):
        out = subprocess.run([sys.executable, "-m", "asmcheck", "explore", str(spec), "--engine", engine, "--format", "json"],
                             capture_output=True, text=True, cwd=ROOT)
        assert out.returncode == 1, out.stderr
        data = json.loads(out.stdout)
        for k in ("seconds", "compile_seconds", "engine"):
            data.pop(k, None)
        runs[engine] = data
    assert runs["native"]["states"] == 82
    assert json.dumps(runs["native"], sort_keys=True, default=str) == \
        json.dumps(runs["python"], sort_keys=True, default=str)


MONEDGE = """asm monedge

import StandardLibrary
import CTLLibrary

signature:
	dynamic monitored b: Boolean
	dynamic controlled x: Boolean

definitions:
	CTLSPEC ctlSpec_always_b: ag(b)
	CTLSPEC ctlSpec_never_b: ag(not b)

	main rule r_main =
		if b then x := not x else x := not x endif

default init s0:
	function x = false
"""


def test_steps_with_other_inputs_to_the_same_state(tmp_path):
    """Both values of b lead from each state to the same successor: the native explorer records
    the pair once, but the CTL structure (a NuSMV state holds the inputs its step reads) needs
    both steps, so neither ag(b) nor ag(not b) holds, on either engine."""
    p = tmp_path / "monedge.asm"
    p.write_text(MONEDGE)
    got = {}
    for engine in ("native", "python"):
        run = api.load(str(p)).explore(engine=engine)
        assert (run.states, run.transitions) == (2, 2)
        got[engine] = [(r.name, r.holds, list(r.nodes), r.stats.get("kripke_nodes")) for r in run.temporal]
    assert got["native"] == got["python"]
    assert [(name, holds, kn) for name, holds, _, kn in got["native"]] == [
        ("ctlSpec_always_b", False, 4), ("ctlSpec_never_b", False, 4)]


def test_step_atoms_pairs(tmp_path):
    """asm_step_atoms: per stored state, the (target, atom values) pairs of its steps, once each."""
    from asmcheck.explore.native import NativeExplorer
    p = tmp_path / "monedge.asm"
    p.write_text(MONEDGE)
    model = api.load(str(p))
    ex = NativeExplorer(model.machine, keep_graph=True, label_atoms=lambda st: label_atoms(model.machine, list(model.temporal), st))
    ex.run()
    atoms = Atoms(model.machine)
    builder = Builder(model.machine, atoms, ex.state(0))
    for prop in model.temporal:
        builder.build(prop.body, "ctl")
    mon = [a for a in atoms.items if a.monitored]
    assert [a.text for a in mon] == ["b", "not b"]
    tf, ft = (True, False), (False, True)

    def triples(items, ok):
        # three arrays: sources, targets, the atoms' values as bits (bit k: atom k)
        src, dst, bits = ex.step_atoms(items, ok)
        return [(s, d, tuple(bool(b >> k & 1) for k in range(len(items)))) for s, d, b in zip(src, dst, bits)]
    assert triples(mon, bytearray(b"\x01\x01")) == [(0, 1, ft), (0, 1, tf), (1, 0, ft), (1, 0, tf)]
    assert triples(mon, bytearray(b"\x00\x01")) == [(1, 0, ft), (1, 0, tf)]
    # b is read by the step (False first, as the monitored values are enumerated)
    assert triples(mon[:1], bytearray(b"\x01\x00")) == [(0, 1, (False,)), (0, 1, (True,))]


MONUNREAD = """asm monunread

import StandardLibrary
import CTLLibrary

signature:
	enum domain Mode = {AA | BB | CC}
	dynamic monitored b: Boolean
	dynamic monitored md: Mode
	dynamic controlled x: Boolean
	dynamic controlled cnt: Mode

definitions:
	CTLSPEC ctlSpec_1: ag(b implies ef(md = CC))
	CTLSPEC ctlSpec_2: ag(md = AA or x)
	CTLSPEC ctlSpec_3: ef(b and not x and md = BB)
	CTLSPEC ctlSpec_4: ag(ex(cnt = BB and md = CC))

	main rule r_main =
		if b then par x := not x cnt := md endpar else x := true endif

default init s0:
	function x = false
	function cnt = AA
"""


def test_inputs_the_step_does_not_read(tmp_path):
    """md is read by the step only when b holds; the CTL atoms over md take every value of it
    where the step does not read it: the same report (verdicts, traces) on both engines."""
    p = tmp_path / "monunread.asm"
    p.write_text(MONUNREAD)
    out = {}
    for engine in ("native", "python"):
        r = subprocess.run([sys.executable, "-m", "asmcheck", "explore", str(p), "--engine", engine],
                           capture_output=True, text=True, cwd=ROOT)
        assert r.returncode == 1, r.stderr
        lines = r.stdout.splitlines()
        assert lines[0].startswith("monunread.asm: 6 states, 21 transitions, depth 2,")
        assert lines[0].endswith(f"{engine} engine")
        out[engine] = lines[1:]
    assert out["native"] == out["python"]
    assert out["native"][:4] == ["  ctlSpec_1                                holds",
                                 "  ctlSpec_2                                violated",
                                 "  ctlSpec_3                                holds",
                                 "  ctlSpec_4                                violated"]
