"""The explored configurations of a spec, observed rule by rule.

A *configuration* is a reachable state together with one resolution of its step: the values
of the monitored locations the step reads and the alternatives of its ``choose`` rules.  This
module explores the reachable states breadth first and, from each, runs the step once per
configuration (every ``choose`` candidate separately: the machine's grouping of candidates
by effect is off), with a rule hook that records each activation of a rule occurrence: the
branch an ``if`` took, the case a ``switch`` took, whether a ``choose``/``forall`` found
elements, the location and value of an update.

A configuration whose step fails (an inconsistent update, a value outside a subset domain,
an undef guard) has no successor, but its activations count and the exploration goes on.
In an inconsistent step every update still runs (the clash is recorded, the step goes on),
so every clash of the step is seen.

This is the one place that drives the explorer's storage; the checks (advise, coverage,
testgen) read what it records.
"""
from __future__ import annotations

import time

from ..errors import AsmError, InconsistentUpdate
from ..semantics import ir
from ..semantics.choice import Chooser, Enumerator, Prune
from ..semantics.machine import Machine
from ..semantics.state import UpdateSet, apply_updates, same_value
from ..semantics.terms import Ctx, Thunk, Undetermined
from ..semantics.choice import next_prefix


class Event:
    """One activation of a rule occurrence in one configuration."""

    __slots__ = ("node", "parent", "outcome", "key", "value", "binding", "before", "vector")

    def __init__(self, node, parent):
        self.vector = None      # if, with conditions on: the value of each condition of the guard
        self.node = node
        self.parent = parent
        self.outcome = None     # if: "then"/"else"; switch: case number or "otherwise"/"none";
        #                         choose/forall: number of body activations (choose: -1 = ifnone)
        self.key = None         # update: location key
        self.value = None       # update: value assigned
        self.binding = ()       # update: the variables bound at the update
        self.before = None      # update: the location's value in the state of the step


class Clash:
    """Two update activations of one location with different values in one configuration."""

    __slots__ = ("key", "first", "second")

    def __init__(self, key, first, second):
        self.key = key
        self.first = first      # Event (or (span, value) when only the error told us)
        self.second = second


class _RecordingUpdates:
    """Stands for an update set at one update rule: records the location and value, and lets
    the step go on past an inconsistent update (the clash is recorded)."""

    __slots__ = ("ups", "ev", "tracer")

    def __init__(self, ups, ev, tracer):
        self.ups = ups
        self.ev = ev
        self.tracer = tracer

    def add(self, key, value, span, agent, rule, machine):
        ev = self.ev
        ev.key = key
        ev.value = value
        tr = self.tracer
        seen = tr.written.setdefault(id(self.ups), (self.ups, {}))[1].setdefault(key, [])
        for other in seen:
            if not same_value(other.value, value):
                tr.clashes.append(Clash(key, other, ev))
        seen.append(ev)
        try:
            self.ups.add(key, value, span, agent, rule, machine)
        except InconsistentUpdate:
            if not tr.lenient:
                raise
            tr.inconsistent = True


class Tracer:
    """The rule hook: wraps each compiled rule so that running it records an :class:`Event`."""

    def __init__(self, lenient: bool = True, conditions: bool = False):
        self.lenient = lenient          # an inconsistent update is recorded and the step goes on
        self.conditions = conditions    # record the value of each condition of an if's guard (MC/DC)
        self.machine = None
        self.events: list[Event] = []
        self.stack: list[int] = []
        self.clashes: list[Clash] = []
        self.written: dict = {}
        self.inconsistent = False

    def reset(self):
        self.events = []
        self.stack = []
        self.clashes = []
        self.written = {}
        self.inconsistent = False

    def __call__(self, r: ir.Rule, fn):
        tracer = self
        if isinstance(r, ir.Update):
            def update(ctx, ups):
                ev = tracer._enter(r)
                try:
                    ev.binding = _binding(ctx)
                    fn(ctx, _RecordingUpdates(ups, ev, tracer))
                    ev.before = ctx.base.get(ev.key)
                finally:
                    tracer.stack.pop()
            return update
        if isinstance(r, ir.If) and self.conditions and len(conditions(r.cond)) > 1:
            atoms = [self.machine.term(a) for a in conditions(r.cond)]

            def if_conditions(ctx, ups):
                ev = tracer._enter(r)
                p = len(tracer.events) - 1
                st, env = ctx.st, dict(ctx.env)
                ok = False
                try:
                    fn(ctx, ups)
                    ok = True
                finally:
                    tracer.stack.pop()
                    _outcome(r, ev, tracer.events, p, ok)
                if ok:
                    ev.vector = _condition_values(ctx, st, env, atoms)
            return if_conditions
        if isinstance(r, (ir.If, ir.SwitchRule, ir.Choose, ir.Forall)):
            def branching(ctx, ups):
                ev = tracer._enter(r)
                p = len(tracer.events) - 1
                ok = False
                try:
                    fn(ctx, ups)
                    ok = True
                finally:
                    tracer.stack.pop()
                    _outcome(r, ev, tracer.events, p, ok)
            return branching

        def plain(ctx, ups):
            tracer._enter(r)
            try:
                fn(ctx, ups)
            finally:
                tracer.stack.pop()
        return plain

    def _enter(self, r):
        ev = Event(r, self.stack[-1] if self.stack else -1)
        self.stack.append(len(self.events))
        self.events.append(ev)
        return ev


def conditions(t) -> list:
    """The conditions of a guard: its operands under and, or, implies and not."""
    if isinstance(t, ir.Call) and t.name in ("and", "or", "implies") and len(t.args) == 2:
        return conditions(t.args[0]) + conditions(t.args[1])
    if isinstance(t, ir.Call) and t.name == "not" and len(t.args) == 1:
        return conditions(t.args[0])
    return [t]


class _NoChoice(Chooser):
    """Refuses every choice: a condition that reads a monitored location the step did not read
    has no value in this configuration."""

    def choose(self, kind, label, options, values_repr=None):
        raise _Unread()


class _Unread(Exception):
    pass


def _condition_values(ctx, st, env, atoms) -> tuple:
    """Each condition's value (True/False, None for undef, "?" when it reads a monitored location
    the step did not read), in the state and bindings of the guard's evaluation."""
    c = Ctx(ctx.machine, st, _NoChoice())
    c.base = ctx.base
    c.env = dict(env)
    c.mon = dict(ctx.mon)
    c.self_ = ctx.self_
    c.lazy = dict(ctx.lazy)
    c.fresh = dict(ctx.fresh)
    out = []
    for a in atoms:
        try:
            v = a(c)
        except (_Unread, AsmError):
            v = "?"
        out.append(v if v in (True, False, None, "?") else "?")
    return tuple(out)


def _binding(ctx) -> tuple:
    out = []
    for u, v in ctx.env.items():
        if type(v) is Thunk:
            continue
        try:
            hash(v)
        except TypeError:
            v = repr(v)
        out.append((u, type(v) is bool, v))
    return tuple(out)


def _outcome(r, ev: Event, events: list, p: int, ok: bool) -> None:
    """What the branching rule at events[p] did, read from its child activations."""
    children = [e for e in events[p + 1:] if e.parent == p]
    first = children[0].node if children else None
    if isinstance(r, ir.If):
        if first is r.then:
            ev.outcome = "then"
        elif first is not None and first is r.other:
            ev.outcome = "else"
        elif ok:
            ev.outcome = "else"          # guard false, no else branch
    elif isinstance(r, ir.SwitchRule):
        for i, (_, body) in enumerate(r.cases):
            if first is body:
                ev.outcome = i
                return
        if first is not None and first is r.other:
            ev.outcome = "otherwise"
        elif ok:
            ev.outcome = "none"
    elif isinstance(r, ir.Choose):
        if first is r.body:
            ev.outcome = 1
        elif ok or first is not None:
            ev.outcome = 0               # no candidate (ifnone, if any, ran)
    else:   # forall
        ev.outcome = sum(1 for e in children if e.node is r.body)


class Configuration:
    """One resolution of the step from one state."""

    __slots__ = ("state", "picks", "log", "events", "clashes", "error", "target", "mon")

    def __init__(self, state, picks, log, events, clashes, error, target, mon):
        self.state = state          # id of the stored state
        self.picks = picks          # the choices (replayable with ScriptChooser)
        self.log = log
        self.events = events
        self.clashes = clashes
        self.error = error          # AsmError ending the step, or None
        self.target = target        # id of the successor, or None
        self.mon = mon


def review_machine(spec, options: dict | None = None, lenient: bool = True, conditions: bool = False):
    """A machine for review: the rule hook on, every choose candidate a configuration of its own."""
    opts = dict(options or {})
    tracer = Tracer(lenient, conditions)
    opts["rule_hook"] = tracer
    opts["dedupe"] = False
    # the tracer compiles the conditions of guards with the machine it observes
    m = Machine.__new__(Machine)
    tracer.machine = m
    Machine.__init__(m, spec, opts)
    return m, tracer


def run_step(machine: Machine, tracer: Tracer, state: dict, chooser):
    """One step of ``machine`` with the tracer on: (events, clashes, error, next state or None, mon)."""
    tracer.reset()
    ctx = Ctx(machine, state, chooser)
    ups = UpdateSet()
    err = None
    nxt = None
    try:
        if machine.main is not None:
            machine.main(ctx, ups)
        if not tracer.inconsistent:
            nxt = apply_updates(state, ups, machine.keep_undef)
            if ctx.lazy:
                for k, v in ctx.lazy.items():
                    if k not in nxt and k not in ups.locs:
                        nxt[k] = v
    except Prune:
        raise
    except Undetermined:
        raise
    except AsmError as e:
        err = e
    if tracer.inconsistent and err is None:
        c = tracer.clashes[0]
        err = InconsistentUpdate(c.second.node.span, f"inconsistent update of {machine.location_text(c.key)}: "
                                 f"two update rules assign it different values")
    return tracer.events, tracer.clashes, err, nxt, ctx.mon


class Space:
    """The explored configurations (see the module text)."""

    def __init__(self, spec, options: dict | None = None, *, max_states=None, max_seconds=None,
                 max_configurations=1_000_000, observer=None, conditions=False):
        from ..explore.bfs import Explorer
        self.spec = spec
        self.machine, self.tracer = review_machine(spec, options, conditions=conditions)
        self.explorer = Explorer(self.machine)
        self.max_states = max_states
        self.max_seconds = max_seconds
        self.max_configurations = max_configurations
        self.observer = observer        # called with each Configuration
        self.states = 0
        self.transitions = 0
        self.configurations = 0
        self.incomplete: str | None = None
        self.seconds = 0.0
        self.initial: list[int] = []

    def state(self, sid: int) -> dict:
        return self.explorer.state(sid)

    def depth(self, sid: int) -> int:
        return self.explorer.depth_of[sid]

    def run(self, on_state=None):
        """Explore; ``on_state(sid, state)`` sees each new state, the observer each configuration."""
        ex = self.explorer
        m = self.machine
        t0 = time.perf_counter()
        frontier = []
        self.tracer.reset()
        for log, st in m.initial_states():
            if not ex._invar_ok(st):
                continue
            sid, new = ex._add(ex._norm(st), -1, tuple(c.pick for c in log), 0)
            if new:
                frontier.append(sid)
                self.initial.append(sid)
                if on_state is not None:
                    on_state(sid, ex.state(sid))
        depth = 0
        stop = False
        while frontier and not stop:
            nxt_frontier = []
            for sid in frontier:
                st = ex.state(sid)
                targets = set()
                prefix: list = []
                count = 0
                while True:
                    ch = Enumerator(prefix)
                    try:
                        events, clashes, err, nxt, mon = run_step(m, self.tracer, st, ch)
                    except Prune:
                        events = None
                    if events is not None:
                        picks = tuple(c.pick for c in ch.log)
                        tid = None
                        if nxt is not None and (not ex.invars or (ex._invar_ok(st, mon) and ex._invar_ok(nxt))):
                            tid, new = ex._add(ex._norm(nxt), sid, picks, depth + 1)
                            targets.add(tid)
                            if new:
                                nxt_frontier.append(tid)
                                if on_state is not None:
                                    on_state(tid, ex.state(tid))
                        elif nxt is not None:
                            events = None       # excluded by an INVAR: not a configuration
                        if events is not None:
                            self.configurations += 1
                            count += 1
                            if self.observer is not None:
                                self.observer(Configuration(sid, picks, ch.log, events, clashes, err, tid, mon))
                    if count > self.max_configurations:
                        raise AsmError(None, f"more than {self.max_configurations} configurations from one state")
                    prefix = next_prefix(ch.log)
                    if prefix is None:
                        break
                self.transitions += len(targets)
                if self.max_states is not None and len(ex.frozen) >= self.max_states:
                    self.incomplete = f"state limit {self.max_states} reached"
                    stop = True
                    break
                if self.max_seconds is not None and time.perf_counter() - t0 >= self.max_seconds:
                    self.incomplete = f"time limit {self.max_seconds} s reached"
                    stop = True
                    break
            depth += 1
            frontier = nxt_frontier
        self.states = len(ex.frozen)
        self.seconds = time.perf_counter() - t0
        return self

    # ------------------------------------------------------------------ paths
    def path_to(self, sid: int) -> list[int]:
        return self.explorer.path_to(sid)
