"""The explorer: exact state counts, shortest replayed traces, limits, exit codes, formats."""
import json
import subprocess
import sys

import pytest

from asmcheck.cli import main
from asmcheck.explore.bfs import Explorer
from asmcheck.props import spec_properties
from asmcheck.report.trace import build_trace

from conftest import need_bench
from helpers import machine, spec, write

pytestmark = pytest.mark.engines("both")


def twin(tmp_path, t, k, bug=False):
    bench = need_bench()
    out = subprocess.run([sys.executable, str(bench / "gen_swing.py"), str(t), str(k)] + (["--bug"] if bug else [])
                         + [str(tmp_path)], capture_output=True, text=True, check=True)
    return out.stdout.strip()


def explore(m, **kw):
    state, step = spec_properties(m)
    ex = Explorer(m, state_props=state, step_props=step, **kw)
    return ex, ex.run()


def test_twin_T7_K16_has_SPINs_state_count(tmp_path, capsys):
    path = twin(tmp_path, 7, 16)
    assert main(["explore", path, "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["verdict"], out["states"], out["violations"]) == ("holds", 5571, [])
    assert out["transitions"] == 14404


@pytest.mark.slow
@pytest.mark.engines("native")
def test_twin_T31_K128_has_SPINs_state_count(tmp_path, capsys):
    # the native engine's (the Python engine takes about 40 s over its 562,947 states; it has
    # SPIN's count on the twin T7 K16 above, and its peer in ../shared/bench on the larger ones)
    path = twin(tmp_path, 31, 128)
    assert main(["explore", path, "--format", "json", "--engine", "native"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["verdict"], out["states"], out["engine"]) == ("holds", 562947, "native")


def test_twin_bug_is_found_with_the_13_step_trace(tmp_path, capsys):
    path = twin(tmp_path, 7, 16, bug=True)
    assert main(["explore", path, "--format", "json"]) == 1
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "violated"
    (v,) = out["violations"]
    assert v["property"] == "inv_exclusive"
    trace = v["trace"]
    assert len(trace) == 14
    actions = [c["value"]["$a"] for e in trace[1:] for c in e["choices"]]
    assert actions == ["WR_TICK", "WR_TICK", "WR_BEGIN", "WR_WRITE", "WR_END", "WR_TICK", "WR_TICK", "WR_SWAP",
                       "WR_BEGIN", "RD_TICK", "RD_TICK", "RD_TICK", "RD_BEGIN"]
    last = trace[-1]["state"]
    assert last["wb1"] is True and last["rb1"] is True
    assert trace[-1]["changed"] == {"rb1": True, "rc": 0, "rpc": 1}


def test_text_trace_shows_choices_and_only_changed_locations(tmp_path, capsys):
    path = twin(tmp_path, 7, 16, bug=True)
    assert main(["explore", path]) == 1
    out = capsys.readouterr().out.splitlines()
    i = out.index(next(l for l in out if l.startswith("inv_exclusive")))
    assert "shortest counterexample, 13 steps" in out[i]
    step13 = out.index(next(l for l in out if "step 13" in l))
    assert out[step13 + 1:step13 + 4] == ["      rb1 = true", "      rc = 0", "      rpc = 1"]
    assert out[-1] == "verdict: violated"


COUNTER = spec("\tdomain Small subsetof Integer\n\tcontrolled x: Small\n\tmonitored go: Boolean",
               "\tdomain Small = {0 : 4}\n"
               "\tinvariant inv_small over x: x < 4\n"
               "\tmain rule r_main = if go then if x < 4 then x := x + 1 else x := 0 endif endif",
               "\tfunction x = 0")


def test_golden_counter_trace_and_counts(tmp_path):
    m = machine(tmp_path, COUNTER)
    ex, res = explore(m)
    assert (res.states, res.transitions, res.verdict) == (5, 10, "violated")
    tr = build_trace(ex, res.violations[0])
    assert [st.number for st in tr.steps] == [0, 1, 2, 3, 4]
    assert [[(c.label, c.value) for c in st.choices] for st in tr.steps[1:]] == [[("go", True)]] * 4
    assert [st.state[m.spec.functions[m.fname.index("x")].index] for st in tr.steps] == [0, 1, 2, 3, 4]


def test_limits_give_incomplete_and_exit_3(tmp_path, capsys):
    path = twin(tmp_path, 7, 16)
    assert main(["explore", path, "--max-states", "100", "--format", "json"]) == 3
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "incomplete" and out["states"] == 100 and "state limit" in out["incomplete"]
    assert main(["explore", path, "--max-depth", "5", "--format", "json"]) == 3
    out = json.loads(capsys.readouterr().out)
    assert out["verdict"] == "incomplete" and out["depth"] == 5


def test_deadlock_detection(tmp_path, capsys):
    text = spec("\tdomain Small subsetof Integer\n\tcontrolled x: Small",
                "\tdomain Small = {0 : 3}\n\tmain rule r_main = if x < 3 then x := x + 1 endif", "\tfunction x = 0")
    path = write(tmp_path, text)
    assert main(["explore", path]) == 0
    capsys.readouterr()
    assert main(["explore", path, "--deadlock", "--format", "json"]) == 1
    out = json.loads(capsys.readouterr().out)
    (v,) = out["violations"]
    assert v["property"] == "deadlock" and len(v["trace"]) == 4


def test_fresh_elements_are_canonical_and_dropped_when_unreferenced(tmp_path, capsys):
    # a buffer of two slots refilled forever with new elements: finite once names are canonical
    text = spec("\tdynamic abstract domain Data\n\tdomain Slot subsetof Integer\n\tcontrolled buf: Slot -> Data\n"
                "\tcontrolled next: Slot",
                "\tdomain Slot = {0 : 1}\n"
                "\tmain rule r_main = extend Data with $d do par buf(next) := $d next := 1 - next endpar",
                "\tfunction next = 0")
    path = write(tmp_path, text)
    assert main(["explore", path, "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["states"] == 4


def test_graph_export(tmp_path):
    path = write(tmp_path, COUNTER.replace("x: x < 4", "x: x < 5"))
    dot = tmp_path / "g.dot"
    gml = tmp_path / "g.graphml"
    assert main(["explore", path, "--graph", str(dot)]) == 0
    assert main(["explore", path, "--graph", str(gml)]) == 0
    text = dot.read_text()
    assert text.count(" -> ") == 10 and text.startswith("digraph states {")
    import networkx as nx
    g = nx.read_graphml(gml)
    assert g.number_of_nodes() == 5 and g.number_of_edges() == 10


def test_exploration_is_deterministic(tmp_path, capsys):
    path = twin(tmp_path, 7, 16, bug=True)
    main(["explore", path, "--format", "json"])
    a = json.loads(capsys.readouterr().out)
    main(["explore", path, "--format", "json"])
    b = json.loads(capsys.readouterr().out)
    a.pop("seconds"), b.pop("seconds")
    a.pop("compile_seconds", None), b.pop("compile_seconds", None)
    assert a == b


def test_unbounded_monitored_integer_is_a_located_error(tmp_path, capsys):
    text = spec("\tmonitored m: Integer\n\tcontrolled x: Integer", "\tmain rule r_main = x := m")
    path = write(tmp_path, text)
    assert main(["explore", path]) == 2
    got = capsys.readouterr()
    # a located input error goes to stderr; stdout carries results only
    assert got.out == "" and f"{path}:4:" in got.err and "--monitored m=LO..HI" in got.err
    assert main(["explore", path, "--format", "json"]) == 2
    got = capsys.readouterr()
    assert json.loads(got.out)["error"]["line"] == 4 and f"{path}:4:" in got.err
    assert main(["explore", path, "--monitored", "m=1..3", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["states"] == 4


@pytest.mark.parametrize("bug", [False, True])
def test_native_and_python_engines_agree(tmp_path, capsys, bug):
    from asmcheck.explore.native_build import compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    path = twin(tmp_path, 7, 16, bug=bug)
    outs = []
    for engine in ("native", "python"):
        assert main(["explore", path, "--format", "json", "--engine", engine]) == (1 if bug else 0)
        out = json.loads(capsys.readouterr().out)
        assert out.pop("engine") == engine
        out.pop("seconds")
        out.pop("compile_seconds", None)
        outs.append(out)
    assert outs[0] == outs[1]


@pytest.mark.engines("native")
def test_native_engine_refuses_what_it_cannot_translate(tmp_path, capsys):
    from asmcheck.explore.native_build import compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    # a Real location holding -0.0 (equal to 0.0 in the Python engine's states, not in the native ones)
    text = spec("\tcontrolled s: Real\n\tcontrolled z: Real", "\tmain rule r_main = par s := s + 1.5 z := -s endpar",
                "\tfunction s = 0.0")
    path = write(tmp_path, text)
    assert main(["explore", path, "--engine", "native", "--max-states", "3"]) == 2
    assert "the native explorer cannot run S.asm" in capsys.readouterr().err
    assert main(["explore", path, "--max-states", "3", "--format", "json"]) == 3
    assert json.loads(capsys.readouterr().out)["engine"] == "python"


COUNTER_TEN = """asm CounterTen
import StandardLibrary
signature:
	dynamic controlled x: Integer
definitions:
	invariant inv_small over x: x < 3
	invariant inv_nonneg over x: x >= 0
	main rule r_main = x := (x + 1) mod 10
default init s0:
	function x = 0
"""


def test_a_limit_leaves_the_other_properties_incomplete_beside_a_violation(tmp_path, capsys):
    import json as _json

    from asmcheck.cli import main

    spec = tmp_path / "CounterTen.asm"
    spec.write_text(COUNTER_TEN, encoding="utf-8")
    assert main(["explore", str(spec), "--max-depth", "5", "--format", "json"]) == 1
    out = _json.loads(capsys.readouterr().out)
    assert (out["verdict"], out["states"], out["incomplete"]) == ("violated", 6, "depth limit 5 reached")
    assert {p["property"]: p["verdict"] for p in out["properties"]} == {"inv_small": "violated",
                                                                         "inv_nonneg": "incomplete"}
    assert main(["explore", str(spec), "--max-depth", "5"]) == 1
    text = capsys.readouterr().out
    assert "  inv_nonneg                               incomplete\n" in text
    assert text.endswith("incomplete: depth limit 5 reached\nverdict: violated\n")
    # without a limit the search covers everything: the other invariant holds
    assert main(["explore", str(spec), "--format", "json"]) == 1
    out = _json.loads(capsys.readouterr().out)
    assert {p["property"]: p["verdict"] for p in out["properties"]}["inv_nonneg"] == "holds"
    assert "incomplete" not in out
