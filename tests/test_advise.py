"""asmcheck advise: AsmetaMA's checks over the explored configurations, pinned on a spec built to
show each of them (tests/data/review/advisor_demo.asm), on ASMETA's forModelAdvisor specs and on
a spec of specs/."""
import json
from pathlib import Path

import pytest

from asmcheck.cli import main as cli_main
from asmcheck.review.advise import CHECKS, advise, advise_text
from conftest import ROOT, need_asmeta

pytestmark = pytest.mark.engines("python")

DEMO = str(ROOT / "tests" / "data" / "review" / "advisor_demo.asm")


def _summary(doc):
    out = {}
    for e in doc["meta_properties"]:
        out[e["check"]] = (e["verdict"], [(w.get("line"), w.get("location") or w.get("function") or w.get("domain")
                                           or w.get("macro"), w["status"]) for w in e["where"]])
    return out


def test_demo_every_check():
    doc = advise(DEMO)
    assert (doc["states"], doc["transitions"], doc["configurations"], doc["failing_configurations"]) == (3, 3, 6, 3)
    assert [e["check"] for e in doc["meta_properties"]] == [c[1] for c in CHECKS] and len(CHECKS) == 16
    s = _summary(doc)
    assert s["InconsistentUpdate"] == ("violated", [(30, "fooD", "inconsistent")])
    mp1 = doc["meta_properties"][0]["where"][0]
    assert (mp1["pairs"], mp1["updates"]) == (1, [[30, "AA"], [31, "CC"]])
    assert s["CondRuleIsComplete"] == ("violated", [(30, None, "incomplete"), (31, None, "incomplete"),
                                                    (32, None, "incomplete"), (33, None, "incomplete")])
    assert s["CaseRuleIsComplete"] == ("satisfied", [])
    assert s["ChooseRuleIsEmpty"] == ("violated", [(34, None, "always_empty")])
    assert s["ForallRuleIsEmpty"] == ("satisfied", [(35, None, "always_not_empty")])
    assert s["CondRuleEvalToTrue"] == ("violated", [(30, None, "ok"), (31, None, "ok"), (32, None, "ok"),
                                                    (33, None, "never_then")])
    assert s["TrivialUpdate"] == ("violated", [(29, "fooA", "always_trivial")])
    assert s["DomainAllUsed"] == ("violated", [(6, "Col", "all_used"), (7, "Unused", "unuseful"),
                                               (8, "Small", "all_used")])
    assert s["ContrLocTakesEveryValue"][1] == [
        (9, "fooA", "could_be_resized"), (9, "fooA", "could_be_resized"), (10, "fooB", "never_used"),
        (10, "fooB", "never_used"), (11, "fooD", "never_used"), (11, "fooD", "never_used"),
        (13, "never", "never_used"), (13, "never", "initialized_and_never_used"), (14, "u", "never_used"),
        (14, "u", "initialized_and_never_used")]
    assert s["LocationCouldBeRemoved"] == ("violated", [(10, "fooB", "used_only_in_unreachable_code"),
                                                        (13, "never", "never_used"), (14, "u", "never_used")])
    assert s["ContrLocIsUpdated"] == ("violated", [(10, "fooB", "never_updated"), (13, "never", "never_updated"),
                                                   (14, "u", "never_updated")])
    assert s["ContrLocCouldBeStatic"][1] == [
        (9, "fooA", "could_be_static"), (9, "fooA", "could_be_static"), (10, "fooB", "could_be_static"),
        (10, "fooB", "could_be_static"), (11, "fooD", "could_be_static"), (11, "fooD", "could_be_static")]
    kinds = [w["kind"] for w in doc["meta_properties"][11]["where"]]
    assert kinds == ["function", "location"] * 3
    reached = s["RuleIsReached"][1]
    assert [x for x in reached if x[2] == "never_reached"] == [(33, "fooB", "never_reached"),
                                                               (34, "fooB", "never_reached")]
    assert [x for x in reached if x[2] == "sometimes_reached"] == [(30, "fooD", "sometimes_reached"),
                                                                   (31, "fooD", "sometimes_reached"),
                                                                   (32, "cnt", "sometimes_reached")]
    assert len(reached) == 14
    assert s["MacroRuleCalled"] == ("violated", [(25, "r_unused", "never_called")])
    assert s["StatDerIsUsed"] == ("satisfied", [])


def test_text_lists_violations_first_with_their_line():
    lines = advise_text(advise(DEMO))
    assert lines[0] == ("advise advisor_demo (" + DEMO + "): 3 states, 3 transitions, 6 configurations, "
                        "3 of them fail")
    assert lines[2] == "MP1 InconsistentUpdate violated (No inconsistent update is ever performed): 1 finding"
    assert lines[3] == "  advisor_demo.asm:30:14  location fooD: inconsistent (1 pair of updates: line 30 := AA, line 31 := CC)"
    assert "  advisor_demo.asm:29:4  fooA := AA [fooA]: always_trivial" in lines
    assert lines[-1] == ("satisfied: MP2 CaseRuleIsComplete, MP3 ForallRuleIsEmpty, MP MacroCallRuleIsReached, "
                         "MP StatDerIsUsed")


def test_mp_selection_and_exit_codes(capsys):
    assert cli_main(["advise", DEMO, "--mp", "4", "--format", "json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert [e["check"] for e in doc["meta_properties"]] == ["TrivialUpdate"]
    assert cli_main(["advise", DEMO, "--mp", "9"]) == 2
    assert "--mp takes 1..7 and rules, not 9" in capsys.readouterr().err
    assert cli_main(["advise", DEMO, "--mp", "1,rules"]) == 1
    text = capsys.readouterr().out
    assert "MP1 InconsistentUpdate violated" in text and "MP MacroRuleCalled violated" in text
    assert "TrivialUpdate" not in text


def test_deterministic():
    a = advise(DEMO)
    b = advise(DEMO)
    a.pop("seconds"), b.pop("seconds")
    assert json.dumps(a) == json.dumps(b)


def test_bad_input_is_an_error_with_a_position(tmp_path):
    p = tmp_path / "bad.asm"
    p.write_text("asm bad\nsignature:\n  controlled x: Foo\ndefinitions:\nmain rule r_main = skip\n")
    doc = advise(str(p))
    assert doc["error"]["line"] == 3 and doc["meta_properties"] == []


def test_partial_exploration_is_incomplete_unless_proven():
    doc = advise(DEMO, max_states=1)
    verdicts = {e["check"]: e["verdict"] for e in doc["meta_properties"]}
    assert doc["incomplete"] == "state limit 1 reached"
    assert verdicts["InconsistentUpdate"] == "violated"        # one configuration proves it
    assert verdicts["CondRuleIsComplete"] == "violated"
    assert verdicts["TrivialUpdate"] == "incomplete"           # "always" needs every state
    assert verdicts["ContrLocIsUpdated"] == "incomplete"


@pytest.mark.parametrize("n, loc, states, updates", [
    ("", "tokens(p1)", 1, [[78, "0"], [80, "2"]]),
    ("2", "tokens(p2)", 1, [[93, "0"], [95, "3"]]),
    ("3", "tokens(p4)", 14, [[132, "0"], [134, "2"]]),
])
def test_petri_nets_for_the_model_advisor(n, loc, states, updates):
    # ASMETA's specs built to show MP1: a place both input and output of the transition that fires
    asmeta = need_asmeta()
    p = asmeta / "asm_examples/examples/petriNets/forModelAdvisor" / f"petriNet_forModelAdvisor_InconsUpdateViolation{n}.asm"
    doc = advise(str(p), groups={"1"})
    assert doc["states"] == states
    (mp1,) = doc["meta_properties"]
    assert mp1["verdict"] == "violated"
    assert [(w["location"], w["pairs"], w["updates"]) for w in mp1["where"]] == [(loc, 1, updates)]


def test_spec_of_specs_folder():
    doc = advise(str(ROOT / "specs" / "sb_sync_slave.asm"))
    assert (doc["states"], doc["transitions"], doc["configurations"]) == (267, 662, 794)
    v = {e["check"]: (e["verdict"], sum(1 for w in e["where"] if w["status"] in (
        "incomplete", "always_trivial", "never_reached"))) for e in doc["meta_properties"]}
    assert v["InconsistentUpdate"] == ("satisfied", 0)
    assert v["CondRuleIsComplete"] == ("violated", 12)
    assert v["TrivialUpdate"] == ("violated", 7)
    assert v["RuleIsReached"] == ("satisfied", 0)


def test_domain_used_inside_a_product_argument(tmp_path):
    p = tmp_path / "prod.asm"
    p.write_text("""asm prod
import StandardLibrary
signature:
	enum domain Col = {AA | BB | CC}
	enum domain Dir = {UP | DOWN}
	controlled f: Prod(Prod(Col, Boolean), Dir) -> Boolean
	controlled g: Prod(Col, Dir)
definitions:
	main rule r_main =
		par
			f((BB, true), UP) := true
			g := (CC, UP)
		endpar
""")
    doc = advise(str(p), groups={"5"})
    (mp5,) = doc["meta_properties"]
    assert [(w["domain"], w["used"], w["unused"]) for w in mp5["where"]] == [
        ("Col", ["BB", "CC"], ["AA"]), ("Dir", ["UP"], ["DOWN"])]


def test_for_mp1_file_restricts_mp1(tmp_path):
    spec = tmp_path / "advisor_demo.asm"
    spec.write_text(Path(DEMO).read_text())
    (tmp_path / "advisor_demo.forMP1").write_text("cnt\n")
    (mp1,) = advise(str(spec), groups={"1"})["meta_properties"]
    assert (mp1["verdict"], mp1["where"]) == ("satisfied", [])
    (tmp_path / "advisor_demo.forMP1").write_text("cnt\nfooD\n")
    (mp1,) = advise(str(spec), groups={"1"})["meta_properties"]
    assert [w["location"] for w in mp1["where"]] == ["fooD"]
