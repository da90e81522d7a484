"""What the searches do where the fast path ends: a failing step in the partitioned search, the
time limit of the check that recovers a failing state's errors, the refusal of a state with too
many sequences of choices, the time-limit reason, the memory bound of the hand-over, the advice
on an unbounded input and the monitored values a trace prints.

Engines: both (each test names the one it pins)."""
from __future__ import annotations

import contextlib
import io
import json

import pytest

from asmcheck.cli import main
from asmcheck.explore.bfs import Explorer
from asmcheck.parallel import explore_partitioned
from asmcheck.props import spec_properties
from asmcheck.props.load import load_machine
from helpers import write
from test_error_graph import HALT, STUCK
from test_native_errors import BRANCHY, too_many


def cli(*args) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in args])
    return code, out.getvalue(), err.getvalue()


def json_report(*args) -> tuple[int, dict]:
    code, out, _ = cli("explore", *args, "--format", "json")
    doc = json.loads(out)
    for k in ("seconds", "compile_seconds", "workers", "engine"):
        doc.pop(k, None)
    return code, doc


def sequential_summary(ex, r):
    return (r.states, r.transitions, r.depth, r.verdict, r.reason,
            [(v.prop.name, v.state, v.source, v.message) for v in r.violations],
            [(s, p, e.message, str(e.span)) for s, p, e in ex.error_edges],
            [ex.parent[i] for i in range(r.states)])


# ----------------------------------------------------------------- 1. the partitioned search past a failing step
@pytest.mark.engines("python", "native")
@pytest.mark.parametrize("text", [HALT, STUCK, BRANCHY], ids=["halt", "stuck", "branchy"])
@pytest.mark.parametrize("expander", ["python", "native"])
def test_the_partitioned_search_goes_on_past_a_failing_step(tmp_path, text, expander):
    """The partitioned search itself keeps a failing state's well-defined successors and records
    every failing branch: the sequential search's states, parents, transitions, violations and
    failing branches (the graph kept, for the temporal halts), for 1, 2 and 3 partitions, on the
    Python and on the compiled step function."""
    if expander == "native":
        from asmcheck.explore.native_build import compiler
        if compiler() is None:
            pytest.skip("no C compiler: the native expander cannot run here")
    _, m = load_machine(write(tmp_path, text))
    sp, stp = spec_properties(m)
    for deadlock in (False, True):
        seq = Explorer(m, state_props=sp, step_props=stp, keep_graph=True, deadlock=deadlock)
        want = sequential_summary(seq, seq.run())
        assert want[6], "the spec has a failing branch"
        for workers in (1, 2, 3):
            ex, r = explore_partitioned(m, workers=workers, backend="inline", state_props=sp, step_props=stp,
                                        keep_graph=True, deadlock=deadlock, expander=expander)
            assert r.engine == expander
            assert sequential_summary(ex, r) == want, (workers, deadlock)


@pytest.mark.engines("python", "native")
@pytest.mark.parametrize("text", [HALT, BRANCHY], ids=["halt", "branchy"])
def test_the_report_of_a_failing_step_is_the_same_for_any_number_of_worker_processes(tmp_path, text,
                                                                                       monkeypatch):
    """explore --workers N on the Python engine (worker processes) gives the one-process report,
    JSON and text, byte for byte (but the workers' count), without running the search again on one
    worker; the native one-process report is the same but for the engine's name."""
    path = write(tmp_path, text)
    monkeypatch.chdir(tmp_path)
    for more in ([], ["--deadlock"]):
        code, one = json_report(path, "--engine", "python", *more)
        assert "scaling_note" not in one
        for workers in (2, 3):
            assert json_report(path, "--engine", "python", "--workers", workers, *more) == (code, one)
        assert json_report(path, *more) == (code, one)
        _, t1, _ = cli("explore", path, "--engine", "python", *more)
        _, t3, _ = cli("explore", path, "--engine", "python", "--workers", 3, *more)
        assert t1.splitlines()[1:] == t3.splitlines()[1:]
        assert "ran again on one worker" not in t3


@pytest.mark.engines("python")
def test_the_partitioned_search_stops_where_the_sequential_one_meets_too_many_choices(tmp_path, monkeypatch):
    """An error in the initial state, then a state whose step has 2^20 sequences of choices, more
    than the bound (lowered to 5,000 here): the sequential search stops there, incomplete, naming
    the choices; so does the partitioned one."""
    monkeypatch.setattr(Explorer, "MAX_SUCCESSORS", 5_000)
    _, m = load_machine(write(tmp_path, too_many()))
    sp, stp = spec_properties(m)
    seq = Explorer(m, state_props=sp, step_props=stp, keep_graph=True)
    want = sequential_summary(seq, seq.run())
    assert want[:5] == (2, 1, 1, "violated", want[4]) and want[4].startswith(
        "more than 5,000 successors of one state: the step chooses among b0 (2 values)")
    for workers in (1, 2):
        ex, r = explore_partitioned(m, workers=workers, backend="inline", state_props=sp, step_props=stp,
                                    keep_graph=True)
        assert sequential_summary(ex, r) == want
