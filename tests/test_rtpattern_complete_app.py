"""The library's CompleteApplication explored to completion with the swinging-buffer properties. See
test_rtpattern.py, and test_rtpattern_apps.py (its first 3,000 states, on both engines).

The run to completion is the native engine's: the Python engine takes over a minute (70,867 states)
and gives the same report (the figures below are its own)."""
import pytest

from rtpattern.rtlib import PROPS_SB, app, explore_json, verdicts

pytestmark = [pytest.mark.slow, pytest.mark.engines("native")]


def test_complete_application_passed_free_holds(capsys):
    code, out = explore_json(capsys, app("CompleteApplication"), PROPS_SB, "--engine", "native")
    assert (code, out["verdict"], out["states"], out["transitions"], out["depth"]) == (0, "holds", 70867, 141734, 70865)
    assert out["engine"] == "native"
    v = verdicts(out)
    assert len(v) == 14 and set(v.values()) == {"holds"}
