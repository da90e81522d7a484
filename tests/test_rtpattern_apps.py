"""RobotController to completion, CompleteApplication bounded (test_rtpattern_complete_app.py explores it
to completion), and the VisualServoing set-up under nondeterministic scheduling (tests/rtpattern/RtNondetVS.asm)
bounded in depth (test_rtpattern_nondet_vs.py: to completion). See test_rtpattern.py."""
import pytest

from rtpattern.rtlib import PROPS_NONDET, PROPS_SB, app, explore_json, nondet_spec, trace_steps, verdicts, violated

pytestmark = [pytest.mark.slow, pytest.mark.engines("both")]


def test_robot_controller_passed_free_holds(capsys):
    code, out = explore_json(capsys, app("RobotController"), PROPS_SB)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (0, "holds", 10076, 20152, 10074)
    v = verdicts(out)
    assert len(v) == 14 and set(v.values()) == {"holds"}


def test_complete_application_first_3000_states(capsys):
    code, out = explore_json(capsys, app("CompleteApplication"), PROPS_SB, "--max-states", "3000")
    assert (code, out["verdict"], out["states"], out["depth"]) == (3, "incomplete", 3000, 2998)
    v = verdicts(out)
    assert len(v) == 14 and set(v.values()) == {"incomplete"}


def test_nondet_visual_servoing_stale_swap(capsys):
    """Under nondeterministic scheduling the VS task swaps cam2Vs twice without the camera writing in between:
    the paper's three properties hold (to depth 20), the freshness property does not (18 steps)."""
    path, imp = nondet_spec("RtNondetVS")
    code, out = explore_json(capsys, path, PROPS_NONDET, "--max-depth", "20", *imp)
    assert code == 1
    assert (out["states"], out["transitions"], out["depth"]) == (3820, 9036, 20)
    assert out["incomplete"] == "depth limit 20 reached"
    assert len(verdicts(out)) == 16
    assert violated(out) == {"stp_swap_publishes_latest"}
    assert trace_steps(out) == {"stp_swap_publishes_latest": 18}
    last = out["violations"][0]["trace"][-1]["state"]
    assert last["buffers(cam2Vs_SB)"] == {"seq": ["DataStream!1"]}          # one write only ...
    assert (last["indexRead(cam2Vs_SB)"], last["indexWrite(cam2Vs_SB)"]) == (1, 0)   # ... and the second swap
