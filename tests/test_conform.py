"""asmcheck against ASMETA's simulator: transcripts in ../shared/asmeta/oracle."""
import os

import pytest

from asmcheck.cli import main
from asmcheck.conform import conform, read_transcript
from asmcheck.errors import AsmError
from asmcheck.semantics.machine import Machine
from asmcheck.semantics.resolve import load_spec

from conftest import need_asmeta
from helpers import spec, write

pytestmark = pytest.mark.engines("none")

# Transcripts asmcheck does not follow, and why (see the issue notes):
KNOWN = {
    # the spec reads Java's wall clock (currTimeNanosecs): no value in a model checker
    "asm_examples/test/simulator/STDL/currentTimeJava.asm",
    # AsmetaS reads a monitored location twice in one step (inside seq it works on a copy of the
    # state) and got two different values; which read took which value is not in the transcript
    "asm_examples/examples/ermts_etcs/scenarios/ertms_hl3_scenario4.asm",
}


def _transcripts(root):
    out = []
    for dp, _, files in os.walk(root / "oracle"):
        for f in files:
            if f.endswith(".trace"):
                rel = os.path.relpath(os.path.join(dp, f), root / "oracle")
                out.append(rel[:-6] + ".asm")
    return sorted(out)


# every transcript, in SHARDS tests over every SHARDS-th one (so that the test workers share them); each
# checks on its transcripts what holds for all of them (which implies it for the whole set)
SHARDS = 4


@pytest.mark.slow
@pytest.mark.parametrize("index", range(SHARDS))
def test_conform_with_every_transcript(index):
    root = need_asmeta()
    ok, bad = [], {}
    mine = _transcripts(root)[index::SHARDS]
    for rel in mine:
        try:
            m = Machine(load_spec(str(root / rel)))
            res = conform(m, read_transcript(str(root / "oracle" / (rel[:-4] + ".trace"))))
        except AsmError as e:
            bad[rel] = str(e)
            continue
        if res is None:
            ok.append(rel)
        else:
            bad[rel] = f"step {res.step}: {res.reason}"
    total = len(ok) + len(bad)
    print(f"\nconform: {len(ok)} of {total} transcripts conform ({100 * len(ok) / total:.1f} %)")
    assert len(ok) / total >= 0.95
    assert set(bad) == KNOWN & set(mine), bad


def test_the_transcript_shards_cover_every_transcript_once_and_the_known_ones():
    root = need_asmeta()
    every = _transcripts(root)
    parts = [every[i::SHARDS] for i in range(SHARDS)]
    assert sorted(t for part in parts for t in part) == every and len(set(every)) == len(every)
    assert KNOWN <= set(every)


def test_conform_command_exit_codes(tmp_path, capsys):
    text = spec("\tenum domain C = {AA | BB}\n\tmonitored m: C\n\tcontrolled x: C", "\tmain rule r_main = x := m")
    path = write(tmp_path, text)
    good = tmp_path / "good.trace"
    good.write_text("# java -jar AsmetaS.jar -n 2 -rnd S.asm\ntaking BB for m\n<State 0 (monitored)>\nm=BB\n"
                    "</State 0 (monitored)>\n<State 1 (controlled)>\nx=BB\n</State 1 (controlled)>\n"
                    "taking AA for m\n<State 2 (controlled)>\nx=AA\n</State 2 (controlled)>\nFinal state:\nx=AA\n")
    assert main(["conform", path, str(good)]) == 0
    assert "conforms (2 step(s) checked)" in capsys.readouterr().out
    bad = tmp_path / "bad.trace"
    bad.write_text("taking BB for m\n<State 1 (controlled)>\nx=AA\n</State 1 (controlled)>\n")
    assert main(["conform", path, str(bad)]) == 1
    out = capsys.readouterr().out
    assert "bad.trace:3: step 1 does not conform" in out
    assert "the transcript shows   x=AA" in out and "asmcheck allows        x=BB" in out
    assert main(["conform", path, str(tmp_path / "missing.trace")]) == 2
