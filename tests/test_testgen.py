"""testgen: few shortest-path scenarios that cover every coverable target, each passing under
asmcheck scenario; uncoverable targets listed."""
import pytest

from asmcheck.avalla.runner import run_scenario
from asmcheck.review.testgen import testgen as generate_tests
from conftest import ROOT, need_asmeta

pytestmark = pytest.mark.engines("none")

DEMO = str(ROOT / "tests" / "data" / "review" / "advisor_demo.asm")


def test_demo_branch(tmp_path):
    doc = generate_tests(DEMO, "branch", str(tmp_path))
    assert (doc["targets"], doc["coverable"], len(doc["scenarios"]), doc["total_steps"]) == (22, 15, 1, 3)
    assert doc["one_per_target"] == {"scenarios": 15, "total_steps": 17}
    assert [u["target"] for u in doc["uncoverable"]] == [
        "advisor_demo.asm:33:4 branch then", "advisor_demo.asm:33:14 rule fired", "advisor_demo.asm:34:35 rule fired"]
    out = run_scenario(doc["written"][0])
    assert out.ok and out.steps == 3
    assert len(doc["failing_only"]) == 4
    text = doc["scenarios"][0]["text"]
    assert "set m := false;" in text and "check cnt = 2;" in text


def test_demo_update_criterion():
    doc = generate_tests(DEMO, "update", None)
    # the updates of fooD run only in failing steps (an inconsistent update): no test can end there
    assert [u["target"] for u in doc["failing_only"]] == ["advisor_demo.asm:30:14 update executed",
                                                          "advisor_demo.asm:31:14 update executed"]
    assert doc["written"] == [] and len(doc["scenarios"]) == 1


@pytest.mark.slow
def test_visual_servoing_spec(tmp_path):
    doc = generate_tests(str(ROOT / "specs" / "visual_servoing.asm"), "branch", str(tmp_path))
    assert doc["states"] == 5219
    assert (doc["targets"], doc["coverable"]) == (169, 167)
    n, total = len(doc["scenarios"]), doc["total_steps"]
    assert (n, total) == (12, 49)
    assert doc["one_per_target"] == {"scenarios": 167, "total_steps": 457}
    for path in doc["written"]:
        out = run_scenario(path)
        assert out.ok, path
    assert [u["target"] for u in doc["uncoverable"]] == [
        "visual_servoing.asm:127:3 branch else (guard false, no else)",
        "visual_servoing.asm:140:3 branch else (guard false, no else)"]


def test_mcdc(tmp_path):
    spec = str(ROOT / "tests" / "data" / "review" / "mcdc_demo.asm")
    doc = generate_tests(spec, "mcdc", str(tmp_path))
    assert (doc["targets"], doc["coverable"], len(doc["scenarios"]), doc["total_steps"]) == (13, 13, 3, 4)
    mc = sorted(c for s in doc["scenarios"] for c in s["covers"] if " mcdc " in c)
    assert mc == [f"mcdc_demo.asm:16:4 mcdc condition {i} of 3 {side}" for i in (1, 2, 3) for side in ("false", "true")]
    # condition 3 (c, a controlled location) needs the state after one step: a then b false, c true
    assert "set a := true;\nset b := false;\nstep\ncheck c = false;\ncheck hits = true;" in doc["scenarios"][0]["text"]
    for path in doc["written"]:
        assert run_scenario(path).ok
    branch = generate_tests(spec, "branch", None)
    assert (branch["targets"], len(branch["scenarios"])) == (7, 2)
