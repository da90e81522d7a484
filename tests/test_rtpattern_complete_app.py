"""The library's CompleteApplication explored to completion with the swinging-buffer properties
(about two minutes). See test_rtpattern.py."""
import pytest

from rtpattern.rtlib import PROPS_SB, app, explore_json, verdicts

pytestmark = [pytest.mark.slow, pytest.mark.engines("both")]


def test_complete_application_passed_free_holds(capsys):
    code, out = explore_json(capsys, app("CompleteApplication"), PROPS_SB)
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (0, "holds", 70867, 141734, 70865)
    v = verdicts(out)
    assert len(v) == 14 and set(v.values()) == {"holds"}
