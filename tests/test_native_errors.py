"""The native engine past a step that fails.

Where a branch of a state's step fails at run time (an inconsistent update, a value outside its
domain), the native search records the branch and goes on with the state's well-defined successors,
as the Python explorer does (docs/run-time-errors.md): the same states, transitions, edges,
violations, failing branches (``error_edges``: state, choices, the error with its message and span)
and so the same verdicts relative to the error, traces, --deadlock and --graph.  The errors
themselves are made by the Python step function from each state where the native search saw a step
fail; it must make the successors the native search made there, or the run goes to the Python
engine with that reason.

Engines: both (python is the reference, native is checked)."""
from __future__ import annotations

import contextlib
import io
import json
import sys
from pathlib import Path

import pytest

from asmcheck.cli import main
from asmcheck.explore.bfs import Explorer
from asmcheck.explore.native import NativeExplorer, Unsupported
from asmcheck.explore.native_build import compiler
from asmcheck.props import spec_properties
from asmcheck.props.load import load_machine
from conftest import ASMETA, need_asmeta
from helpers import write
# HALT: a failing branch that depends on a monitored value; STUCK: every step from n = 1 fails
from test_error_graph import HALT, STUCK

pytestmark = pytest.mark.engines("native")


@pytest.fixture(autouse=True)
def _need_compiler():
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")


# several failing branches in one state, between well-defined ones: a choose, then a monitored
# value; x = 1 with go clashes on n (unless n + 1 is 0 mod 5), x = 2 with go in n = 3 puts 7 in m
BRANCHY = """asm Branchy
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	controlled m: Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 4}
	invariant inv_n over n: n < 4
	main rule r_main =
		choose $x in {0, 1, 2} with true do
			par
				n := ($x + n) mod 5
				if $x = 1 and go then n := 0 endif
				if $x = 2 and n = 3 and go then m := 7 endif
				if $x = 0 and go then m := (m + 1) mod 5 endif
			endpar
default init s0:
	function n = 0
	function m = 0
"""

# INVAR excludes go = true: the failing branch (go true in n = 1) is no step of the model, so the
# Python engine reports no error; the native search saw the step fail and hands the run over
INVAR_HIDES = """asm InvarHides
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 3}
	INVAR not go
	invariant inv_small over n: n < 3
	main rule r_main =
		par
			if n < 3 then n := n + 1 endif
			if go and n = 1 then n := 0 endif
		endpar
default init s0:
	function n = 0
"""


def engines(tmp_path, text, **kw):
    """(machine, Python explorer and result, native explorer and result), both run with ``kw``."""
    _, m = load_machine(write(tmp_path, text))
    state_props, step_props = spec_properties(m)
    py = Explorer(m, state_props=state_props, step_props=step_props, **kw)
    pres = py.run()
    nat = NativeExplorer(m, state_props=state_props, step_props=step_props, **kw)
    nres = nat.run()
    return m, py, pres, nat, nres


def violations(res):
    return [(v.prop.name, v.state, v.source, v.picks, v.message, str(getattr(v.prop, "span", "") or ""))
            for v in res.violations]


def failing(ex):
    return [(s, p, e.message, str(e.span)) for s, p, e in ex.error_edges]


def distinct_edges(edges):
    """The (src, dst) pairs of the Python explorer's edges (every enumerated step), each once per
    source, in the order first met: the native engine's edges."""
    seen, out = set(), []
    for a, b, _ in edges:
        if (a, b) not in seen:
            seen.add((a, b))
            out.append((a, b))
    return out


def same_search(py, pres, nat, nres):
    assert nres.engine == "native"
    assert (nres.verdict, nres.states, nres.transitions, nres.depth, nres.reason) == \
        (pres.verdict, pres.states, pres.transitions, pres.depth, pres.reason)
    assert [nat.state(s) for s in range(nres.states)] == [py.state(s) for s in range(pres.states)]
    assert list(nat.parent) == list(py.parent)
    assert violations(nres) == violations(pres)


def test_halt_the_well_defined_successors_of_the_failing_state_are_explored(tmp_path):
    m, py, pres, nat, nres = engines(tmp_path, HALT, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.depth, nres.verdict, nres.reason) == (4, 4, 3, "violated", "")
    src, dst = nat.edge_arrays()
    assert list(zip(src, dst)) == [(0, 1), (1, 2), (2, 3), (3, 3)] == distinct_edges(py.edges)
    # go true in n = 1 fails: one failing branch, with the choices of its step (go's position)
    at = f"{tmp_path / 'Halt.asm'}:19:25"
    assert failing(nat) == [(1, (1,), "inconsistent update of n: 2 and 0", at)] == failing(py)
    assert [(v[0], v[1], v[4]) for v in violations(nres)] == [
        ("error", 1, "inconsistent update of n: 2 and 0"), ("inv_small", 3, "")]
    assert nres.violations[0].prop.span == pres.violations[0].prop.span
    # the edges with their choices, as --graph writes them: the failing branch is no edge
    assert nat.graph_edges() == py.edges


def test_halt_without_the_graph_the_error_is_not_one_of_the_properties(tmp_path):
    # the search does not stop once the one invariant and the error are violated: the error is no
    # property, so the invariant beyond it is still searched for (and found at n = 3)
    _, py, pres, nat, nres = engines(tmp_path, HALT)
    same_search(py, pres, nat, nres)
    assert [v[0] for v in violations(nres)] == ["error", "inv_small"]
    assert (nres.states, nres.transitions, nres.reason) == (4, 4, "")
    assert nat.error_edges == [] == py.error_edges


def test_a_state_whose_every_step_fails_is_no_deadlock(tmp_path):
    _, py, pres, nat, nres = engines(tmp_path, STUCK, deadlock=True, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions) == (2, 1)
    assert [v[0] for v in violations(nres)] == ["error"]
    assert [(s, p, msg) for s, p, msg, _ in failing(nat)] == [(1, (), "inconsistent update of n: 2 and 0")]
    assert failing(nat) == failing(py)


def test_several_failing_branches_between_well_defined_ones(tmp_path):
    m, py, pres, nat, nres = engines(tmp_path, BRANCHY, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.depth) == (25, 100, 6)
    assert list(zip(*nat.edge_arrays())) == distinct_edges(py.edges)
    assert nat.graph_edges() == py.edges
    got = failing(nat)
    assert got == failing(py)
    assert (len(got), len({s for s, _, _, _ in got})) == (25, 20)
    # the failing branch of the initial state (n = 0, m = 0): x = 1 with go true (the step function
    # merges the choose's alternatives with go's values: one choice of six outcomes)
    path = str(tmp_path / "Branchy.asm")
    assert got[0] == (0, (3,), "inconsistent update of n: 1 and 0", f"{path}:15:27")
    # and of the first state with n = 3: x = 1 (a clash) and x = 2 (7 is not in Small), with go true
    n = next(f for f in m.spec.functions if f.name == "n").index
    three = next(i for i in range(nres.states) if nat.state(i)[n] == 3)
    assert [(p, msg, at.rsplit(":", 2)[1:]) for s, p, msg, at in got if s == three] == [
        ((3,), "inconsistent update of n: 4 and 0", ["15", "27"]),
        ((5,), "value out of domain: 7 is not in Small (the codomain of m)", ["16", "37"])]
    assert [(v[0], v[1]) for v in violations(nres)] == [("error", 0), ("inv_n", 8)]


def test_several_workers_give_the_same_result(tmp_path, monkeypatch):
    # every level on the threads (a level of fewer than 8 states runs on one by default)
    monkeypatch.setenv("ASMCHECK_THREAD_MIN_CHUNK", "1")
    _, m = load_machine(write(tmp_path, BRANCHY))
    state_props, step_props = spec_properties(m)
    one = NativeExplorer(m, state_props=state_props, keep_graph=True)
    r1 = one.run()
    e1 = (list(one.parent), list(zip(*one.edge_arrays())), failing(one), violations(r1))
    one.close()
    two = NativeExplorer(m, state_props=state_props, keep_graph=True, workers=2)
    two.threaded = True
    two.adapt = False
    r2 = two.run()
    assert two.thread_stats()["parallel_chunks"] > 0
    assert (r2.states, r2.transitions, r2.depth) == (r1.states, r1.transitions, r1.depth) == (25, 100, 6)
    assert (list(two.parent), list(zip(*two.edge_arrays())), failing(two), violations(r2)) == e1


def cli(*args) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in args])
    return code, out.getvalue(), err.getvalue()


def json_report(*args) -> tuple[int, dict]:
    code, out, _ = cli("explore", *args, "--format", "json")
    doc = json.loads(out)
    doc.pop("seconds")
    doc.pop("compile_seconds")
    return code, doc


def both_reports(*args) -> dict:
    """The JSON report of the auto engine (which must be the native one) and the Python engine's
    are the same but for the engine's name; returns the native one."""
    code_n, nat = json_report(*args)
    code_p, py = json_report(*args, "--engine", "python")
    assert (nat.pop("engine"), nat.pop("engine_note", None)) == ("native", None)
    assert py.pop("engine") == "python"
    assert (code_n, nat) == (code_p, py)
    return nat


@pytest.mark.parametrize("more", [[], ["--deadlock"]])
def test_the_json_report_relative_to_the_error_is_the_python_engines(tmp_path, more, monkeypatch):
    write(tmp_path, HALT)
    monkeypatch.chdir(tmp_path)
    doc = both_reports("Halt.asm", *more)
    at = "Halt.asm:19:25"
    # with --deadlock: n = 3 steps to itself (the failing state n = 1 is no deadlock)
    assert doc["properties"] == [
        {"property": "inv_small", "kind": "invariant", "verdict": "violated"},
        {"property": "error", "kind": "error", "verdict": "violated"}] + (
        [{"property": "deadlock", "kind": "deadlock", "verdict": "violated"}] if more else []) + [
        {"property": "ltl_1", "kind": "ltl", "verdict": "violated", "relative_to": at},
        {"property": "ltl_2", "kind": "ltl", "verdict": "holds", "relative_to": at},
        {"property": "ctl_1", "kind": "ctl", "verdict": "holds", "relative_to": at},
        {"property": "ctl_2", "kind": "ctl", "verdict": "violated", "relative_to": at}]
    assert [(v["property"], v.get("message")) for v in doc["violations"]] == [
        ("error", "inconsistent update of n: 2 and 0"), ("inv_small", "")] + (
        [("deadlock", "the only successor is the state itself")] if more else []) + [
        ("ltl_1", None), ("ctl_2", None)]
    err = next(v for v in doc["violations"] if v["property"] == "error")
    assert (err["message"], err["location"], err["failing_step"]) == (
        "inconsistent update of n: 2 and 0", {"path": "Halt.asm", "line": 19, "column": 25},
        {"step": 2, "choices": [{"kind": "monitored", "at": "go", "value": True}]})
    assert [s["state"] for s in err["trace"]] == [{"n": 0}, {"n": 1}]


def test_the_text_report_and_the_graph_are_the_python_engines(tmp_path, monkeypatch):
    write(tmp_path, BRANCHY)
    monkeypatch.chdir(tmp_path)
    code_n, out_n, _ = cli("explore", "Branchy.asm", "--graph", "n.dot")
    code_p, out_p, _ = cli("explore", "Branchy.asm", "--graph", "p.dot", "--engine", "python")
    first_n, *rest_n = out_n.splitlines()
    first_p, *rest_p = out_p.splitlines()
    assert first_n.startswith("Branchy.asm: 25 states, 100 transitions, depth 6, ") and first_n.endswith(
        "native engine")
    assert first_p.endswith("python engine")
    assert (code_n, rest_n) == (code_p, rest_p) and code_n == 1
    assert "a step fails (Branchy.asm:15:27): inconsistent update of n: 1 and 0" in out_n
    assert (tmp_path / "n.dot").read_text() == (tmp_path / "p.dot").read_text()


def test_a_failing_branch_the_python_engine_does_not_make_goes_to_the_python_engine(tmp_path):
    _, m = load_machine(write(tmp_path, INVAR_HIDES))
    with pytest.raises(Unsupported, match="a run-time error of the native search that the Python step function "
                                          "does not make"):
        NativeExplorer(m, state_props=spec_properties(m)[0]).run()
    code, doc = json_report(str(tmp_path / "InvarHides.asm"))
    assert (code, doc["engine"], doc["states"], doc["transitions"]) == (1, "python", 4, 4)
    assert doc["engine_note"] == ("native engine not used: a run-time error of the native search that the "
                                  "Python step function does not make")
    assert [v["property"] for v in doc["violations"]] == ["inv_small"]


# the specs with NuSMV verdicts whose steps fail (see tests/test_error_graph.py): states,
# transitions, failing branches (state, choices, message) of the whole graph
CORPUS = {
    "asm_examples/PillBox/Level1/pillbox_1_elia": (1431, 2706, 6, 3, "inconsistent update of redLed: OFF and BLINKING"),
    "asm_examples/stereoacuity/modelReview/certifierGroundWrongGuard": (
        45, 65, 2, 2, "value out of domain: 7 is not in Level (the codomain of levelTest)"),
    "asmeta_models/tutorials/tutorial_FM26/SchedulerInvariant": (28, 113, 42, 13,
                                                                 "inconsistent update of st(JOB1): RUN and FIN"),
}


@pytest.mark.corpus
@pytest.mark.parametrize("rel", sorted(CORPUS))
def test_the_corpus_specs_whose_steps_fail_run_native(rel):
    need_asmeta()
    path = ASMETA / (rel + ".asm")
    states, transitions, branches, where, first = CORPUS[rel]
    _, m = load_machine(str(path))
    py = Explorer(m, keep_graph=True)
    pres = py.run()
    nat = NativeExplorer(m, keep_graph=True)
    nres = nat.run()
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, len(nat.error_edges), len({s for s, _, _ in nat.error_edges})) == (
        states, transitions, branches, where)
    assert failing(nat) == failing(py)
    assert list(zip(*nat.edge_arrays())) == distinct_edges(py.edges)
    assert nres.violations[0].message == first
    # the whole JSON report (its properties and their LTL/CTL verdicts relative to the error,
    # traces), with and without the deadlock check
    for more in ([], ["--deadlock"]):
        both_reports(path, *more)


def test_the_survey_counts_the_engine_that_ran(monkeypatch, tmp_path):
    # a report the Python engine made is no native run, however equal: the survey lists it with
    # the reason the report gives
    sys.path.insert(0, str(Path(__file__).parent))
    import test_native_diff as survey
    reports = {"python": {"spec": "X", "verdict": "holds", "states": 3, "transitions": 2, "engine": "python"},
               "native": {"spec": "X", "verdict": "holds", "states": 3, "transitions": 2, "engine": "python",
                          "engine_note": "native engine not used: a reason"}}

    def fake(args, hard_stop):
        return 0, json.dumps(reports["python" if "python" in args else "native"]), ""
    monkeypatch.setattr(survey, "run_cli", fake)
    spec = tmp_path / "X.asm"
    assert survey.compare(spec) == ("fallback", "a reason")
    share, text = survey.summary({"X.asm": ("fallback", "a reason"), "Y.asm": ("native", "3 states")})
    assert share == 0.5
    assert text.splitlines()[1:] == ["    1  fallback: a reason", "         X.asm"]
    reports["native"] = dict(reports["python"], engine="native")
    assert survey.compare(spec) == ("native", "3 states")


def too_many() -> str:
    """A failing branch in the initial state, then a state whose step reads 20 monitored booleans:
    2^20 sequences of choices, more than the search follows from one state."""
    mons = "\n".join(f"\tmonitored b{i}: Boolean\n\tcontrolled f{i}: Boolean" for i in range(20))
    ups = "\n".join(f"\t\t\t\t\tf{i} := b{i}" for i in range(20))
    return f"""asm TooMany
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	monitored go: Boolean
{mons}
definitions:
	domain Small = {{0 : 1}}
	main rule r_main =
		if n = 0 then
			par
				n := 1
				if go then n := 0 endif
			endpar
		else
			par
{ups}
			endpar
		endif
default init s0:
	function n = 0
"""


def test_a_state_with_too_many_choices_after_an_error_goes_to_the_python_engine(tmp_path):
    # the Python explorer stops at that state (incomplete, naming the choices that multiply) and
    # counts a choose's alternatives after merging those with the same effect: not the native count
    _, m = load_machine(write(tmp_path, too_many()))
    with pytest.raises(Unsupported, match=r"more than 1,000,000 sequences of choices from one state"):
        NativeExplorer(m).run()


# ----------------------------------------------------------------- local functions
# a local function per call of a recursive turbo rule (the factorial through x), two local
# functions of one rule updated in seq steps and in parallel (x := 7 beside a := x), and an
# inconsistent update of a local function where the monitored clash is true in n = 3
LOCALS = """asm Locals
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	controlled fact: Integer
	controlled a: Integer
	controlled b: Integer
	monitored clash: Boolean
definitions:
	domain Small = {1 : 4}
	turbo rule r_fact($k in Integer) in Integer =
		local x : Integer [ x := 1 ]
		if $k <= 1 then result := 1
		else seq
			x <- r_fact($k - 1)
			result := $k * x
		endseq endif
	rule r_two =
		local x : Integer [ x := n ]
		local y : Integer [ y := 2 ]
		seq
			x := x + y
			par
				a := x
				x := 7
				if clash and n = 3 then x := 8 endif
			endpar
			b := x
		endseq
	main rule r_main =
		par
			fact <- r_fact(n)
			r_two[]
			if n < 4 then n := n + 1 else n := 1 endif
		endpar
default init s0:
	function n = 1
	function fact = 0
	function a = 0
	function b = 0
"""


def test_local_functions_run_native(tmp_path):
    m, py, pres, nat, nres = engines(tmp_path, LOCALS, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.depth) == (5, 5, 4)
    names = {f.index: f.name for f in m.spec.functions}
    got = [{names[k]: v for k, v in nat.state(i).items()} for i in range(nres.states)]
    # the local functions are no locations of the states; fact is n! (and so is the location
    # result the main rule's call leaves), a is n + 2, b is 7
    assert got == [{"n": 1, "fact": 0, "a": 0, "b": 0}, {"n": 2, "fact": 1, "a": 3, "b": 7, "result": 1},
                   {"n": 3, "fact": 2, "a": 4, "b": 7, "result": 2}, {"n": 4, "fact": 6, "a": 5, "b": 7, "result": 6},
                   {"n": 1, "fact": 24, "a": 6, "b": 7, "result": 24}]
    assert failing(nat) == failing(py)
    assert [(s, p, msg) for s, p, msg, _ in failing(nat)] == [(2, (1,), "inconsistent update of x: 7 and 8")]
    assert list(zip(*nat.edge_arrays())) == distinct_edges(py.edges)


@pytest.mark.corpus
def test_the_recursive_factorial_with_a_local_function_runs_native():
    need_asmeta()
    _, m = load_machine(str(ASMETA / "asm_examples/test/errors/rpns/r/fattoriale_ricorsivo.asm"))
    py, nat = Explorer(m), NativeExplorer(m)
    pres, nres = py.run(), nat.run()
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions) == (2, 2)
    assert sorted(nat.state(1).values()) == [5, 120]


# ----------------------------------------------------------------- a location at an undef argument
# pick is undef until go: seen(pick) := true updates seen at an undef argument, a location the
# Python engine keeps in the state (its key's argument None), and seen(pick) reads it back
UNDEF_ARG = """asm UndefArg
import StandardLibrary
signature:
	enum domain Color = {RED | GREEN}
	controlled pick: Color
	controlled seen: Color -> Boolean
	controlled hits: Integer
	monitored go: Boolean
definitions:
	main rule r_main =
		par
			if go then pick := RED endif
			seen(pick) := true
			if seen(pick) = true and hits < 3 then hits := hits + 1 endif
		endpar
default init s0:
	function hits = 0
"""


def test_a_location_at_an_undef_argument_runs_native(tmp_path):
    m, py, pres, nat, nres = engines(tmp_path, UNDEF_ARG, keep_graph=True)
    same_search(py, pres, nat, nres)
    assert (nres.states, nres.transitions, nres.depth) == (13, 18, 5)
    seen = next(f for f in m.spec.functions if f.name == "seen").index
    # the search ran again on a layout with seen(undef): the states hold that location
    assert seen in nat.gen.undef_args
    assert nat.state(1)[(seen, (None,))] is True
    # seen(pick) = true read back at the undef argument: hits counts while pick is undef
    hits = next(f for f in m.spec.functions if f.name == "hits").index
    assert [nat.state(i)[hits] for i in range(nres.states)] == [0, 0, 0, 1, 1, 0, 2, 2, 1, 3, 3, 2, 3]
    assert list(zip(*nat.edge_arrays())) == distinct_edges(py.edges)


# ----------------------------------------------------------------- a failing run inside a seq block
# with go false the call of r_bad fails (7 is not in Small) after the seq block's first step wrote
# n + 1 into the working state; the next run (go true) must start from the state (n + 1, not n + 2)
SEQ_LEAK = """asm SeqLeak
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled n: Small
	controlled k: Small
	monitored go: Boolean
definitions:
	domain Small = {0 : 3}
	rule r_bad = if not go then k := 7 endif
	main rule r_main =
		seq
			n := (n + 1) mod 4
			r_bad[]
		endseq
default init s0:
	function n = 0
	function k = 0
"""


def test_each_run_after_a_failing_one_starts_from_the_state(tmp_path):
    m, py, pres, nat, nres = engines(tmp_path, SEQ_LEAK, keep_graph=True)
    same_search(py, pres, nat, nres)
    n = next(f for f in m.spec.functions if f.name == "n").index
    assert [nat.state(i)[n] for i in range(nres.states)] == [0, 1, 2, 3]
    assert list(zip(*nat.edge_arrays())) == [(0, 1), (1, 2), (2, 3), (3, 0)]
    assert [(s, p, msg) for s, p, msg, _ in failing(nat)] == [
        (s, (0,), "value out of domain: 7 is not in Small (the codomain of k)") for s in range(4)]
    assert failing(nat) == failing(py)
