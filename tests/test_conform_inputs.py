"""conform: what is and is not a transcript, and reals counted by either ASMETA build."""
import os

from asmcheck.cli import main
from asmcheck.conform import conform, read_transcript, real_text

from helpers import machine, spec, write
import pytest

pytestmark = pytest.mark.engines("none")

SPEC = spec("\tenum domain C = {AA | BB}\n\tmonitored m: C\n\tcontrolled x: C", "\tmain rule r_main = x := m")


def test_a_file_that_is_not_a_transcript_is_an_input_error(tmp_path, capsys):
    path = write(tmp_path, SPEC)
    empty = tmp_path / "empty.trace"
    empty.write_bytes(b"")
    noise = tmp_path / "noise.trace"
    noise.write_bytes(bytes(range(256)) * 8)
    words = tmp_path / "passwd"
    words.write_text("root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n")
    for bad in (empty, noise, words):
        assert main(["conform", path, str(bad)]) == 2
        err = capsys.readouterr()
        assert f"{bad}:1:1" in err.out + err.err
        assert "not a transcript of ASMETA's simulator" in err.out + err.err
        assert "conforms" not in err.out
    assert main(["conform", path, str(tmp_path)]) == 2
    msg = "".join(capsys.readouterr())
    assert "not a regular file" in msg or "is a folder, not a transcript" in msg
    # a run of 0 steps is a transcript
    zero = tmp_path / "zero.trace"
    zero.write_text("# java -jar AsmetaS.jar -n 0 S.asm\nFinal state:\n")
    assert main(["conform", path, str(zero)]) == 0
    assert "conforms (0 step(s) checked)" in capsys.readouterr().out


def test_reals_of_an_interval_conform_whichever_way_asmeta_counted_them(tmp_path):
    # older AsmetaS builds add the step in doubles ({-0.8 : 0.8} = {-0.8, 0.19999999999999996}), newer
    # ones in decimal ({-0.8, 0.2}); asmcheck counts in decimal and accepts both transcripts
    assert real_text("(0.19999999999999996,VALID)") == "(0.2,VALID)" == real_text("(0.2,VALID)")
    assert real_text("0.7999999999999999") == real_text("0.8") and real_text("X0.5") == "X0.5"
    m = machine(tmp_path, spec("\tdomain D subsetof Real\n\tmonitored r: D\n\tcontrolled y: Real",
                               "\tdomain D = {-0.8 : 0.8}\n\tmain rule r_main = y := r"))
    for shown in ("0.19999999999999996", "0.2"):
        t = tmp_path / "r.trace"
        t.write_text(f"taking {shown} for r\n<State 1 (controlled)>\ny={shown}\n</State 1 (controlled)>\n")
        assert conform(m, read_transcript(str(t))) is None
    t.write_text("taking 0.3 for r\n<State 1 (controlled)>\ny=0.3\n</State 1 (controlled)>\n")
    assert conform(m, read_transcript(str(t))) is not None


UNDEF_RANGE = spec("\tcontrolled outs: Integer -> Powerset(Integer)\n\tcontrolled x: Integer",
                   "\tmain rule r_main =\n\t\tchoose $k in {1, 2} with true do\n"
                   "\t\t\tchoose $t in outs($k) with $t > 0 do x := $t ifnone x := 99",
                   "\tfunction outs($i in Integer) = if $i = 1 then {5} else undef endif\n\tfunction x = 0")


def test_choose_over_an_undef_range(tmp_path):
    # AsmetaS (RuleEvaluator.evaluateRanges) casts the range's value to a collection: over undef the
    # run stops with an error.  asmcheck stops with a located error where the step takes that branch;
    # following a transcript, a branch that fails is not the step the simulator made (its run went on)
    from asmcheck.errors import AsmRuntimeError
    from asmcheck.semantics.machine import ScriptChooser
    import pytest
    m = machine(tmp_path, UNDEF_RANGE)
    t = tmp_path / "u.trace"
    t.write_text("<State 1 (controlled)>\nouts(1)={5}\nx=5\n</State 1 (controlled)>\n")
    assert conform(m, read_transcript(str(t))) is None
    with pytest.raises(AsmRuntimeError) as info:
        m.successors(m.initial_state())
    assert info.value.message == "the range of $t is undef"
    assert (info.value.span.line, info.value.span.col) == (9, 17)
    assert [(c.kind, c.value) for c in info.value.choices] == [("choose", {"$k": 2})]
    st = m.initial_state()
    _, nxt, _ = m.step(st, ScriptChooser([0]))
    assert [v for k, v in nxt.items() if k == m.fname.index("x")] == [5]


def test_a_choose_over_integer_or_real_conforms_with_the_value_the_simulator_drew(tmp_path):
    # AsmetaS draws a random value for a choose over Integer, Natural or Real (guard true): the
    # transcript shows it through the locations the body updates
    m = machine(tmp_path, spec("\tcontrolled foo: Integer\n\tcontrolled r: Real",
                               "\tmain rule r_main = par\n\t\tchoose $s in Integer with true do foo := $s\n"
                               "\t\tchoose $q in Real with true do r := $q\n\tendpar", "\tfunction foo = 1"))
    t = tmp_path / "c.trace"
    t.write_text("<State 1 (controlled)>\nfoo=-1234567\nr=0.4411\n</State 1 (controlled)>\n"
                 "<State 2 (controlled)>\nfoo=99\nr=0.5\n</State 2 (controlled)>\n")
    assert conform(m, read_transcript(str(t))) is None
    t.write_text("<State 1 (controlled)>\nfoo=7\nr=abc\n</State 1 (controlled)>\n")
    res = conform(m, read_transcript(str(t)))
    assert (res.step, res.location, res.expected, res.allowed) == (1, "r", "abc", ["0.0"])
