"""A Ctrl-C during `asmcheck simulate` keeps the steps taken so far: they are printed (text, JSON,
ASMETA's blocks) with a line that says where the run stopped, and the exit code is 3 (the output
was only 'asmcheck: interrupted before any result', however many steps had run)."""
from __future__ import annotations

import json

import pytest

import asmcheck.simulate
from asmcheck.cli import main

pytestmark = pytest.mark.engines("none")

COUNT = """asm Count
import StandardLibrary
signature:
	dynamic controlled x: Integer
definitions:
	main rule r_main = x := x + 1
default init s0:
	function x = 0
"""


@pytest.fixture
def three_steps_then_ctrl_c(monkeypatch):
    real = asmcheck.simulate.simulate

    def simulate(machine, steps, **kw):
        for st in real(machine, steps, **kw):
            if st.number == 4:
                raise KeyboardInterrupt
            yield st
    monkeypatch.setattr(asmcheck.simulate, "simulate", simulate)


def test_the_text_keeps_the_steps_and_says_where_it_stopped(write_spec, capsys, three_steps_then_ctrl_c):
    path = write_spec(COUNT)
    assert main(["simulate", path, "-n", "1000"]) == 3
    out = capsys.readouterr().out
    assert out == ("state 0 (initial)\n    x = 0\nstep 1: r_main\n    x = 1\nstep 2: r_main\n    x = 2\n"
                   "step 3: r_main\n    x = 3\ninterrupted (Ctrl-C) after step 3\n")


def test_the_json_says_it_too(write_spec, capsys, three_steps_then_ctrl_c):
    path = write_spec(COUNT)
    assert main(["simulate", path, "-n", "1000", "--format", "json"]) == 3
    doc = json.loads(capsys.readouterr().out)
    assert [s["step"] for s in doc["steps"]] == [0, 1, 2, 3]
    assert doc["interrupted"] == "interrupted (Ctrl-C) after step 3"


def test_asmeta_blocks_and_the_note_on_stderr(write_spec, capsys, three_steps_then_ctrl_c):
    path = write_spec(COUNT)
    assert main(["simulate", path, "-n", "1000", "--format", "asmeta"]) == 3
    cap = capsys.readouterr()
    assert "<State 3 (controlled)>" in cap.out and "<State 4 (controlled)>" not in cap.out
    assert cap.err == "asmcheck: interrupted (Ctrl-C) after step 3\n"


def test_a_run_that_takes_its_steps_is_unchanged(write_spec, capsys):
    path = write_spec(COUNT)
    assert main(["simulate", path, "-n", "2"]) == 0
    assert capsys.readouterr().out == "state 0 (initial)\n    x = 0\nstep 1: r_main\n    x = 1\nstep 2: r_main\n    x = 2\n"
