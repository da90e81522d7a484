"""The Avalla export of every seeded bug's counterexample (specs/buggy/*.asm), run by
`asmcheck scenario`, reproduces the violation; and the exporter's corner cases."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from asmcheck.cli import build_parser, main
from asmcheck.props.load import load_machine
from asmcheck.explore.bfs import Explorer
from asmcheck.props import spec_properties
from asmcheck.props.files import properties_for
from asmcheck.report.avalla_export import explore_avalla, trace_scenario
from asmcheck.report.gate import expect_lines, property_text, temporal_trace
from asmcheck.report.trace import build_trace

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parent.parent
BUGGY = sorted((ROOT / "specs" / "buggy").glob("*.asm"))


def need_scenario_command():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    if "scenario" not in sub.choices:
        pytest.skip("the 'asmcheck scenario' subcommand is not registered yet (asmcheck/commands_scenario.py)")


def run_scenario(path: Path, capsys) -> dict:
    main(["scenario", str(path), "--format", "json"])
    return json.loads(capsys.readouterr().out)


def counterexample(spec_path: str, name: str):
    """(machine, trace, property, loop) of the shortest counterexample of ``name``: the
    explorer checks only that property, so it stops at its first violation."""
    spec, m = load_machine(spec_path)
    state, step = spec_properties(m)
    extra_state, extra_step, temporal = properties_for(spec, m, spec_path)
    state, step = state + extra_state, step + extra_step
    st = [p for p in state if p.name == name]
    sp = [p for p in step if p.name == name]
    if st or sp:
        ex = Explorer(m, state_props=st, step_props=sp)
        res = ex.run()
        (v,) = res.violations
        return m, build_trace(ex, v), v.prop, None
    from asmcheck.temporal import check_temporal
    props = [p for p in temporal if p.name == name or p.kind in ("justice", "compassion")]
    assert any(p.name == name for p in props), f"{name} is no property of {spec_path}"
    ex = Explorer(m, keep_graph=True)
    ex.run()
    results = [t for t in check_temporal(ex, props) if t.name == name]
    assert results and not results[0].holds
    tr, loop = temporal_trace(results[0])
    return m, tr, next(p for p in props if p.name == name), loop


@pytest.mark.parametrize("spec_path", BUGGY, ids=[p.stem for p in BUGGY])
def test_avalla_export_of_each_seeded_bug_reproduces_it(spec_path, tmp_path, capsys):
    need_scenario_command()
    (name,) = expect_lines(str(spec_path))
    m, tr, prop, loop = counterexample(str(spec_path), name)
    out = tmp_path / f"{spec_path.stem}.avalla"
    out.write_text(trace_scenario(m, tr, spec_path=str(spec_path), out_path=str(out), prop=prop, loop=loop))
    doc = run_scenario(out, capsys)
    n = len(tr.steps) - 1
    assert doc["steps"] == n, doc
    checks = [e for e in doc["events"] if e["kind"] == "check"]
    kind = getattr(prop, "kind", "")
    if kind == "invariant":
        if prop.source == "spec":
            # the validator stops at the spec's invariant, violated after the last step
            assert doc["stopped"] == f"invariant {name}"
            assert all(c["ok"] for c in checks)
        else:
            # every check passes but the last: the invariant itself
            assert all(c["ok"] for c in checks[:-1]) and not checks[-1]["ok"]
            assert checks[-1]["text"] == property_text(prop)
            assert doc["result"] == "fail"
    else:
        # a step property or an LTL lasso: the run follows the counterexample to its end
        assert all(c["ok"] for c in checks), [c for c in checks if not c["ok"]]
        assert doc["result"] == "pass" or doc["stopped"].startswith("invariant ")
        if kind == "ltl":
            assert loop is not None
            assert out.read_text().rstrip().splitlines()[-2].startswith(f"// {name} is violated: the state is now")


def test_a_diverging_run_fails_its_checks(tmp_path, capsys):
    """The checks do pin the counterexample down: another choice fails them."""
    need_scenario_command()
    spec = ROOT / "tests" / "data" / "check" / "tiny_mutex.asm"
    m, tr, prop, _ = counterexample(str(spec), "inv_mutex")
    text = trace_scenario(m, tr, spec_path=str(spec), out_path=str(tmp_path / "x.avalla"), prop=prop)
    assert text.count("pick $p := PB;") == 2
    (tmp_path / "x.avalla").write_text(text.replace("pick $p := PB;", "pick $p := PA;"))
    doc = run_scenario(tmp_path / "x.avalla", capsys)
    assert any(not e["ok"] for e in doc["events"] if e["kind"] == "check")


def test_monitored_invariant_is_checked_with_the_inputs_set(tmp_path, capsys):
    """An invariant over monitored values is violated in a state with the next step's inputs:
    the scenario sets them and checks the invariant before that step."""
    need_scenario_command()
    spec = tmp_path / "mon.asm"
    spec.write_text("asm mon\nimport StandardLibrary\nsignature:\n\tcontrolled x: Boolean\n\tmonitored go: Boolean\n"
                    "definitions:\n\tmain rule r_main = x := true\ndefault init s0:\n\tfunction x = false\n")
    # in a property file: the validator checks the spec's own invariants after every step,
    # when the monitored values of the next step are not set yet
    (tmp_path / "properties").mkdir()
    (tmp_path / "properties" / "mon.prop").write_text("applies to mon\ninvariant inv_calm: not(go and x)\n")
    m, tr, prop, _ = counterexample(str(spec), "inv_calm")
    assert tr.kind == "step"
    out = tmp_path / "mon.avalla"
    text = trace_scenario(m, tr, spec_path=str(spec), out_path=str(out), prop=prop)
    assert text.rstrip().endswith("set go := true;\n\n// inv_calm is violated with the monitored values set above: "
                                  "this check fails\ncheck not(go and x);")
    out.write_text(text)
    doc = run_scenario(out, capsys)
    checks = [e for e in doc["events"] if e["kind"] == "check"]
    assert doc["result"] == "fail" and not checks[-1]["ok"] and all(c["ok"] for c in checks[:-1])


def test_pick_names_the_rule_when_two_rules_bind_the_variable(tmp_path):
    spec = tmp_path / "two.asm"
    spec.write_text("asm two\nimport StandardLibrary\nsignature:\n\tcontrolled a: Integer\n\tcontrolled b: Integer\n"
                    "definitions:\n\trule r_a = choose $x in {1, 2} with true do a := $x\n"
                    "\trule r_b = choose $x in {3, 4} with true do b := $x\n"
                    "\tinvariant inv_small over a, b: a + b < 6\n"
                    "\tmain rule r_main = par r_a[] r_b[] endpar\n"
                    "default init s0:\n\tfunction a = 0\n\tfunction b = 0\n")
    m, tr, prop, _ = counterexample(str(spec), "inv_small")
    text = trace_scenario(m, tr, spec_path=str(spec), out_path=str(tmp_path / "t.avalla"), prop=prop)
    assert "pick $x in r_a := 2;" in text and ("pick $x in r_b := 4;" in text)


def test_undef_and_load_path(tmp_path):
    spec = ROOT / "tests" / "data" / "check" / "tiny_mutex.asm"
    m, tr, prop, _ = counterexample(str(spec), "stp_no_reentry")
    inside = ROOT / "tests" / "data" / "out" / "x.avalla"
    text = trace_scenario(m, tr, spec_path=str(spec), out_path=str(inside), prop=prop)
    assert "\nload ../check/tiny_mutex.asm\n" in text
    text = trace_scenario(m, tr, spec_path=str(spec), out_path=None, prop=prop)
    assert f"\nload {spec.as_posix()}\n" in text


def test_explore_avalla_helper_writes_one_file_per_counterexample(tmp_path):
    spec = ROOT / "tests" / "data" / "check" / "tiny_mutex.asm"
    m, tr, prop, _ = counterexample(str(spec), "inv_mutex")

    class V:
        pass
    v = V()
    v.prop = prop
    one = explore_avalla(str(tmp_path / "cx.avalla"), m, str(spec), [(v, tr)])
    assert [Path(p).name for p in one] == ["cx.avalla"]
    two = explore_avalla(str(tmp_path / "cx.avalla"), m, str(spec), [(v, tr), (v, tr)])
    assert [Path(p).name for p in two] == ["cx.inv_mutex.avalla", "cx.inv_mutex.avalla"]
    d = explore_avalla(str(tmp_path / "dir") + "/", m, str(spec), [(v, tr)])
    assert [Path(p).name for p in d] == ["tiny_mutex.inv_mutex.avalla"]
