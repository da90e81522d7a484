"""The state graph as temporal/ reads it: only through the explorer interface that both engines
offer (``n_states``, ``parent``, ``edge_arrays()``, ``edges`` with picks read lazily, ``state``,
``replay_steps``, optional ``state_labels`` and ``find``).  An explorer reduced to those names gives
the same verdicts and traces as the Python explorer itself, and in state mode reads the states
and the choices of only the steps a trace prints.  Engine pinned: python (wrapped)."""
from __future__ import annotations

from pathlib import Path

import pytest

import asmcheck
from asmcheck.explore.bfs import Explorer
from asmcheck.props.files import properties_for
from asmcheck.semantics.machine import Chooser, Ctx
from asmcheck.report.trace import temporal_json
from asmcheck.temporal import check_temporal

pytestmark = pytest.mark.engines("native")

ROOT = Path(__file__).resolve().parent.parent
TEMPORAL = ROOT / "specs" / "temporal"


class LazyEdges:
    def __init__(self, owner):
        self.owner = owner

    def __len__(self):
        return len(self.owner._src)

    def __getitem__(self, i):
        self.owner.pick_reads += 1
        return self.owner._ex.edges[i]

    def __iter__(self):
        self.owner.iterated = True
        return iter(self.owner._ex.edges)


class GraphOnly:
    """A finished Python explorer seen through the interface names only."""

    def __init__(self, ex: Explorer, labels: bool):
        self._ex = ex
        self.m = ex.m
        self.n_states = ex.n_states
        self.parent = ex.parent
        self._src, self._dst = ex.edge_arrays()
        self.edges = LazyEdges(self)
        self.state_calls: list[int] = []
        self.pick_reads = 0
        self.iterated = False
        if labels:
            self.state_labels = self._labels

    def edge_arrays(self):
        return self._src, self._dst

    def state(self, sid):
        self.state_calls.append(sid)
        return self._ex.state(sid)

    def find(self, st):
        return self._ex.index.get(self._ex.layout.freeze(self._ex._norm(st)))

    def replay_steps(self, first, steps):
        return self._ex.replay_steps(first, steps)

    def _labels(self, items):
        # what a native engine computes in C: here by the step function's evaluator, unseen by the counters
        out = [bytearray(self.n_states) for _ in items]
        for sid in range(self.n_states):
            ctx = Ctx(self.m, self._ex.state(sid), Chooser())
            for k, a in enumerate(items):
                ctx.env = dict(a.env) if a.env else {}
                if a.fn(ctx) is True:
                    out[k][sid] = 1
        return out


def explored(name: str):
    path = str(TEMPORAL / f"{name}.asm")
    model = asmcheck.load(path)
    spec, machine = model.spec, model.machine
    _, _, temporal = properties_for(spec, machine, path, None, use_default=True)
    ex = Explorer(machine, keep_graph=True)
    assert ex.run().verdict != "incomplete"
    return machine, ex, temporal


def outcome(machine, results):
    return [(r.name, r.holds, temporal_json(r, machine)) for r in results]


@pytest.mark.parametrize("name", ["counter", "peterson", "spinlock", "request_ack", "grid"])
@pytest.mark.parametrize("labels", [False, True])
def test_interface_only_explorer_gives_the_same_verdicts_and_traces(name, labels):
    machine, ex, temporal = explored(name)
    want = outcome(machine, check_temporal(ex, temporal))
    view = GraphOnly(ex, labels)
    got = outcome(machine, check_temporal(view, temporal))
    assert got == want
    assert len(want) > 0


def test_state_mode_reads_only_the_states_and_choices_a_trace_prints():
    machine, ex, temporal = explored("counter")
    ltl = [p for p in temporal if p.kind == "ltl"]
    view = GraphOnly(ex, labels=True)
    results = check_temporal(view, ltl)
    assert view.state_calls == [0]            # the formula builder's first state only
    assert not view.iterated and view.pick_reads == 0
    out = outcome(machine, results)            # the traces are built (and replayed) here
    assert {name for name, holds, _ in out if not holds} == {"ltlSpec_reset_often", "ltlSpec_wrong_past"}
    steps = sum(len(j["trace"]) - 1 for _, holds, j in out if not holds)
    assert 0 < view.pick_reads <= steps
    assert view.state_calls == [0]


def test_agent_fairness_through_find():
    machine, ex, temporal = explored("peterson")
    temporal = [p for p in temporal if p.kind not in ("justice", "compassion")]
    want = outcome(machine, check_temporal(ex, temporal, fair=["Proc"]))
    assert all(holds for _, holds, _ in want)
    got = outcome(machine, check_temporal(GraphOnly(ex, labels=True), temporal, fair=["Proc"]))
    assert got == want
    # without fairness some property is violated: the fairness reached the check
    assert not all(holds for _, holds, _ in outcome(machine, check_temporal(GraphOnly(ex, True), temporal)))
