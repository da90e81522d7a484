"""The library's VisualServoing application explored to completion with the swinging-buffer
properties (properties/rtpattern*.prop), with `passed` free and fixed to true. See test_rtpattern.py."""
import pytest

from rtpattern.rtlib import PROPS_SB, app, explore_json, verdicts

pytestmark = [pytest.mark.slow, pytest.mark.engines("both")]


def test_visual_servoing_passed_free_holds(capsys):
    code, out = explore_json(capsys, app("VisualServoing"), PROPS_SB)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (0, "holds", 15710, 31420, 15708)
    v = verdicts(out)
    assert len(v) == 14 and set(v.values()) == {"holds"}


def test_visual_servoing_passed_true_is_one_chain(capsys):
    # ASMETA's simulator revisits a state after about 15,708 distinct states: asmcheck counts those plus
    # the initial state (initialized = false)
    code, out = explore_json(capsys, app("VisualServoing"), [], "--monitored", "passed=true")
    # no property file is given: the run checks nothing, and says so
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == \
        (0, "no property checked", 15709, 15709, 15708)
