"""Options that reach the step function from the command line: --max-loop, scenario bounds, properties
over infinite domains, and the inputs of a step that fails."""
from __future__ import annotations

import json

import pytest

from asmcheck.cli import main

pytestmark = pytest.mark.engines("both")

LOOP = """asm Lp
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	invariant inv_x over x: x >= 0
	main rule r_main = while x < 20000 do x := x + 1
default init s0:
	function x = 0
"""

QUANT = """asm Qi
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	invariant inv_q over x: (forall $i in Integer with $i > x implies $i > 0)
	main rule r_main = if x < 3 then x := x + 1 endif
default init s0:
	function x = 0
"""

CLASH = """asm Cl
import StandardLibrary
signature:
	controlled x: Integer
	monitored go: Boolean
definitions:
	main rule r_main = par
		x := 1
		if go then x := 2 endif
	endpar
default init s0:
	function x = 0
"""

PICK = """asm Pick
import StandardLibrary
signature:
	controlled x: Integer
	monitored m: Integer
definitions:
	main rule r_main = choose $i in Integer with $i > 2 and $i < 5 do x := $i + m
default init s0:
	function x = 0
"""


def run(capsys, *argv):
    code = main(list(argv))
    got = capsys.readouterr()
    return code, got.out, got.err


@pytest.mark.parametrize("engine", ["python", "native"])
def test_max_loop_raises_the_while_bound(capsys, write_spec, engine):
    path = write_spec(LOOP)
    code, out, _ = run(capsys, "explore", path, "--engine", engine)
    if engine == "native" and "cannot run" in out:
        pytest.skip("no native engine here")
    assert code == 1
    assert "a step fails (Lp.asm:7:21): the while at Lp.asm:7:21 did not end after 10000 iterations in one " \
           "step (raise the bound with --max-loop)" in out
    code, out, _ = run(capsys, "explore", path, "--engine", engine, "--max-loop", "20001")
    assert code == 0, out
    assert out.startswith(f"Lp.asm: 2 states, 2 transitions, depth 1, ")
    assert f" s, {engine} engine\n" in out.splitlines(keepends=True)[0]


def test_max_loop_must_be_positive(capsys, write_spec):
    code, _, err = run(capsys, "simulate", write_spec(LOOP), "--max-loop", "0")
    assert code == 2 and "0: expected 1 or more" in err


def test_a_property_over_integer_is_an_input_error_at_its_range(capsys, write_spec):
    path = write_spec(QUANT)
    code, out, err = run(capsys, "explore", path)
    assert code == 2 and out == ""
    assert err.splitlines()[0] == (f"{path}:6:40: the property inv_q quantifies over Integer, which is infinite: "
                                   "asmcheck cannot evaluate it (bound the variable with a subset domain, or give "
                                   "--int-range LO..HI)")
    code, out, _ = run(capsys, "explore", path, "--int-range", "-5..5")
    assert code == 0 and "inv_q                                    holds" in out


@pytest.mark.parametrize("engine", ["python", "native"])
def test_a_failing_step_shows_its_inputs(capsys, write_spec, engine):
    path = write_spec(CLASH)
    code, out, _ = run(capsys, "explore", path, "--engine", engine)
    if engine == "native" and "cannot run" in out:
        pytest.skip("no native engine here")
    assert code == 1
    lines = out.splitlines()
    i = lines.index("a step fails (Cl.asm:9:14): inconsistent update of x: 1 and 2 -- shortest counterexample, "
                    "0 steps, then step 1 fails:")
    assert lines[i + 1:i + 4] == ["  state 0 (initial)", "      x = 0",
                                  "  step 1: r_main; reads go = true  <- fails (the step cannot be made)"]
    code, out, _ = run(capsys, "explore", path, "--engine", engine, "--format", "json")
    v = json.loads(out)["violations"][0]
    assert v["property"] == "error"
    assert v["failing_step"] == {"step": 1, "choices": [{"kind": "monitored", "at": "go", "value": True}]}


def test_scenario_takes_int_range_and_refuses_monitored(capsys, tmp_path):
    (tmp_path / "Pick.asm").write_text(PICK)
    sc = tmp_path / "pick.avalla"
    sc.write_text("scenario pick\nload Pick.asm\nset m := 1;\nstep\ncheck x = 4;\n")
    code, out, _ = run(capsys, "scenario", str(sc))
    assert code == 1 and "choose over the infinite domain Integer with a guard" in out
    code, out, _ = run(capsys, "scenario", str(sc), "--int-range", "-3..10")
    assert code == 0 and "scenario pick: PASS: 1 of 1 check(s) passed; 1 step(s)" in out
    code, _, err = run(capsys, "scenario", str(sc), "--monitored", "m=0..3")
    assert code == 2 and "--monitored does not apply to a scenario" in err
