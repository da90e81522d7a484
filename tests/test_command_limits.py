"""Every command checks its limits alike: bmc, advise and testgen took a negative --max-states,
a negative or NaN --max-seconds and a negative --loop-bound (bmc --max-seconds nan was an internal
error; testgen --max-states -5 listed reachable code as dead); testgen says that what a limited
exploration did not cover may be beyond the limit, and exits 3 (it exited 0 and called it dead
code)."""
from __future__ import annotations

import pytest

from asmcheck.cli import main

pytestmark = pytest.mark.engines("python")

COUNT = """asm Count
import StandardLibrary
signature:
	domain Cnt subsetof Integer
	dynamic controlled x: Cnt
	monitored inc: Boolean
definitions:
	domain Cnt = {0 : 9}
	invariant over x: x < 10
	main rule r_main =
		if inc then
			if x < 9 then x := x + 1 else x := 0 endif
		endif
default init s0:
	function x = 0
"""


@pytest.mark.parametrize("args, message", [
    (["bmc", "SPEC", "-k", "3", "--max-seconds", "nan"], "--max-seconds must be a number of seconds, 0 or more"),
    (["bmc", "SPEC", "-k", "3", "--max-seconds", "-1"], "--max-seconds must be a number of seconds, 0 or more"),
    (["bmc", "SPEC", "-k", "3", "--loop-bound", "-5"], "--loop-bound must be 1 or more"),
    (["advise", "SPEC", "--max-states", "-3"], "--max-states must be 1 or more, not -3"),
    (["advise", "SPEC", "--max-seconds", "inf"], "--max-seconds must be a number of seconds, 0 or more"),
    (["testgen", "SPEC", "--max-states", "-5"], "--max-states must be 1 or more, not -5"),
    (["testgen", "SPEC", "--max-seconds", "-2"], "--max-seconds must be a number of seconds, 0 or more"),
])
def test_a_bad_limit_is_a_usage_error(write_spec, capsys, args, message):
    path = write_spec(COUNT)
    assert main([path if a == "SPEC" else a for a in args]) == 2
    cap = capsys.readouterr()
    assert (cap.out, cap.err) == ("", f"asmcheck: error: {message}\n")


def test_testgen_on_a_limited_exploration_does_not_call_code_dead(write_spec, capsys):
    path = write_spec(COUNT)
    assert main(["testgen", path, "--criterion", "rule", "--max-states", "3"]) == 3
    out = capsys.readouterr().out.splitlines()
    assert out[1] == "exploration incomplete (state limit 3 reached): more targets may be coverable"
    assert out[-2:] == ["not covered in the states explored (dead code, or beyond the limit): 1",
                        "  Count.asm:12:34 rule fired: x := 0"]
    assert main(["testgen", path, "--criterion", "rule"]) == 0
    out = capsys.readouterr().out
    assert "dead code" not in out and out.startswith("testgen Count (rule): 4 of 4 targets coverable")


def test_coverage_on_a_limited_exploration_speaks_of_the_explored_configurations(write_spec, capsys):
    """(it said 'the guard x < 9 is true in every reachable configuration that reaches it', of a
    guard that is false at x = 9, beyond the limit)"""
    path = write_spec(COUNT)
    main(["explore", path, "--coverage", "--max-states", "3"])
    out = capsys.readouterr().out
    cov = out[out.index("coverage of"):].splitlines()
    assert cov == [
        "coverage of Count over 3 states (exploration incomplete: state limit 3 reached):",
        "  rule: 3 of 4 (75.0 %)",
        "  branch: 3 of 4 (75.0 %)",
        "  update: 1 of 2 (50.0 %)",
        "not covered (3):",
        "  Count.asm:12:4  branch if else: if x < 9 then x := x + 1 else x := 0 endif",
        "      the guard x < 9 is true in every explored configuration that reaches it",
        "  Count.asm:12:34  rule update fired: x := 0",
        "      the enclosing if (line 12) never has its guard x < 9 false in an explored configuration",
        "  Count.asm:12:34  update update executed: x := 0",
        "      the enclosing if (line 12) never has its guard x < 9 false in an explored configuration"]
