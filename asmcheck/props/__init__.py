"""State and step predicates that the explorer checks on every state or transition."""
from __future__ import annotations

from ..errors import AsmRuntimeError
from ..semantics.machine import Chooser, Ctx
from ..semantics.analysis import mentions_monitored
from ..semantics.choice import next_prefix


class StateProperty:
    """An invariant: a Boolean term true in every reachable state."""

    kind = "invariant"

    def __init__(self, prop, machine):
        self.prop = prop
        self.name = prop.name
        self.span = prop.span
        self.source = getattr(prop, "source", "spec")
        self.expect = getattr(prop, "expect", None)
        self.fn = machine.term(prop.body)

    def check_state(self, machine, state) -> bool:
        ctx = Ctx(machine, state, Chooser())
        v = self.fn(ctx)
        if v is None:
            raise AsmRuntimeError(self.span, f"invariant {self.name} is undef")
        return v is True


class MonitoredInvariant:
    """An invariant that reads monitored functions: checked before each step, with that
    step's monitored values (as ASMETA's simulator does)."""

    kind = "invariant"

    def __init__(self, prop, machine):
        self.prop = prop
        self.name = prop.name
        self.span = prop.span
        self.source = getattr(prop, "source", "spec")
        self.expect = getattr(prop, "expect", None)
        body = machine.term(prop.body)
        invars = [machine.term(p.body) for p in machine.spec.properties if p.kind == "invar"]
        if invars:
            # values of monitored functions that break an INVAR are not inputs the spec considers
            def fn(ctx):
                for i in invars:
                    if i(ctx) is not True:
                        return True
                return body(ctx)
            self.fn = fn
        else:
            self.fn = body

    def check_step(self, machine, state, ups, nxt, mon) -> bool:
        # monitored locations the step did not read may take any value: all must satisfy it
        for v in evaluate_all(machine, self.fn, state, mon):
            if v is None:
                raise AsmRuntimeError(self.span, f"invariant {self.name} is undef")
            if v is not True:
                return False
        return True


def evaluate_all(machine, fn, state, mon=None):
    """The values of a term for every choice of the monitored values it reads (those in
    ``mon`` are fixed)."""
    from ..semantics.machine import Enumerator
    prefix: list = []
    while True:
        ch = Enumerator(prefix)
        ctx = Ctx(machine, state, ch)
        if mon:
            ctx.mon = dict(mon)
        yield fn(ctx)
        prefix = next_prefix(ch.log)
        if prefix is None:
            return


def spec_properties(machine):
    """The spec's own invariants, split into state and step checks."""
    state, step = [], []
    for p in machine.spec.properties:
        if p.kind != "invariant":
            continue
        if mentions_monitored(p.body):
            step.append(MonitoredInvariant(p, machine))
        else:
            state.append(StateProperty(p, machine))
    return state, step
