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
