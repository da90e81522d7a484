"""Avalla scenarios: each command on small specs, reports, exit codes and located errors."""
import json
import textwrap

import pytest

from asmcheck.avalla.runner import run_scenario
from asmcheck.cli import main
from asmcheck.errors import AsmError

pytestmark = pytest.mark.engines("none")

# A job scheduler in the style of ASMETA's tutorial: a choose rule, a monitored function,
# an out function, a derived function, an invariant, a dynamic abstract domain.
SCHED = """\
asm Sched
import StandardLibrary
signature:
	enum domain Job = {JA | JB | JC}
	enum domain Status = {RDY | RUN | FIN}
	dynamic abstract domain Ticket
	dynamic controlled st: Job -> Status
	dynamic controlled count: Integer
	dynamic controlled last: Ticket
	dynamic out idle: Boolean
	dynamic monitored fin: Job -> Boolean
	dynamic monitored bump: Integer
	derived running: Integer
definitions:
	function running = size({$j in Job | st($j) = RUN : $j})
	rule r_run = choose $j in Job with st($j) = RDY do st($j) := RUN ifnone idle := true
	rule r_finish = forall $j in Job with st($j) = RUN do if fin($j) then st($j) := FIN endif
	main rule r_main =
		par
			r_run[]
			r_finish[]
			count := count + bump
			extend Ticket with $t do last := $t
		endpar
default init s0:
	function st($j in Job) = RDY
	function idle = false
	function count = 0
"""

FINS = "set fin(JA) := false;\nset fin(JB) := false;\nset fin(JC) := false;\nset bump := 1;\n"


@pytest.fixture
def scenario(tmp_path):
    """Write the spec and a scenario (loading it) into tmp_path; return the scenario's path."""
    def _write(body: str, name: str = "sc", spec: str = SCHED, spec_name: str = "Sched") -> str:
        (tmp_path / f"{spec_name}.asm").write_text(spec, encoding="utf-8")
        p = tmp_path / f"{name}.avalla"
        p.write_text(f"scenario {name}\nload {spec_name}.asm\n" + textwrap.dedent(body), encoding="utf-8")
        return str(p)
    return _write


def checks(out):
    return [(e.span.line, e.ok) for e in out.events if e.kind == "check"]


def cli(capsys, *argv):
    code = main(["scenario", *argv])
    return code, capsys.readouterr().out


# ----------------------------------------------------------------- set / check / step
def test_set_monitored_then_step_and_check(scenario):
    out = run_scenario(scenario(FINS + "check st(JA) = RDY;\nstep\ncheck st(JA) = RUN and st(JB) = RDY;\n"
                                       "check count = 1;\n"))
    assert out.ok and out.steps == 1
    assert checks(out) == [(7, True), (9, True), (10, True)]


def test_monitored_values_persist_until_set_again(scenario):
    # as in AsmetaV (monitored functions become controlled ones): the value set stays
    out = run_scenario(scenario(FINS + "set bump := 5;\nstep\nstep\ncheck count = 10;\nset bump := 1;\nstep\n"
                                       "check count = 11;\n"))
    assert out.ok, out.events


def test_set_a_controlled_location_directly(scenario):
    out = run_scenario(scenario(FINS + "set st(JA) := FIN;\nset count := 41;\ncheck st(JA) = FIN;\nstep\n"
                                       "check st(JB) = RUN and count = 42;\n"))
    assert out.ok, out.events


def test_a_failed_check_reports_position_and_values_and_the_run_goes_on(scenario, capsys):
    path = scenario(FINS + "step\ncheck st(JB) = RUN or running = 3;\ncheck count = 1;\n")
    out = run_scenario(path)
    assert checks(out) == [(8, False), (9, True)]
    bad = out.events[[e.kind for e in out.events].index("check")]
    assert bad.values == [("st(JB)", "RDY"), ("running", "1")]
    code, text = cli(capsys, path)
    assert code == 1
    assert f"{path}:8:1: check FAILED (state 1): st(JB) = RUN or running = 3\n    st(JB) = RDY, running = 1" in text
    assert f"{path}:9:1: check passed (state 1): count = 1" in text
    assert text.rstrip().endswith("scenario sc: FAIL: 1 of 2 check(s) passed, 1 failed; 1 step(s)")


def test_an_undef_check_fails(scenario):
    out = run_scenario(scenario("check fin(JA);\n"))
    assert checks(out) == [(3, False)]
    assert out.events[0].message == "the term is undef"


def test_unset_monitored_location_reads_undef_and_the_error_names_it(scenario, capsys):
    path = scenario("set bump := 0;\nstep\nstep\n")     # the second step reads fin(JA)
    out = run_scenario(path)
    assert out.stopped == "runtime error" and out.steps == 1
    err = out.events[-1]
    assert err.kind == "error" and err.span.line == 5
    assert "not set: fin(JA), fin(JB), fin(JC)" in err.note
    code, text = cli(capsys, path)
    assert code == 1 and "the guard is undef" in text and "Sched.asm:" in text


def test_a_check_that_cannot_be_evaluated_fails_with_the_reason(scenario):
    out = run_scenario(scenario("check (if fin(JA) then true else false endif);\ncheck true;\n"))
    assert checks(out) == [(3, False), (4, True)]
    assert out.checks[0].message == "cannot be evaluated: the condition is undef"


def test_step_with_a_semicolon_is_accepted(scenario):
    out = run_scenario(scenario(FINS + "step;\nstep ;\ncheck count = 2;\n"))
    assert out.ok and out.steps == 2


# ----------------------------------------------------------------- step until
def test_step_until_runs_until_the_condition_holds(scenario):
    out = run_scenario(scenario(FINS + "step until st(JC) = RUN;\ncheck count = 3;\nstep until count = 3;\n"))
    assert out.ok and out.steps == 3
    until = [e for e in out.events if e.kind == "until"]
    assert [e.message for e in until] == ["reached after 3 step(s)", "reached after 0 step(s)"]


def test_step_until_stops_at_the_limit(scenario, capsys):
    path = scenario(FINS + "step until count = -1;\ncheck count = 0;\n")
    out = run_scenario(path, max_until=7)
    assert out.stopped == "step until" and out.steps == 7 and not out.checks
    code, text = cli(capsys, "--max-until", "7", path)
    assert code == 1
    assert f"{path}:7:1: step until: the condition is still false after 7 steps" in text
    assert "count = 7" in text


# ----------------------------------------------------------------- exec
def test_exec_fires_a_rule_on_the_current_state(scenario):
    out = run_scenario(scenario(FINS + """\
        exec
            par
                forall $j in Job do st($j) := FIN
                count := 100
            endpar;
        check (forall $j in Job with st($j) = FIN) and count = 100;
        step
        check idle and count = 101;
        """))
    assert out.ok, out.events
    assert out.steps == 1


def test_exec_may_call_rules_of_the_spec(scenario):
    out = run_scenario(scenario(FINS + "exec r_run[];\ncheck st(JA) = RUN;\ncheck count = 0;\n"))
    assert out.ok and out.steps == 0


def test_an_exec_makes_a_new_state(scenario):
    out = run_scenario(scenario("invariant low: count < 50;\n" + FINS +
                                "check count = 0;\nexec count := 7;\ncheck count = 7;\nstep\ncheck count = 8;\n"
                                "exec count := 99;\ncheck true;\n"))
    assert [(e.kind, e.state) for e in out.events if e.kind in ("check", "exec", "step")] == [
        ("check", 0), ("exec", 1), ("check", 1), ("step", 2), ("check", 2), ("exec", 3)]
    assert out.steps == 1 and out.execs == 2
    assert out.stopped == "invariant low"
    assert out.events[-1].message == "scenario invariant low is violated after the exec at line 13"


def test_exec_errors_stop_the_run(scenario):
    out = run_scenario(scenario("exec par count := 1 count := 2 endpar;\ncheck true;\n"))
    assert out.stopped == "runtime error" and "inconsistent update" in out.events[-1].message


# ----------------------------------------------------------------- pick
def test_pick_fixes_the_choice_of_the_next_step_only(scenario):
    out = run_scenario(scenario(FINS + "pick $j := JC;\nstep\ncheck st(JC) = RUN and st(JA) = RDY;\n"
                                       "step\ncheck st(JA) = RUN;\n"
                                       "pick $j in r_run := JB;\nstep\ncheck st(JB) = RUN;\n"))
    assert out.ok, out.events


def test_a_pick_holds_for_every_step_of_a_step_until(scenario):
    out = run_scenario(scenario(FINS + "pick $j := JC;\nstep until st(JC) = RUN;\n"
                                       "check st(JA) = RDY and st(JB) = RDY;\n"))
    assert out.ok and out.steps == 1
    # as in AsmetaV, the pick is checked again before every step: JC is no longer ready
    out = run_scenario(scenario(FINS + "pick $j := JC;\nstep until count = 2;\n"))
    assert out.stopped == "pick" and out.steps == 1


def test_the_last_pick_of_a_variable_wins(scenario):
    out = run_scenario(scenario(FINS + "pick $j := JC;\npick $j := JB;\nstep\ncheck st(JB) = RUN;\n"))
    assert out.ok, out.events


def test_pick_of_a_value_the_guard_excludes_stops_the_run(scenario):
    path = scenario(FINS + "set st(JB) := FIN;\npick $j := JB;\nstep\ncheck true;\n")
    out = run_scenario(path)
    assert out.stopped == "pick" and out.steps == 0 and not out.checks
    ev = out.events[-1]
    assert (ev.span.line, ev.span.col) == (8, 1)
    assert "guard of the choose rule in r_run" in ev.message


def test_pick_of_a_value_out_of_the_range(scenario):
    # AsmetaV (TestSingleFile.choosePickOutOfDomain): outside a range term the run fails; outside the
    # domain of a DomainTerm range it throws, an error in the scenario (exit 2), not a failed check
    spec = SCHED.replace("choose $j in Job with", "choose $j in {JA, JB} with")
    out = run_scenario(scenario(FINS + "pick $j := JC;\nstep\n", spec=spec))
    assert out.stopped == "pick" and out.events[-1].message == "JC is not in the range of $j in r_run"
    spec = ("asm Two\nimport StandardLibrary\nsignature:\n\tdomain Two subsetof Integer\n"
            "\tdynamic controlled c: Two\ndefinitions:\n\tdomain Two = {1 : 2}\n"
            "\trule r_run = choose $k in Two with true do c := $k\n\tmain rule r_main = r_run[]\n")
    path = scenario("pick $k := 5;\nstep\n", spec=spec, spec_name="Two")
    with pytest.raises(AsmError) as info:
        run_scenario(path)
    assert info.value.message == "pick $k := 5: 5 is not in the range of $k in r_run (the domain Two)"
    assert (info.value.span.line, info.value.span.col) == (3, 12)
    assert main(["scenario", path]) == 2


# ----------------------------------------------------------------- blocks
def test_blocks_run_where_written_and_again_by_execblock(scenario):
    out = run_scenario(scenario(FINS + """\
        begin one
            step
        end
        check count = 1;
        execblock one;
        check count = 2;
        execblock sc:one;
        check count = 3;
        """))
    assert out.ok, out.events
    assert out.steps == 3


def test_execblock_of_another_scenario_file(scenario, tmp_path):
    (tmp_path / "lib.avalla").write_text("scenario lib\nload Sched.asm\nbegin setup\n" + FINS +
                                         "end\nbegin two\n step\n step\nend\n", encoding="utf-8")
    out = run_scenario(scenario("execblock lib:setup;\nexecblock lib:two;\ncheck count = 2;\n"))
    assert out.ok and out.steps == 2
    assert out.events[-1].span.path.endswith("sc.avalla")


def test_nested_blocks_can_be_run_by_name(scenario):
    out = run_scenario(scenario(FINS + "begin outer\n begin inner\n  step\n end\nend\nexecblock inner;\n"
                                       "check count = 2;\n"))
    assert out.ok and out.steps == 2


def test_events_from_an_execblock_remember_it(scenario):
    out = run_scenario(scenario(FINS + "begin b\n check count = 5;\nend\nexecblock b;\n"))
    first, second = out.checks
    assert first.via == () and [s.line for s in second.via] == [10]


# ----------------------------------------------------------------- invariants
def test_scenario_invariant_holds(scenario):
    out = run_scenario(scenario("invariant small: count < 10;\n" + FINS + "step\nstep\ncheck count = 2;\n"))
    assert out.ok


def test_scenario_invariant_violation_stops_the_run(scenario, capsys):
    path = scenario("invariant small: count < 2;\n" + FINS + "step\nstep\nstep\ncheck true;\n")
    out = run_scenario(path)
    assert out.stopped == "invariant small" and out.steps == 2 and not out.checks
    code, text = cli(capsys, path)
    assert code == 1
    assert f"{path}:3:11: scenario invariant small is violated after step 2\n    count = 2" in text


def test_sets_are_checked_against_invariants_before_the_next_step(scenario):
    out = run_scenario(scenario("invariant small: count < 2;\n" + FINS + "set count := 5;\nstep\n"))
    assert out.stopped == "invariant small" and out.steps == 0
    assert "in the initial state" in out.events[-1].message


def test_spec_invariants_are_checked_too(scenario):
    spec = SCHED.replace("\tmain rule", "\tinvariant inv_few over count: count < 3\n\tmain rule")
    out = run_scenario(scenario(FINS + "step\nstep\nstep\nstep\n", spec=spec))
    assert out.stopped == "invariant inv_few" and out.steps == 3
    assert out.events[-1].span.path.endswith("Sched.asm")


# ----------------------------------------------------------------- element names (ASMETA issue #156)
def test_extend_made_elements_are_written_D_bang_k(scenario):
    out = run_scenario(scenario(FINS + "step\ncheck last = Ticket!1;\nstep\ncheck last = Ticket!2 and "
                                       "last != Ticket!1;\nset last := Ticket!1;\ncheck last = Ticket!1;\n"))
    assert out.ok, out.events
    assert out.checks[0].values == [("last", "Ticket!1")]


def test_element_name_of_a_domain_that_is_not_abstract(scenario):
    with pytest.raises(AsmError) as info:
        run_scenario(scenario("check last = Job!1;\n"))
    assert (info.value.span.line, info.value.span.col) == (3, 14)
    assert "not an abstract domain" in info.value.message


# ----------------------------------------------------------------- syntax details
def test_comments_and_strings_with_semicolons(scenario):
    spec = SCHED.replace("dynamic out idle: Boolean", "dynamic out idle: Boolean\n\tdynamic controlled s: String")
    out = run_scenario(scenario(FINS + """\
        // a comment; with a semicolon
        set s := "a;b"; /* another; one */
        check s = "a;b" // trailing comment
           and count = 0;
        """, spec=spec))
    assert out.ok and len(out.checks) == 1


# ----------------------------------------------------------------- reports
def test_json_report(scenario, capsys):
    path = scenario(FINS + "step\ncheck count = 2;\n")
    code, text = cli(capsys, "--format", "json", path)
    assert code == 1
    doc = json.loads(text)
    assert doc["result"] == "fail" and doc["steps"] == 1
    assert doc["checks"] == {"total": 1, "passed": 0, "failed": 1}
    check = [e for e in doc["events"] if e["kind"] == "check"][0]
    assert check == {"kind": "check", "path": path, "line": 8, "column": 1, "state": 1, "text": "count = 2",
                     "ok": False, "values": {"count": "1"}}


def test_json_report_of_an_input_error(scenario, capsys):
    path = scenario("check nope;\n")
    code, text = cli(capsys, "--format", "json", path)
    assert code == 2
    assert json.loads(text) == {"file": path, "result": "error", "error": {
        "path": path, "line": 3, "column": 7, "message": "unknown function 'nope'"}}


def test_output_is_deterministic(scenario, capsys):
    path = scenario(FINS + "step until st(JC) = RUN;\ncheck running = 3;\nstep\ncheck count = 9;\n")
    first = cli(capsys, "-v", path)
    assert first == cli(capsys, "-v", path)
    assert first[0] == 1


def test_a_folder_runs_every_scenario_in_it(scenario, tmp_path, capsys):
    scenario(FINS + "step\ncheck count = 1;\n", name="a")
    scenario(FINS + "step\ncheck count = 7;\n", name="b")
    code, text = cli(capsys, str(tmp_path))
    assert code == 1
    assert text.rstrip().endswith("2 scenarios: 1 passed, 1 failed, 0 with input errors")


def test_random_choices_with_a_seed_are_reproducible(scenario):
    path = scenario(FINS + "step\nstep\n")
    runs = [run_scenario(path, seed=s) for s in (4, 4)]
    assert [e.state for e in runs[0].events] == [e.state for e in runs[1].events]


# ----------------------------------------------------------------- input errors
BAD = [
    ("no load", "scenario b\ncheck x;\n", 2, 1, "unexpected 'check'; expected 'load'"),
    ("unknown command", "scenario b\nload Sched.asm\nchek count = 0;\n", 3, 1, "unexpected 'chek'"),
    ("missing ';' before the next command", "scenario b\nload Sched.asm\ncheck count = 0\nstep\ncheck true;\n",
     4, 1, "unexpected 'step' (is a ';' missing"),
    ("missing ';' at the end", "scenario b\nload Sched.asm\ncheck count = 0\n", 3, 16, "expected ';'"),
    ("empty check", "scenario b\nload Sched.asm\ncheck ;\n", 3, 7, "unexpected ';'"),
    ("term ends too early", "scenario b\nload Sched.asm\ncheck count = ;\n", 3, 14, "the term ends too early"),
    ("bad rule", "scenario b\nload Sched.asm\nexec\n  par\n    count := 1\n    idle := 3\n  endpar;\n",
     6, 13, "not compatible"),
    ("unknown location", "scenario b\nload Sched.asm\nset nope(JA) := 3;\n", 3, 5, "unknown function 'nope'"),
    ("wrong value domain", "scenario b\nload Sched.asm\nset bump := true;\n", 3, 13, "not compatible"),
    ("set of a derived function", "scenario b\nload Sched.asm\nset running := 3;\n", 3, 5, "running is derived"),
    ("check that is not Boolean", "scenario b\nload Sched.asm\ncheck count + 1;\n", 3, 7, "expected a Boolean"),
    ("invariant after a command", "scenario b\nload Sched.asm\nstep\ninvariant i: true;\n", 4, 1,
     "scenario invariants come right after 'load'"),
    ("unknown block", "scenario b\nload Sched.asm\nexecblock nope;\n", 3, 11, "no block nope"),
    ("unknown scenario file", "scenario b\nload Sched.asm\nexecblock other:blk;\n", 3, 1, "no scenario"),
    ("block running itself", "scenario b\nload Sched.asm\nbegin b1\n execblock b1;\nend\n", 4, 2,
     "the block runs itself"),
    ("pick of an unknown variable", "scenario b\nload Sched.asm\npick $k := JA;\n", 3, 6, "no choose rule"),
    ("pick in an unknown rule", "scenario b\nload Sched.asm\npick $j in r_nope := JA;\n", 3, 12, "no rule r_nope"),
    ("pick of undef", "scenario b\nload Sched.asm\npick $j := undef;\n", 3, 12, "undef is not allowed"),
    ("pick of the wrong domain", "scenario b\nload Sched.asm\npick $j := RUN;\n", 3, 12, "ranges over Job"),
    ("missing spec", "scenario b\nload Nope.asm\n", 2, 6, "cannot find the spec"),
    ("unknown element domain", "scenario b\nload Sched.asm\ncheck last = Nope!1;\n", 3, 14, "unknown domain 'Nope'"),
]


@pytest.mark.parametrize("label,text,line,col,msg", BAD, ids=[b[0] for b in BAD])
def test_bad_scenarios_are_located_input_errors(tmp_path, capsys, label, text, line, col, msg):
    (tmp_path / "Sched.asm").write_text(SCHED, encoding="utf-8")
    path = tmp_path / "b.avalla"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(AsmError) as info:
        run_scenario(str(path))
    err = info.value
    assert (err.span.path, err.span.line, err.span.col) == (str(path), line, col), err.render()
    assert msg in err.message
    code, out = cli(capsys, str(path))
    assert code == 2
    assert out.startswith(f"{path}:{line}:{col}: ") and "Traceback" not in out


def test_a_spec_that_does_not_parse_is_an_input_error_located_in_the_spec(scenario, capsys):
    path = scenario("step\n", spec=SCHED.replace("count := count + bump", "count := count +"))
    code, out = cli(capsys, path)
    assert code == 2
    first = out.splitlines()[0]
    assert "Sched.asm:" in first and "note: loaded by scenario sc" in out


def test_a_spec_without_main_rule(scenario):
    spec = "module Sched\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
    with pytest.raises(AsmError) as info:
        run_scenario(scenario("step\n", spec=spec))
    assert info.value.span.line == 2 and "no main rule" in info.value.message


# ----------------------------------------------------------------- picks as AsmetaV applies them
OVERLOADS = """\
asm Ov
import StandardLibrary
signature:
	dynamic controlled a: Integer
	dynamic controlled b: Integer
definitions:
	rule r_chooseRandom =
		choose $i1 in {1, 2, 3} with true do a := $i1
	rule r_chooseRandom($f in Boolean) =
		choose $i1 in {1, 2, 3} with true do b := $i1
	main rule r_main = par r_chooseRandom[] r_chooseRandom[true] endpar
default init s0:
	function a = 0
	function b = 0
"""


def test_pick_names_the_overload_as_asmetav_does(scenario):
    # AsmetaV keys a rule by name_Domain1_Domain2 and a pick's 'in r_x(D1,D2)' the same way: 'in r_x'
    # is the r_x without parameters, 'in r_x(Boolean)' the overload over Boolean
    out = run_scenario(scenario("pick $i1 in r_chooseRandom := 3;\nstep\ncheck a = 3;\ncheck b = 1;\n",
                                spec=OVERLOADS, spec_name="Ov"))
    assert checks(out) == [(5, True), (6, True)], out.events
    out = run_scenario(scenario("pick $i1 in r_chooseRandom(Boolean) := 2;\nstep\ncheck a = 1;\ncheck b = 2;\n",
                                spec=OVERLOADS, spec_name="Ov"))
    assert checks(out) == [(5, True), (6, True)], out.events
    with pytest.raises(AsmError) as info:
        run_scenario(scenario("pick $i1 in r_chooseRandom(Integer) := 2;\nstep\n", spec=OVERLOADS, spec_name="Ov"))
    assert info.value.message == "no rule r_chooseRandom(Integer) in Ov"


INFINITE = """\
asm Inf
import StandardLibrary
signature:
	dynamic controlled foo: Integer
	dynamic controlled nat: Natural
	dynamic controlled re: Real
definitions:
	main rule r_main = par
		choose $s in Integer with true do foo := $s
		choose $n in Natural with true do nat := $n
		choose $r in Real with true do re := $r
	endpar
default init s0:
	function foo = 1
"""


def test_pick_of_integer_natural_and_real_values(scenario):
    out = run_scenario(scenario("pick $s := -5;\npick $n := 7;\npick $r := 0.25;\nstep\n"
                                "check foo = -5;\ncheck nat = 7;\ncheck re = 0.25;\n", spec=INFINITE, spec_name="Inf"))
    assert checks(out) == [(7, True), (8, True), (9, True)], out.events
    # without a pick the value is drawn, as ASMETA's simulator does (seeded: the same each run)
    a = run_scenario(scenario("step\n", spec=INFINITE, spec_name="Inf"))
    b = run_scenario(scenario("step\n", spec=INFINITE, spec_name="Inf"))
    assert a.ok and a.steps == b.steps == 1
    with pytest.raises(AsmError) as info:
        run_scenario(scenario("pick $n := -1;\nstep\n", spec=INFINITE, spec_name="Inf"))
    assert info.value.message == "pick $n := -1: -1 is not in the range of $n (Natural) in r_main"
    assert (info.value.span.line, info.value.span.col) == (3, 12)


def test_scenario_takes_the_machine_options(scenario):
    spec = INFINITE.replace("choose $s in Integer with true do foo := $s",
                            "choose $s in Integer with $s > 2 do foo := $s")
    out = run_scenario(scenario("step\n", spec=spec, spec_name="Inf"))
    assert out.stopped == "runtime error" and out.events[-1].message.startswith(
        "step 1 failed: choose over the infinite domain Integer with a guard"), out.events
    spec2 = spec.replace("choose $n in Natural with true do nat := $n", "nat := 0n").replace(
        "choose $r in Real with true do re := $r", "re := 0.0")
    out = run_scenario(scenario("step\ncheck foo = 3;\n", spec=spec2, spec_name="Inf"),
                       options={"int_range": (-5, 5)})
    assert checks(out) == [(4, True)], out.events


def test_load_tries_the_path_as_given_then_beside_the_scenario(tmp_path, monkeypatch):
    (tmp_path / "specs").mkdir()
    (tmp_path / "scen").mkdir()
    (tmp_path / "specs" / "Sched.asm").write_text(SCHED, encoding="utf-8")
    sc = tmp_path / "scen" / "a.avalla"
    sc.write_text("scenario a\nload specs/Sched.asm\n" + FINS + "step\ncheck count = 1;\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    assert run_scenario(str(sc)).ok
    (tmp_path / "scen" / "Sched.asm").write_text(SCHED, encoding="utf-8")
    sc.write_text("scenario a\nload Sched.asm\n" + FINS + "step\ncheck count = 1;\n", encoding="utf-8")
    out = run_scenario(str(sc))
    assert out.ok and out.spec_path == str(tmp_path / "scen" / "Sched.asm")


def test_load_of_an_absolute_looking_or_quoted_path_beside_the_scenario(tmp_path):
    # AsmetaV (ScenarioUtility.getAsmPath): the path as given if it exists, else joined to the scenario's
    # folder -- so 'load /Sched.asm' finds the Sched.asm beside the scenario
    (tmp_path / "Sched.asm").write_text(SCHED, encoding="utf-8")
    sc = tmp_path / "b.avalla"
    for load in ("/Sched.asm", '"Sched.asm"'):
        sc.write_text(f"scenario b\nload {load}\n" + FINS + "step\ncheck count = 1;\n", encoding="utf-8")
        out = run_scenario(str(sc))
        assert out.ok and out.spec_path == str(tmp_path / "Sched.asm"), load
