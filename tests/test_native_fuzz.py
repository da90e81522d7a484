"""The native engine against the Python engine (the reference) on random small specs
(tests/fuzzgen.py: every rule form, values of every kind, monitored inputs, derived functions,
macro and turbo calls, agents, extend; invariants, step properties, deadlock, CTL and LTL): the whole
``explore --format json`` report must be the same but the timings and the engine's name.  Longer
campaigns: ``python scripts/fuzz_native.py FIRST COUNT --deadlock``.

Engines: both (python is the reference, native is checked)."""
from __future__ import annotations

import contextlib
import io
import json

import pytest

import fuzzgen
from asmcheck.cli import main
from asmcheck.explore.native_build import compiler

pytestmark = [pytest.mark.slow, pytest.mark.engines("native")]

# the seeds (of the first 300) whose specs have the most states within the bound: every feature of
# the generator is among them
SEEDS = (283, 169, 265, 261, 38, 213, 210, 172, 279, 170, 235, 36, 136, 158, 187, 189, 219, 297, 160, 166, 268, 288, 184, 238)
IGNORED = ("seconds", "engine", "compile_seconds", "engine_note")


def explore(path: str, engine: str, more: list[str]) -> tuple[int, dict]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(["explore", path, "--format", "json", "--max-states", "3000", "--engine", engine, *more])
    assert code in (0, 1, 3), err.getvalue()
    return code, json.loads(out.getvalue())


# each seed's spec as the Python engine explores it (states, transitions, verdict): a change of the
# generator changes these (the seeds' specs are then other specs)
EXPECTED = {283: (3000, 11959, "violated"), 169: (2153, 3230, "violated"), 265: (1100, 10795, "violated"),
            261: (1077, 1077, "violated"), 38: (1025, 7175, "violated"), 213: (528, 1256, "violated"),
            210: (513, 2985, "violated"), 172: (307, 1377, "violated"), 279: (257, 2570, "holds"),
            170: (257, 772, "violated"), 235: (196, 792, "violated"), 36: (193, 4609, "violated"),
            136: (161, 1014, "violated"), 158: (160, 944, "violated"), 187: (129, 7178, "violated"),
            189: (96, 564, "violated"), 219: (72, 280, "violated"), 297: (65, 195, "violated"),
            160: (64, 640, "holds"), 166: (40, 66, "violated"), 268: (37, 236, "violated"),
            288: (33, 99, "violated"), 184: (32, 224, "violated"), 238: (29, 110, "holds")}


@pytest.mark.parametrize("seed", SEEDS)
def test_same_report(tmp_path, seed):
    if compiler() is None:
        pytest.skip("no C compiler: the native engine cannot be built here")
    path = tmp_path / f"fz{seed}.asm"
    text, props = fuzzgen.spec_and_props(seed)
    path.write_text(text, encoding="utf-8")
    (tmp_path / f"fz{seed}.prop").write_text(props, encoding="utf-8")
    i = SEEDS.index(seed)
    # every other seed with the deadlock check, every third with its file of step properties
    more = (["--deadlock"] if i % 2 else []) + (["--properties", str(tmp_path / f"fz{seed}.prop")] if i % 3 == 0 else [])
    code, py = explore(str(path), "python", more)
    assert (py["states"], py["transitions"], py["verdict"]) == EXPECTED[seed]
    code_n, nat = explore(str(path), "native", more)
    assert nat["engine"] == "native", nat.get("engine_note")
    assert code_n == code
    assert {k: v for k, v in nat.items() if k not in IGNORED} == {k: v for k, v in py.items() if k not in IGNORED}


def test_the_seeds_cover_every_kind_of_property():
    """The specs of the seeds (with the options above) check invariants, step properties,
    deadlock, run-time errors, CTL and LTL."""
    kinds = set()
    for seed in SEEDS:
        g = fuzzgen.Gen(seed)
        text = g.spec(f"fz{seed}")
        i = SEEDS.index(seed)
        kinds |= {k for k, word in (("invariant", "invariant "), ("ctl", "CTLSPEC"), ("ltl", "LTLSPEC"),
                                    ("justice", "JUSTICE")) if word in text}
        if i % 2:
            kinds.add("deadlock")
        if i % 3 == 0 and "step stp_" in g.prop_file(f"fz{seed}"):
            kinds.add("step")
    assert kinds == {"invariant", "ctl", "ltl", "justice", "deadlock", "step"}
    assert sum(v[0] for v in EXPECTED.values()) == 11524
    assert sum(1 for v in EXPECTED.values() if v[2] == "violated") == 21
