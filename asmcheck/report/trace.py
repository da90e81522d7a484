"""Counterexample traces: rebuilt from parent pointers, replayed, then rendered."""
from __future__ import annotations

from dataclasses import dataclass, field

from ..semantics.printer import location_sort_key, location_text
from ..semantics.state import is_dom_key, same_value
from ..semantics.values import show


@dataclass
class TraceStep:
    number: int                    # 0 for the initial state
    choices: list                  # Choice records of the step that led here
    state: dict
    changed: dict                  # location key -> new value
    updates: object = None         # the update set of the step (None for the initial state)


@dataclass
class Trace:
    prop: object
    steps: list = field(default_factory=list)
    kind: str = "state"            # state: the last state violates; step: the last step does
    message: str = ""


def build_trace(explorer, violation) -> Trace:
    """The shortest trace to a violation, replayed through the step function."""
    path = explorer.path_to(violation.source if violation.source >= 0 else violation.state)
    if violation.source >= 0:
        replayed = explorer.replay(path, violation.picks, violation.state)
        kind = "step"
    else:
        replayed = explorer.replay(path)
        kind = "state"
    steps = []
    prev = None
    for i, (st, log, ups, mon) in enumerate(replayed):
        if prev is None:
            changed = dict(st)
        else:
            changed = {k: st.get(k) for k in set(prev) | set(st) if not same_value(prev.get(k), st.get(k))}
        steps.append(TraceStep(i, log, st, changed, ups))
        prev = st
    return Trace(violation.prop, steps, kind, violation.message)


def choice_text(c) -> str:
    if c.kind == "monitored":
        return f"{c.label} = {show(c.value)}"
    if isinstance(c.value, dict):
        text = ", ".join(f"{k} = {show(v)}" for k, v in c.value.items())
        return f"{c.label}: {text}"
    return f"{c.label}: {c.value!r}"


def _key_order(machine, k):
    if is_dom_key(k):
        return ("~", 0, k[1])
    return location_sort_key(machine, k)


def _loc(machine, k) -> str:
    if is_dom_key(k):
        return k[1]
    return location_text(machine, k)


def _val(k, v) -> str:
    if is_dom_key(k):
        return "{" + ", ".join(e.name for e in (v or ())) + "}"
    return show(v)


def flat_choices(choices) -> list:
    """The choices of a step, with the monitored values read inside choose bodies."""
    out = []
    for c in choices:
        out.append(c)
        for n in (getattr(c, "nested", None) or ()):
            out.extend(x for x in flat_choices([n]) if x.kind == "monitored" or x is not n)
    return out


def trace_text(machine, trace: Trace, color: bool = False) -> list[str]:
    """Per step: the choices and inputs taken, then only the locations that changed."""
    bold = (lambda s: f"\x1b[1m{s}\x1b[0m") if color else (lambda s: s)
    dim = (lambda s: f"\x1b[2m{s}\x1b[0m") if color else (lambda s: s)
    out = []
    for st in trace.steps:
        if st.number == 0:
            out.append(bold("state 0 (initial)") + ":")
        else:
            ch = "; ".join(choice_text(c) for c in flat_choices(st.choices))
            out.append(bold(f"step {st.number}") + (dim(f"  [{ch}]") if ch else "") + ":")
        keys = sorted(st.changed, key=lambda k: _key_order(machine, k))
        for k in keys:
            out.append(f"    {_loc(machine, k)} = {_val(k, st.changed[k])}")
        if not keys and st.number > 0:
            out.append("    (no change)")
    return out


def trace_json(machine, trace: Trace) -> list[dict]:
    from ..commands import _json_value
    entries = []
    for st in trace.steps:
        entries.append({
            "step": st.number,
            "choices": [{"kind": c.kind, "at": c.label, "value": _json_value(c.value)} for c in st.choices],
            "changed": {_loc(machine, k): _json_value(st.changed[k])
                        for k in sorted(st.changed, key=lambda k: _key_order(machine, k))},
            "state": {_loc(machine, k): _json_value(st.state[k])
                      for k in sorted(st.state, key=lambda k: _key_order(machine, k))},
        })
    return entries
