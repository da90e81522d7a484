"""The simulate command: outputs, inputs, invariants, and the RTPatternLibrary applications."""
import json

import pytest

from asmcheck.cli import main

from conftest import need_asmeta
from helpers import spec, write

SCHED = spec("\tenum domain Job = {JA | JB}\n\tenum domain Status = {RDY | RUN | FIN}\n"
             "\tcontrolled st: Job -> Status\n\tmonitored fin: Job -> Boolean",
             "\tinvariant inv_not_both over st: not (st(JA) = FIN and st(JB) = FIN)\n"
             "\tmain rule r_main = par\n"
             "\t\tchoose $j in Job with st($j) = RDY do st($j) := RUN\n"
             "\t\tforall $j in Job with st($j) = RUN do if fin($j) then st($j) := FIN endif\n\tendpar",
             "\tfunction st($j in Job) = RDY")


def test_text_output_shows_choices_and_changes(tmp_path, capsys):
    path = write(tmp_path, SCHED)
    assert main(["simulate", path, "-n", "2"]) == 0
    assert capsys.readouterr().out.splitlines() == [
        "initial state:", "  st(JA) = RDY", "  st(JB) = RDY",
        "step 1  [choose at S.asm:11:3: $j = JA]:", "  st(JA) = RUN",
        "step 2  [fin(JA) = false]:", "  st(JB) = RUN",
    ]


def test_inputs_file_and_invariant_violation(tmp_path, capsys):
    path = write(tmp_path, SCHED)
    inputs = tmp_path / "in.txt"
    inputs.write_text("---\nfin(JA) = true\n---\nfin(JB) = true\n")
    assert main(["simulate", path, "-n", "5", "--input", str(inputs)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[-1].endswith("invariant inv_not_both is violated after step 3")
    assert "step 2  [fin(JA) = true]:" in out


def test_asmeta_format(tmp_path, capsys):
    path = write(tmp_path, SCHED)
    assert main(["simulate", path, "-n", "2", "--format", "asmeta"]) == 0
    assert capsys.readouterr().out.splitlines() == [
        "<State 1 (controlled)>", "st(JA)=RUN", "st(JB)=RDY", "</State 1 (controlled)>",
        "taking false for fin(JA)", "<State 1 (monitored)>", "fin(JA)=false", "</State 1 (monitored)>",
        "<State 2 (controlled)>", "st(JA)=RUN", "st(JB)=RUN", "</State 2 (controlled)>",
        "Final state:", "st(JA)=RUN", "st(JB)=RUN",
    ]


def test_seeded_random_runs_repeat(tmp_path, capsys):
    path = write(tmp_path, SCHED)
    main(["simulate", path, "-n", "6", "--seed", "5", "--format", "json"])
    a = capsys.readouterr().out
    main(["simulate", path, "-n", "6", "--seed", "5", "--format", "json"])
    assert capsys.readouterr().out == a


@pytest.mark.parametrize("app", ["VisualServoing", "CompleteApplication", "Test_SB", "RobotController"])
def test_rtpattern_applications_simulate_1000_steps(app, capsys):
    root = need_asmeta()
    path = root / "asm_examples/RTPatternLibrary/Application" / f"{app}.asm"
    assert main(["simulate", str(path), "-n", "1000", "--random", "--format", "json"]) == 0
    steps = json.loads(capsys.readouterr().out)["steps"]
    assert len(steps) == 1001
    assert all(s["error"] is None and not s["violated"] for s in steps)
