"""A state limit below 1 is a usage error, alike on every engine, with workers, in the gate and in
the API: the initial states are always found, so --max-states 0 cannot stop before them (it
explored the first state and its successors, as --max-states 1 does, and called that 'state limit 0
reached'); --max-depth 0 is the way to check the initial states alone."""
from __future__ import annotations

import pytest

import asmcheck
from asmcheck.cli import main

pytestmark = pytest.mark.engines("native")

SPEC = "specs/sb_async_master.asm"
HINT = " (the initial states are always explored; --max-depth 0 checks them alone)"
RUNS = [["explore", "--engine", "python"], ["explore", "--engine", "native"], ["explore", "--workers", "2"],
        ["check"], ["advise"], ["testgen"]]


@pytest.fixture
def spec(monkeypatch):
    from pathlib import Path
    monkeypatch.chdir(Path(__file__).resolve().parent.parent)
    return SPEC


@pytest.mark.parametrize("run", RUNS, ids=lambda r: " ".join(r))
@pytest.mark.parametrize("value, message", [("0", "--max-states must be 1 or more, not 0" + HINT),
                                            ("-1", "--max-states must be 1 or more, not -1")],
                         ids=["zero", "negative"])
def test_a_state_limit_below_one_is_a_usage_error(spec, capsys, run, value, message):
    assert main([run[0], spec, *run[1:], "--max-states", value]) == 2
    assert capsys.readouterr() == ("", f"asmcheck: error: {message}\n")


@pytest.mark.parametrize("run", RUNS[:4], ids=lambda r: " ".join(r))
def test_a_negative_depth_limit_is_a_usage_error(spec, capsys, run):
    assert main([run[0], spec, *run[1:], "--max-depth", "-1"]) == 2
    assert capsys.readouterr() == ("", "asmcheck: error: --max-depth must be 0 or more\n")


@pytest.mark.parametrize("run", RUNS[:3], ids=lambda r: " ".join(r))
def test_a_state_limit_of_one_and_a_depth_limit_of_zero_on_every_engine(spec, capsys, run):
    # the first state is expanded before the limit of 1 is met (its successors are counted);
    # a depth limit of 0 explores the initial state alone
    main([run[0], spec, *run[1:], "--max-states", "1"])
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith("sb_async_master.asm: 3 states, 2 transitions, depth 1, "), first
    main([run[0], spec, *run[1:], "--max-depth", "0"])
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith("sb_async_master.asm: 1 states, 0 transitions, depth 0, "), first


@pytest.mark.parametrize("engine", ["python", "native"])
def test_the_api_refuses_a_state_limit_below_one(spec, engine):
    model = asmcheck.load(spec)
    with pytest.raises(asmcheck.UsageError) as e:
        model.explore(engine=engine, max_states=0)
    assert str(e.value) == "max_states must be 1 or more, not 0 (the initial states are always explored; " \
                           "max_depth=0 checks them alone)"
    with pytest.raises(asmcheck.UsageError) as e:
        model.explore(engine=engine, max_states=-4)
    assert str(e.value) == "max_states must be 1 or more, not -4"
    with pytest.raises(asmcheck.UsageError) as e:
        asmcheck.check([spec], engine=engine, max_states=0)
    assert str(e.value).startswith("max_states must be 1 or more, not 0")
