"""Counterexample traces as data: rebuilt from parent pointers and replayed through the step function.

The explorer stores states under canonical names for the elements ``extend`` makes
(:mod:`asmcheck.explore.canonical`), so one element may carry another name in each
replayed state.  A trace is shown under *display names* instead, the ones a plain
simulation of the same run gives: an element keeps its name for its whole life, and each
new element gets the next number of its domain (one more than the highest number the
domain has used so far in the trace).  Each :class:`TraceStep` keeps its canonical state
(steps are re-run from it with the recorded choices) beside the state under display names.
The text, JSON and Avalla renderings are in :mod:`asmcheck.report`.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

from ..errors import AsmError
from ..semantics.choice import Chooser
from ..semantics.state import is_dom_key, same_value
from ..semantics.values import AbstractValue, BagV, MapV, RuleValue, SeqV, SetV, fresh_value, rename, \
    rename_state


@dataclass
class TraceStep:
    number: int                    # 0 for the initial state
    choices: list                  # Choice records of the step that led here
    state: dict                    # the state as the explorer stores it (canonical names)
    changed: dict                  # location key -> new value (display names)
    updates: object = None         # the update set of the step (None for the initial state)
    display: dict | None = None    # the state under display names (None: the same as state)
    names: dict = field(default_factory=dict)
    # ``atom_reads``: monitored values that only the atoms of a temporal property read in the
    # state before the step (location key -> value, canonical names of that state), shown with the
    # values the step read; the step function does not see them
    atom_reads: dict = field(default_factory=dict)
    # ``names``: the display name of each element the step's choices, update set and monitored
    # inputs may hold (elements of the state before the step, and the elements it made);
    # an element not in it is shown as it is

    def __post_init__(self):
        if self.display is None:
            self.display = self.state

    def show(self, v):
        """A value of this step (a choice, an update, an input) under display names."""
        return rename(v, self.names) if self.names else v

    def shown_choices(self) -> list:
        """The step's choices with their values under display names."""
        return display_choices(self.choices, self.names)


@dataclass
class Trace:
    prop: object
    steps: list = field(default_factory=list)
    kind: str = "state"            # state: the last state violates; step: the last step does
    message: str = ""
    # a step that fails (property 'error'): the inputs and choices it had taken when it failed
    failing: list | None = None
    # a lasso of a search under symmetry reduction: what its last state equals its loop's first
    # state up to ("the symmetry of Proc's 4 unnamed elements"); "" when the two are equal
    up_to: str = ""


def _elements(v, out: set) -> None:
    """Collect into ``out`` the elements made by ``extend`` inside the value ``v``."""
    t = type(v)
    if t is AbstractValue:
        if v.serial > 0:
            out.add(v)
    elif t in (tuple, SeqV, BagV, SetV):
        for x in v:
            _elements(x, out)
    elif t is MapV:
        for a, b in v:
            _elements(a, out)
            _elements(b, out)
    elif t is RuleValue and v.agent is not None:
        _elements(v.agent, out)


def state_elements(state: dict) -> set:
    """The elements made by ``extend`` in a state: in its domains, location arguments and values."""
    out: set = set()
    for k, v in state.items():
        if is_dom_key(k):
            for e in v or ():
                _elements(e, out)
            continue
        if type(k) is tuple:
            _elements(k[1], out)
        _elements(v, out)
    return out


def _by_serial(e):
    return (e.domain, e.serial, e.name)


def display_names(replayed) -> list[tuple[dict, dict]]:
    """Display names along a replayed run.

    ``replayed``: per state, (canonical state, raw successor, renaming); for the initial
    state the last two are None; for a step, the raw successor is the state as the step
    function made it from the previous canonical state (its old elements are that state's,
    its new ones fresh) and the renaming maps raw elements to their canonical names (the
    canonicaliser's ``last_mapping``: elements not in it keep their name).

    Returns per state (canonical element -> display element, for the elements of the
    canonical state; raw element -> display element, for the values of the step that led
    there).  Both are empty when no element changes its name."""
    out = []
    top: dict = {}            # domain -> the highest number it has used so far
    prev: dict = {}
    for i, (st, raw, mapping) in enumerate(replayed):
        if i == 0 or raw is None:
            now = {e: e for e in state_elements(st)}
            for e in now:
                top[e.domain] = max(top.get(e.domain, 0), e.serial)
            out.append(({}, {}))
            prev = now
            continue
        step = dict(prev)
        # the elements the step made, numbered in the order the step function made them
        for r in sorted(state_elements(raw) - prev.keys(), key=_by_serial):
            k = top.get(r.domain, 0) + 1
            top[r.domain] = k
            step[r] = fresh_value(r.domain, k)
        back = {c: r for r, c in (mapping or {}).items()}
        now = {}
        for e in sorted(state_elements(st), key=_by_serial):
            r = back.get(e, e)
            d = step.get(r)
            if d is None:         # not from the raw successor (should not happen): a new number
                k = top.get(e.domain, 0) + 1
                top[e.domain] = k
                d = step[r] = fresh_value(e.domain, k)
            now[e] = d
        out.append(({e: d for e, d in now.items() if e is not d},
                    {r: d for r, d in step.items() if r is not d}))
        prev = now
    return out


# an element's name in a location's text: D!k (not inside a longer name)
_ELEMENT_NAME = re.compile(r"(?<![\w!])[A-Za-z_][A-Za-z0-9_]*![0-9]+(?![\w!])")


def display_choices(choices, names: dict) -> list:
    """Copies of the Choice records with their values (and nested choices) renamed, and the
    elements named in a monitored location's label."""
    if not names or not choices:
        return list(choices or ())
    by_name = {a.name: b.name for a, b in names.items()}
    out = []
    for c in choices:
        v = c.value
        if isinstance(v, dict):
            v = {k: rename(x, names) for k, x in v.items()}
        else:
            v = rename(v, names)
        label = c.label
        if c.kind == "monitored" and isinstance(label, str) and "!" in label:
            label = _ELEMENT_NAME.sub(lambda mt: by_name.get(mt.group(0), mt.group(0)), label)
        nested = getattr(c, "nested", None)
        out.append(replace(c, value=v, label=label, nested=display_choices(nested, names) if nested else nested))
    return out


def trace_steps(replayed) -> list[TraceStep]:
    """TraceSteps of a replayed run: per state (canonical state, choices log, update set,
    raw successor or None, renaming or None), as :func:`display_names` reads them."""
    names = display_names([(st, raw, mapping) for st, _, _, raw, mapping in replayed])
    steps = []
    prev = None
    for i, ((st, log, ups, _, _), (state_names, step_names)) in enumerate(zip(replayed, names)):
        shown = rename_state(st, state_names) if state_names else st
        if prev is None:
            changed = dict(shown)
        else:
            changed = {k: shown.get(k) for k in set(prev) | set(shown) if not same_value(prev.get(k), shown.get(k))}
        steps.append(TraceStep(i, log, st, changed, ups, shown, step_names))
        prev = shown
    return steps


def atom_values(machine, items, state: dict, mon: dict, chooser=None):
    """The truth values of the atoms ``items`` (``temporal.formula`` atoms) in ``state`` with the
    monitored values ``mon``, and the monitored values they read (``mon`` and those ``chooser``
    chose, location key -> value).  An undef atom is false.  ``chooser`` None: every value the
    atoms read must be in ``mon`` (an AsmError otherwise)."""
    from ..semantics.terms import Ctx
    ctx = Ctx(machine, state, chooser if chooser is not None else _NoChoice())
    ctx.mon = dict(mon or {})
    vec = []
    for a in items:
        ctx.env = dict(a.env) if a.env else {}
        vec.append(a.fn(ctx) is True)
    return tuple(vec), ctx.mon


class _NoChoice(Chooser):
    """A chooser for atoms whose monitored values are all given: any other read is an error."""

    def choose(self, kind, label, options, values_repr=None):
        raise AsmError(None, f"{label} is read but has no value in the trace")

    def value(self, label, codomain):
        raise AsmError(None, f"{label} is read but has no value in the trace")


def atom_reads(machine, items, state: dict, mon: dict, vec) -> dict | None:
    """The monitored values the atoms ``items`` read in ``state`` beyond those of the step
    (``mon``), the first in the enumeration order (each location's values in its domain's order,
    in the order the atoms read them) with which the atoms' truth values are ``vec``: location key
    -> value ({} when the atoms read nothing else), None when no such values exist."""
    from ..semantics.choice import Enumerator, next_prefix
    mon = mon or {}
    want = tuple(bool(x) for x in vec)
    prefix: list = []
    while True:
        ch = Enumerator(prefix)
        got, read = atom_values(machine, items, state, mon, ch)
        if got == want:
            return {k: v for k, v in read.items() if k not in mon}
        prefix = next_prefix(ch.log)
        if prefix is None:
            return None


def term_ids(terms) -> set:
    """The ids of the IR terms below ``terms`` (the bodies of the derived functions they call too):
    which atoms of a temporal structure a property's formula is made of."""
    from ..semantics import ir
    out: set = set()
    stack = list(terms)
    while stack:
        t = stack.pop()
        if isinstance(t, (list, tuple)):
            stack.extend(t)
            continue
        if not isinstance(t, ir.Term) or id(t) in out:
            continue
        out.add(id(t))
        if isinstance(t, ir.Loc) and t.func.kind in ("derived", "static") and t.func.body is not None:
            stack.append(t.func.body)
        for v in vars(t).values():
            if isinstance(v, (ir.Term, list, tuple)):
                stack.append(v)
    return out


def build_trace(explorer, violation) -> Trace:
    """The shortest trace to a violation, replayed through the step function."""
    path = explorer.path_to(violation.source if violation.source >= 0 else violation.state)
    if violation.source >= 0:
        replayed = explorer.replay(path, violation.picks, violation.state)
        kind = "step"
    else:
        replayed = explorer.replay(path)
        kind = "state"
    # (state, choices, update set, monitored values[, raw successor, renaming])
    steps = trace_steps([(r[0], r[1], r[2], r[4] if len(r) > 5 else None, r[5] if len(r) > 5 else None)
                         for r in replayed])
    err = getattr(violation, "error", None)
    message = violation.message
    sym = getattr(explorer, "sym", None)
    if sym is not None and err is not None and violation.prop.name == "error" and steps:
        # (symmetry reduction: the failing branch of the trace's last, concrete state, not the
        # representative's, so that its choices name the trace's elements)
        concrete = sym.concrete_error(explorer.m, steps[-1].state, err)
        if concrete is not None:
            err, message = concrete, concrete.message
    failing = getattr(err, "choices", None) if violation.prop.name == "error" else None
    return Trace(violation.prop, steps, kind, message, list(failing) if failing is not None else None)
