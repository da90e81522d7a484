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


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    if compiler() is None:
        pytest.skip("no C compiler: the native engine cannot be built here")
    folder = tmp_path_factory.mktemp("fuzz")
    out = {}
    for seed in SEEDS:
        path = folder / f"fz{seed}.asm"
        text, props = fuzzgen.spec_and_props(seed)
        path.write_text(text, encoding="utf-8")
        (folder / f"fz{seed}.prop").write_text(props, encoding="utf-8")
        i = SEEDS.index(seed)
        # every other seed with the deadlock check, every third with its file of step properties
        more = (["--deadlock"] if i % 2 else []) + (["--properties", str(folder / f"fz{seed}.prop")] if i % 3 == 0 else [])
        out[seed] = (explore(str(path), "python", more), explore(str(path), "native", more))
    return out


@pytest.mark.parametrize("seed", SEEDS)
def test_same_report(reports, seed):
    (code, py), (code_n, nat) = reports[seed]
    assert nat["engine"] == "native", nat.get("engine_note")
    assert code_n == code
    assert {k: v for k, v in nat.items() if k not in IGNORED} == {k: v for k, v in py.items() if k not in IGNORED}


def test_the_specs_explore_something(reports):
    """The generator's specs as the Python engine explores them (a change of the generator changes
    these: the seeds' specs are then other specs)."""
    states = [py["states"] for (_, py), _ in reports.values()]
    verdicts = sorted(py["verdict"] for (_, py), _ in reports.values())
    kinds = sorted({p["kind"] for (_, py), _ in reports.values() for p in py["properties"]})
    assert (sum(states), max(states)) == EXPECTED_STATES
    assert kinds == ["ctl", "deadlock", "error", "invariant", "ltl", "step"]
    assert verdicts.count("violated") == EXPECTED_VIOLATED


EXPECTED_STATES = (11524, 3000)
EXPECTED_VIOLATED = 21
