"""VisualServoing's set-up under nondeterministic scheduling (tests/rtpattern/RtNondetVS.asm) explored
to completion: the paper's properties hold, the freshness property does not. See test_rtpattern.py and
test_rtpattern_apps.py (the same, bounded in depth, on both engines).

The run to completion is the native engine's: the Python engine takes about two minutes over it
(132,077 states), the longest single test of the suite, and gives the same report (the figures below
are its own). Both engines run the bounded exploration of test_rtpattern_apps.py, with exact counts
and the same 18-step trace."""
import pytest

from rtpattern.rtlib import PROPS_NONDET, explore_json, nondet_spec, trace_steps, verdicts, violated

pytestmark = [pytest.mark.slow, pytest.mark.engines("native")]


def test_nondet_visual_servoing_to_completion(capsys):
    path, imp = nondet_spec("RtNondetVS")
    code, out = explore_json(capsys, path, PROPS_NONDET, "--deadlock", "--engine", "native", *imp)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (1, "violated", 132077, 392131, 81)
    assert "incomplete" not in out and out["engine"] == "native"
    v = verdicts(out)
    assert len(v) == 17
    assert violated(out) == {"stp_swap_publishes_latest"}
    assert {p for p, x in v.items() if x != "violated"} == set(v) - {"stp_swap_publishes_latest"}
    assert set(v.values()) == {"holds", "violated"}
    assert trace_steps(out) == {"stp_swap_publishes_latest": 18}
