"""The simulate command: outputs, inputs, invariants, and the RTPatternLibrary applications."""
import json

import pytest

from asmcheck.cli import main

from conftest import need_asmeta
from helpers import spec, write

pytestmark = pytest.mark.engines("none")

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
        "state 0 (initial)", "    st(JA) = RDY", "    st(JB) = RDY",
        "step 1: r_main chooses $j = JA", "    st(JA) = RUN",
        "step 2: r_main; reads fin(JA) = false", "    st(JB) = RUN",
    ]


def test_inputs_file_and_invariant_violation(tmp_path, capsys):
    path = write(tmp_path, SCHED)
    inputs = tmp_path / "in.txt"
    inputs.write_text("---\nfin(JA) = true\n---\nfin(JB) = true\n")
    assert main(["simulate", path, "-n", "5", "--input", str(inputs)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[-1].endswith("invariant inv_not_both is violated after step 3")
    assert "step 2: r_main; reads fin(JA) = true" in out


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


STRUCT = spec("\tenum domain C = {AA | BB}\n\tmonitored f3: Seq(Integer)\n\tmonitored ps: Powerset(C)\n"
              "\tmonitored pr: Prod(Integer, Boolean)\n\tmonitored mp: Map(C, Integer)\n\tmonitored bg: Bag(Integer)\n"
              "\tmonitored nm: String\n"
              "\tcontrolled n: Integer\n\tcontrolled ok: Boolean\n\tcontrolled t: Integer\n\tcontrolled k: Integer\n"
              "\tcontrolled b: Natural\n\tcontrolled w: String",
              "\tmain rule r_main = par\n\t\tn := length(f3)\n\t\tok := contains(ps, BB)\n\t\tt := first(pr)\n"
              "\t\tk := at(mp, AA)\n\t\tb := count(bg, 1)\n\t\tw := nm\n\tendpar")


def test_structured_input_values_are_values_of_the_codomain(tmp_path, capsys):
    path = write(tmp_path, STRUCT)
    inputs = tmp_path / "in.txt"
    inputs.write_text('f3 = [1,2,4567]\nps = {AA, BB}\npr = (7,true)\nmp = {AA->3,BB->4}\nbg = <1,1,2>\n'
                      'nm = "a b"\n')
    assert main(["simulate", path, "-n", "1", "--input", str(inputs)]) == 0
    assert capsys.readouterr().out.splitlines() == [
        "state 0 (initial)",
        'step 1: r_main; reads bg = <1, 1, 2>, f3 = [1, 2, 4567], mp = {AA->3, BB->4}, nm = "a b", '
        'pr = (7, true), ps = {AA, BB}',
        "    b = 2", "    k = 3", "    n = 3", "    ok = true", "    t = 7", '    w = "a b"']


@pytest.mark.parametrize("line, where, message", [
    ("f3 = [1,2,x]", "1:6", "[1,2,x] is not a value of Seq(Integer) (the codomain of f3)"),
    ("f3 = [1,2", "1:6", "[1,2 is not a value of Seq(Integer) (the codomain of f3)"),
    ("ps = {AA, CC}", "1:6", "{AA, CC} is not a value of Powerset(C) (the codomain of ps)"),
    ("pr = (1,2)", "1:6", "(1,2) is not a value of Prod(Integer,Boolean) (the codomain of pr)"),
    ("n = 3", "1:1", "n is a controlled function, not a monitored one: the inputs give values of monitored "
                     "functions"),
    ("zz = 3", "1:1", "no function zz with 0 argument(s) in S"),
])
def test_a_malformed_input_value_is_a_located_error(tmp_path, capsys, line, where, message):
    path = write(tmp_path, STRUCT)
    inputs = tmp_path / "in.txt"
    inputs.write_text("---\n" + line + "\n")
    assert main(["simulate", path, "-n", "1", "--input", str(inputs)]) == 2
    err = "".join(capsys.readouterr())
    line_no, col = where.split(":")
    assert f"{inputs}:{int(line_no) + 1}:{col}: {message}" in err
