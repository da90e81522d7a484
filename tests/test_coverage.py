"""Coverage of rules, branches and updates: over the explored state space and over scenarios."""
from pathlib import Path

from asmcheck.review.coverage import coverage_html, coverage_text, explore_coverage, scenario_coverage
from asmcheck.review.testgen import testgen as generate_tests
from conftest import ROOT

DEMO = str(ROOT / "tests" / "data" / "review" / "advisor_demo.asm")


def _missing(doc):
    return [(i["line"], i["criterion"], i["target"]) for i in doc["targets"] if not i["covered"]]


def test_demo_coverage_and_reasons():
    _, doc = explore_coverage(DEMO)
    c = doc["criteria"]
    assert (c["rule"]["targets"], c["rule"]["covered"]) == (14, 12)
    assert (c["branch"]["targets"], c["branch"]["covered"]) == (8, 7)
    assert (c["update"]["targets"], c["update"]["covered"]) == (6, 4)
    assert _missing(doc) == [(33, "branch", "then"), (33, "rule", "fired"), (33, "update", "executed"),
                             (34, "rule", "fired"), (34, "update", "executed")]
    why = {(i["line"], i["column"], i["criterion"]): i["why"] for i in doc["targets"] if not i["covered"]}
    assert why[(33, 4, "branch")] == "the guard d is false in every reachable configuration that reaches it"
    assert why[(33, 14, "rule")] == "the enclosing if (line 33) never has its guard d true in a reachable configuration"
    assert why[(34, 35, "rule")] == ("the enclosing choose (line 34) never finds an element satisfying its "
                                     "condition in a reachable configuration")


def test_specs_every_reachable_rule_covered_uncovered_branches_listed():
    _, doc = explore_coverage(str(ROOT / "specs" / "sb_sync_slave.asm"))
    assert {k: (v["targets"], v["covered"]) for k, v in doc["criteria"].items()} == {
        "rule": (110, 110), "branch": (58, 56), "update": (35, 35)}
    assert _missing(doc) == [(96, "branch", "else (guard false, no else)"), (109, "branch", "else (guard false, no else)")]
    text = coverage_text(doc, "sb_sync_slave")
    assert text[1:4] == ["  rule: 110 of 110 (100.0 %)", "  branch: 56 of 58 (96.6 %)", "  update: 35 of 35 (100.0 %)"]


def test_html_colours_lines():
    _, doc = explore_coverage(DEMO)
    page = coverage_html(doc, "advisor_demo")
    lines = [ln for ln in page.split("\n") if ln.startswith("<span class='l")]
    assert len(lines) == len(Path(DEMO).read_text().split("\n"))
    assert lines[28].startswith("<span class='l full'")        # line 29: fooA := AA
    assert lines[32].startswith("<span class='l part'")        # line 33: if d then fooB := BB
    assert lines[33].startswith("<span class='l part'")        # line 34: choose .. never finds one
    assert lines[0] == "<span class='l'><span class='n'>1</span>asm advisor_demo</span>"


def test_scenarios_cover_what_the_generated_tests_cover(tmp_path):
    gen = generate_tests(str(ROOT / "specs" / "sb_async_master.asm"), "branch", str(tmp_path))
    doc, outcomes = scenario_coverage(gen["written"])
    assert all(o.ok for o in outcomes) and len(outcomes) == 11
    _, whole = explore_coverage(str(ROOT / "specs" / "sb_async_master.asm"))
    for crit in ("rule", "branch"):
        assert doc["criteria"][crit]["covered"] == whole["criteria"][crit]["covered"]
    assert doc["criteria"]["rule"] == {"targets": 110, "covered": 109, "percent": 99.1}


# every spec of specs/: the targets and the uncovered ones.  Every spec has two dead guards: r_tick's
# `clock(self) < tMax` is only reached with the clock below tMax (tElapsed is false), and
# r_release's `lockHolder($b) = self` only by the lock holder.  producer_consumer's producer is a
# sync slave that only writes: the reading half of the slave machine (lines 193-218) is dead;
# sb_async_master's tasks are both asynchronous: their trigger is always true (line 267's else,
# r_tick at line 278).
SPECS = {
    "producer_consumer.asm": ({"rule": (87, 77), "branch": (48, 42), "update": (25, 21)},
                              [(113, "branch"), (126, "branch"), (193, "branch"), (200, "rule"), (201, "rule"),
                               (201, "update"), (202, "rule"), (202, "update"), (203, "rule"), (203, "update"),
                               (210, "branch"), (211, "rule"), (211, "branch"), (211, "branch"), (212, "rule"),
                               (213, "rule"), (213, "update"), (214, "rule"), (215, "rule"), (218, "rule")]),
    "sb_async_master.asm": ({"rule": (110, 109), "branch": (58, 55), "update": (35, 35)},
                            [(94, "branch"), (107, "branch"), (267, "branch"), (278, "rule")]),
    "sb_async_slave.asm": ({"rule": (123, 123), "branch": (62, 60), "update": (42, 42)},
                           [(106, "branch"), (120, "branch")]),
    "sb_sync_master.asm": ({"rule": (123, 123), "branch": (62, 60), "update": (42, 42)},
                           [(107, "branch"), (121, "branch")]),
    "sb_sync_slave.asm": ({"rule": (110, 110), "branch": (58, 56), "update": (35, 35)},
                          [(96, "branch"), (109, "branch")]),
    "visual_servoing.asm": ({"rule": (109, 109), "branch": (60, 58), "update": (31, 31)},
                            [(127, "branch"), (140, "branch")]),
}


import pytest  # noqa: E402

pytestmark = pytest.mark.engines("python")


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n == "visual_servoing.asm" else n
                                  for n in sorted(SPECS)])
def test_specs_coverage(name):
    totals, missing = SPECS[name]
    rv, doc = explore_coverage(str(ROOT / "specs" / name))
    assert {k: (v["targets"], v["covered"]) for k, v in doc["criteria"].items()} == totals
    miss = [i for i in doc["targets"] if not i["covered"]]
    assert [(i["line"], i["criterion"]) for i in miss] == missing
    assert all(i["why"] for i in miss)
    # every rule that fires somewhere is covered: the uncovered rules are never reached (dead)
    never = {(w["line"], w["column"]) for w in rv.RuleIsReached() if w["status"] == "never_reached"}
    assert {(i["line"], i["column"]) for i in miss if i["criterion"] == "rule"} == never


def test_command_line(tmp_path, capsys):
    from asmcheck.cli import main
    import json as _json
    spec = str(ROOT / "specs" / "sb_sync_slave.asm")
    html = tmp_path / "cov.html"
    assert main(["explore", spec, "--coverage", str(html)]) == 0
    text = capsys.readouterr().out
    assert "coverage of sb_sync_slave over 267 states:\n  rule: 110 of 110 (100.0 %)" in text
    assert html.read_text().count("class='l none'") == 0 and "class='l part'" in html.read_text()
    assert main(["explore", spec, "--coverage", "--format", "json"]) == 0
    doc = _json.loads(capsys.readouterr().out)
    assert doc["coverage"]["criteria"]["branch"] == {"targets": 58, "covered": 56, "percent": 96.6}
    out = tmp_path / "tests"
    assert main(["testgen", spec, "--out", str(out)]) == 0
    first = capsys.readouterr().out.split("\n")[0]
    assert first == ("testgen sb_sync_slave (branch): 166 of 168 targets coverable, covered by 12 scenarios of "
                     "47 steps in all (one scenario per target: 166 scenarios, 468 steps)")
    assert main(["scenario", str(out), "--coverage"]) == 0
    text = capsys.readouterr().out
    assert "12 scenarios: 12 passed, 0 failed, 0 with input errors" in text
    assert "coverage of sb_sync_slave by 12 scenarios:\n  rule: 110 of 110 (100.0 %)\n  branch: 56 of 58" in text
    assert "true in every scenario step that reaches it" in text


def test_command_line_domain_options(tmp_path, capsys):
    from asmcheck.cli import main
    spec = tmp_path / "inf.asm"
    spec.write_text("asm inf\nimport StandardLibrary\nsignature:\n\tmonitored x: Integer\n\tcontrolled y: Integer\n"
                    "definitions:\n\tmain rule r_main = if x > 1 then y := x endif\n")
    assert main(["explore", str(spec), "--monitored", "x=0..2", "--coverage"]) == 0
    text = capsys.readouterr().out
    assert "coverage of inf over 2 states:\n  rule: 2 of 2 (100.0 %)\n  branch: 2 of 2 (100.0 %)" in text
    assert main(["explore", str(spec), "--monitored", "x=0..1", "--coverage"]) == 0
    text = capsys.readouterr().out
    assert "  rule: 1 of 2 (50.0 %)" in text and "the guard x > 1 is false in every reachable configuration" in text
