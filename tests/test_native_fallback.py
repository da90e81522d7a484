"""What the searches do where the fast path ends: a failing step in the partitioned search, the
time limit of the check that recovers a failing state's errors, the refusal of a state with too
many sequences of choices, the time-limit reason, the memory bound of the hand-over, the advice
on an unbounded input and a Ctrl-C at start-up.

Engines: both (each test names the one it pins)."""
from __future__ import annotations

import json
import re

import pytest

from asmcheck.explore.bfs import Explorer
from asmcheck.parallel import explore_partitioned
from asmcheck.props import spec_properties
from asmcheck.props.load import load_machine
from helpers import warm_native, write
from test_error_graph import HALT, STUCK
from test_native_errors import BRANCHY, cli, too_many


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


# ----------------------------------------------------------------- 2. the check of the failing states' errors
def slow_errors(states: int = 40, inputs: int = 12) -> str:
    """A step fails in every state but the last (n := n + 1 beside n := 0) when the nested equality
    of ``inputs`` monitored booleans is true; the Python step function reads all of them in each
    state: 2^inputs sequences of choices, from each of the failing states."""
    mons = "\n".join(f"\tmonitored b{i}: Boolean" for i in range(inputs))
    cond = "b0"
    for i in range(1, inputs):
        cond = f"({cond} = b{i})"
    return f"""asm SlowErrors
import StandardLibrary
signature:
	domain Count subsetof Integer
	controlled n: Count
{mons}
definitions:
	domain Count = {{0 : {states}}}
	invariant inv_n over n: n <= {states}
	main rule r_main =
		par
			if n < {states} then n := n + 1 else n := 0 endif
			if {cond} then n := 0 endif
		endpar
default init s0:
	function n = 0
"""


@pytest.mark.engines("native")
def test_the_check_of_the_failing_states_keeps_to_the_time_limit(tmp_path):
    """The native search ends soon; the Python step function then recovers the error of the state
    the report shows (state 0: the other 39 failing states are not looked at without a graph),
    65,536 sequences of choices (seconds): --max-seconds 3 ends that check too, incomplete, saying
    where it stopped."""
    from asmcheck.explore.native_build import compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    path = write(tmp_path, slow_errors(40, 16))
    warm_native(path, "--format", "json")
    code, doc = json_report(path, "--max-seconds", 3)
    assert (code, doc["verdict"], doc["states"], doc["transitions"], doc["violations"]) == (3, "incomplete", 41, 41, [])
    assert doc["incomplete"] == ("time limit 3.0 s reached while the Python step function recovered the errors of the "
                                 "states where a step fails (0 of 1 checked, after a search of 41 states)")
    # without a limit the same check finds the error of state 0 (a smaller space: 2^4 choices)
    code, doc = json_report(write(tmp_path, slow_errors(40, 4)))
    assert (code, doc["verdict"], [v["property"] for v in doc["violations"]]) == (1, "violated", ["error"])


# ----------------------------------------------------------------- 4. the time-limit reason in fields
@pytest.mark.engines("python", "native")
@pytest.mark.parametrize("engine", ["python", "native"])
def test_the_time_limit_reason_has_fields_and_names_the_whole_commands_limit(tmp_path, engine):
    """The search had what was left of the command's 1.5 s (0.5 s went before it): the reason names
    the command's limit, written from its fields by TimeLimit.text()."""
    import time as clock

    import asmcheck
    from asmcheck.explore.bfs import TimeLimit
    if engine == "native":
        from asmcheck.explore.native_build import compiler
        if compiler() is None:
            pytest.skip("no C compiler: the native explorer cannot run here")
    assert TimeLimit(30.0, ", while X").text() == "time limit 30.0 s reached, while X"
    assert TimeLimit().text() == "time limit reached"
    # (65,536 sequences of choices from each state: the error of state 0 takes the Python step
    # function seconds to recover)
    model = asmcheck.load(write(tmp_path, slow_errors(40, 16)))
    run = model.explore(engine=engine, max_seconds=1.5, started=clock.perf_counter() - 0.5)
    stop = run.result.time_limit
    # (the Python engine may have found the error of state 0 by then: violated, yet stopped early)
    assert (run.result.stopped_early, stop.seconds, run.reason) == (True, 1.5, stop.text())
    assert run.reason.startswith("time limit 1.5 s reached")


# ----------------------------------------------------------------- 3. a state with too many choices, refused at once
def many_inputs(n: int) -> str:
    """The step reads ``n`` monitored booleans from the initial state (2^n sequences of choices)."""
    mons = "\n".join(f"\tmonitored b{i}: Boolean\n\tcontrolled f{i}: Boolean" for i in range(n))
    ups = "\n".join(f"\t\t\tf{i} := b{i}" for i in range(n))
    inits = "\n".join(f"\tfunction f{i} = false" for i in range(n))
    return f"""asm ManyInputs
import StandardLibrary
signature:
{mons}
definitions:
	main rule r_main =
		par
{ups}
		endpar
default init s0:
{inits}
"""


@pytest.mark.engines("native")
def test_a_state_with_more_than_a_million_sequences_of_choices_is_refused_before_its_enumeration(tmp_path):
    """21 monitored booleans: 2,097,152 sequences of choices from the initial state.  The product of
    the first run's choice sizes refuses the state at once; before, the native search ran a million
    of them first (with a time limit of 0 s it stopped on it after 4,096, the Python engine left no
    time).  20 booleans (1,048,576) are refused too, and 19 (524,288) are enumerated."""
    from asmcheck.explore.native import NativeExplorer, Unsupported
    from asmcheck.explore.native_build import compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    for n in (21, 20):
        _, m = load_machine(write(tmp_path, many_inputs(n)))
        with pytest.raises(Unsupported, match=r"^more than 1,000,000 sequences of choices from one state"):
            NativeExplorer(m, max_seconds=0).run()
    _, m = load_machine(write(tmp_path, many_inputs(4)))
    r = NativeExplorer(m).run()
    assert (r.states, r.transitions, r.verdict) == (16, 256, "holds")


# ----------------------------------------------------------------- 5. the memory bound of the edges
@pytest.mark.engines("native")
def test_the_memory_bound_counts_the_edge_arrays_as_they_are_stored(tmp_path):
    """With the graph kept, the search's tables count the two arrays of edge ends as allocated (4,096
    ends each at first) and the one array Python copies into at the hand-over: 2 x 4 x 4,096 + 4 x
    edges bytes more than the same search without the graph (it counted 5 x 4 bytes an edge)."""
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.explore.native_build import compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    _, m = load_machine(write(tmp_path, BRANCHY))
    plain = NativeExplorer(m)          # (no property: both searches cover every state)
    r = plain.run()
    without = plain.dll.asm_memory_bytes()
    graph = NativeExplorer(m, keep_graph=True)
    seen = []
    take = graph._take_edges

    def measured(n):
        seen.append((graph.dll.asm_memory_bytes(), n))
        take(n)
    graph._take_edges = measured
    rg = graph.run()
    (with_graph, edges), = seen
    assert (r.states, rg.states, edges, len(graph.edge_src)) == (25, 25, 100, 100)
    assert with_graph - without == 2 * 4 * 4096 + 4 * edges


# ----------------------------------------------------------------- 6. the advice on an unbounded input
SET_INPUTS = """asm SetInputs
import StandardLibrary
signature:
	domain Coord subsetof Integer
	domain Position subsetof Prod(Coord, Coord)
	domain Small subsetof Integer
	monitored chargers: Powerset(Position)
	monitored picks: Powerset(Small)
	controlled count: Integer
definitions:
	domain Coord = {-10000 : 10000}
	domain Small = {1 : 3}
	main rule r_main =
		if count < 2 then count := count + size(chargers) + size(picks) endif
default init s0:
	function count = 0
"""


@pytest.mark.engines("python")
def test_the_advice_on_a_set_valued_input_is_a_form_monitored_reads(tmp_path, monkeypatch):
    """chargers ranges over Powerset(Position), 400,040,001 positions: the message comes at once
    (the product's size is worked out from its factors, not by making its elements) and suggests
    set values, not LO..HI; the values it suggests are read (and a finite set codomain takes its
    values written with or without blanks)."""
    path = write(tmp_path, SET_INPUTS)
    code, out, err = cli("explore", path, "--engine", "python")
    assert code == 2 and out == ""
    assert ("SetInputs.asm:7:12: monitored function chargers ranges over Powerset(Position), which is infinite or "
            "too large to enumerate: give its values with --monitored 'chargers={(0, 0)},...' (values of "
            "Powerset(Position), written as asmcheck prints them)") in err
    assert "LO..HI" not in err
    code, doc = json_report(path, "--engine", "python", "--monitored", "chargers={},{(0, 0)},{(1,2), (3, 4)}",
                            "--monitored", "picks={},{1,3}")
    # count 0 and 1 step by 0..4 (set sizes 0, 1, 2 plus 0, 2): states 0..5, 5 + 5 + 4 self-loops
    assert (code, doc["states"], doc["transitions"]) == (0, 6, 14)
    code, out, err = cli("explore", path, "--monitored", "chargers={(0, 0)}", "--monitored", "picks={4}")
    assert code == 2 and "--monitored picks: '{4}' is not a value of picks's codomain Powerset(Small)" in err


@pytest.mark.engines("python")
@pytest.mark.parametrize("kind, hint", [
    ("Integer", "--monitored x=LO..HI (or --int-range LO..HI)"),
    ("Real", "--monitored x=V1,V2,... (real numbers)"),
    ("String", '--monitored x="a","b",...'),
    ("Seq(Integer)", "--monitored 'x=[0],...' (values of Seq(Integer), written as asmcheck prints them)"),
    ("Prod(Integer, Boolean)", "--monitored 'x=(0, true),...' (values of Prod(Integer,Boolean), written as "
                               "asmcheck prints them)"),
])
def test_the_advice_fits_every_kind_of_domain(tmp_path, kind, hint):
    text = f"""asm K
import StandardLibrary
signature:
	monitored x: {kind}
	controlled y: {kind}
definitions:
	main rule r_main = y := x
"""
    code, out, err = cli("explore", write(tmp_path, text), "--engine", "python")
    assert code == 2 and f"give its values with {hint}" in err, err


# ----------------------------------------------------------------- 8. Ctrl-C while the program starts
@pytest.mark.engines("python")
def test_a_ctrl_c_at_any_moment_of_the_start_up_ends_with_a_message_and_exit_code_3(tmp_path):
    """SIGINT at 12 moments of the first 0.6 s of `python -m asmcheck explore` (the imports, the
    parser, the search): never a traceback of the program.  Before, a Ctrl-C during the imports
    printed one (and exited 1 or by the signal) in about 4 runs out of 5."""
    import os
    import signal
    import subprocess
    import sys
    import time
    from pathlib import Path
    from test_adversarial_cli import COUNTER, INTERPRETER_START, sigint_default
    root = Path(__file__).resolve().parent.parent
    env = dict(os.environ, PYTHONPATH=str(root))
    path = write(tmp_path, COUNTER)
    ends = []
    for i in range(12):
        argv = [sys.executable, "-m", "asmcheck", "explore", path, "--engine", "python"]
        proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=tmp_path,
                                preexec_fn=sigint_default)
        try:
            time.sleep(0.05 * i)
            proc.send_signal(signal.SIGINT)
            out, err = proc.communicate(timeout=120)
        finally:
            if proc.poll() is None:     # (the counter never stops: a run the signal missed is ended here)
                proc.kill()
                proc.communicate()
        if proc.returncode == 1 and err.startswith(INTERPRETER_START):
            ends.append("interpreter")          # before any line of the program: the interpreter's own
            continue
        assert "Traceback" not in out + err, err
        if proc.returncode == -signal.SIGINT:
            assert out == err == ""             # before the interpreter's own handler: killed, silently
            ends.append("killed")
        elif out == "":
            assert (proc.returncode, err) == (3, "asmcheck: interrupted before any result\n")
            ends.append("starting")
        else:
            assert proc.returncode == 3 and "verdict: incomplete" in out, out
            ends.append("searching")
    assert "starting" in ends or "searching" in ends


# ----------------------------------------------------------------- 9. the time left after a hand-over
@pytest.mark.engines("native")
def test_a_search_handed_over_to_the_python_engine_gets_the_time_left(tmp_path, monkeypatch):
    """A native search that stops on something it does not handle has spent part of --max-seconds:
    the Python engine's search gets what is left of the whole command's limit, not all of it again."""
    import time

    import asmcheck
    from asmcheck.explore import bfs
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.explore.native_build import Unsupported, compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    path = write(tmp_path, slow_errors(4, 2))
    warm_native(path)

    def refuse_late(self):
        time.sleep(1.5)
        raise Unsupported("a state the test refuses")

    limits = []
    real_init = bfs.Explorer.__init__

    def init(self, *a, **k):
        limits.append(k.get("max_seconds"))
        real_init(self, *a, **k)

    monkeypatch.setattr(NativeExplorer, "run", refuse_late)
    monkeypatch.setattr(bfs.Explorer, "__init__", init)
    res = asmcheck.load(path).explore(engine="auto", max_seconds=4)
    assert res.engine == "python" and res.engine_note == "a state the test refuses"
    assert len(limits) == 1 and limits[0] is not None and limits[0] <= 2.5
