"""The Python API's explore() refuses arguments of the wrong type or naming nothing with a
UsageError (the command line's exit code 2), and a run whose LTL/CTL phase failed inside is
never reported as holding."""
from __future__ import annotations

import pytest

import asmcheck
from asmcheck.errors import UsageError

from helpers import write

pytestmark = pytest.mark.engines("python")

SPEC = """asm Light
import StandardLibrary
import LTLLibrary
signature:
	enum domain Color = {RED | GREEN}
	controlled c: Color
	monitored go: Boolean
definitions:
	LTLSPEC g(c = RED or c = GREEN)
	main rule r_main = if go then c := GREEN endif
default init s0:
	function c = RED
"""


@pytest.mark.parametrize("kwargs,message", [
    (dict(max_seconds="x"), "max_seconds must be a number, not 'x'"),
    (dict(max_states=2.5), "max_states must be an integer, not 2.5"),
    (dict(max_depth="3"), "max_depth must be an integer, not '3'"),
    (dict(workers=True), "workers must be an integer, not True"),
    (dict(fair="all"), "fair must be a list of domain names (or 'all'), not the string 'all'"),
    (dict(fair=["Nope"]), "--fair Nope: the spec has no domain Nope (its domains: Color)"),
])
def test_bad_arguments_are_usage_errors(tmp_path, kwargs, message):
    model = asmcheck.load(write(tmp_path, SPEC))
    with pytest.raises(UsageError) as info:
        model.explore(engine="python", **kwargs)
    assert str(info.value) == message


def test_an_unknown_fair_domain_on_the_command_line_is_a_usage_error(tmp_path, capsys):
    from asmcheck.cli import main
    assert main(["explore", write(tmp_path, SPEC), "--fair", "Nope"]) == 2
    err = capsys.readouterr().err
    assert err == "asmcheck: error: --fair Nope: the spec has no domain Nope (its domains: Color)\n"


def test_fair_all_and_a_domain_are_accepted(tmp_path):
    run = asmcheck.load(write(tmp_path, SPEC)).explore(engine="python", fair=["all", "Color"])
    assert (run.result.verdict, run.result.states) == ("holds", 2)


def test_a_failure_inside_the_temporal_phase_is_not_a_pass(tmp_path, monkeypatch):
    import asmcheck.temporal as temporal

    def broken(*args, **kwargs):
        raise RuntimeError("boom")

    monkeypatch.setattr(temporal, "check_temporal", broken)
    run = asmcheck.load(write(tmp_path, SPEC)).explore(engine="python")
    assert run.result.verdict == "incomplete"
    assert run.result.reason == "internal error in LTL/CTL checking: RuntimeError: boom"
    assert run.exit_code == 3


INV_AND_LTL = SPEC.replace("\tLTLSPEC", "\tinvariant inv_color over c: c = RED or c = GREEN\n\tLTLSPEC")


def test_a_limit_in_the_temporal_phase_leaves_the_invariants_decided(tmp_path, monkeypatch):
    """The search was complete: its invariants hold; only the LTL/CTL properties are incomplete
    (they were all reported incomplete, in explore's report and in the gate)."""
    import asmcheck.temporal as temporal
    from asmcheck.explore.bfs import TimeUp

    def out_of_time(*args, **kwargs):
        raise TimeUp()

    monkeypatch.setattr(temporal, "check_temporal", out_of_time)
    path = write(tmp_path, INV_AND_LTL)
    run = asmcheck.load(path).explore(engine="python", max_seconds=60)
    assert (run.result.verdict, run.result.reason) == ("incomplete", "time limit 60 s reached in the LTL/CTL phase")
    assert [(r["property"], r["verdict"]) for r in run.rows] == [("inv_color", "holds"), ("ltl_1", "incomplete")]
    gate = asmcheck.check([path], max_seconds=60, engine="python")
    assert [(p.name, p.verdict) for p in gate.outcomes[0].properties] == [("inv_color", "holds"),
                                                                          ("ltl_1", "incomplete")]


@pytest.mark.engines("native")
def test_a_ctrl_c_while_the_graph_is_made_keeps_the_searchs_counts(tmp_path, monkeypatch):
    """The search was over when the Ctrl-C came, in the enumeration of the graph's steps: the
    report keeps its states and transitions (it said 0 transitions, depth 0)."""
    from asmcheck.explore import native_build
    from asmcheck.explore.native import NativeExplorer
    if native_build.compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")

    def interrupted(self):
        raise KeyboardInterrupt

    monkeypatch.setattr(NativeExplorer, "graph_edges", interrupted)
    path = write(tmp_path, INV_AND_LTL)
    run = asmcheck.load(path).explore(engine="native", graph=True)
    r = run.result
    assert (r.engine, r.verdict, r.states, r.transitions, r.depth) == ("native", "incomplete", 2, 3, 1)
    assert r.reason == "interrupted (Ctrl-C) while the state graph's steps were enumerated"
    assert run.interrupted
