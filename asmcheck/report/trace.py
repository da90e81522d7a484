"""Counterexample traces rendered: text (as ``asmcheck explore`` prints them) and JSON
(``docs/trace.schema.json``).  The traces themselves are :mod:`asmcheck.explore.trace`."""
from __future__ import annotations

import re

from ..explore.trace import (Trace, TraceStep, build_trace, display_choices, display_names,  # noqa: F401
                             state_elements, trace_steps)
from ..semantics.printer import location_sort_key, location_text
from ..semantics.state import is_dom_key
from ..semantics.values import AbstractValue, BagV, EnumValue, MapV, RuleValue, SeqV, SetV, show


def json_value(v):
    """A value as JSON: scalars as they are, elements by name, collections tagged."""
    if v is None or isinstance(v, (bool, int, float, str)):
        return v
    if isinstance(v, (EnumValue, AbstractValue)):
        return v.name
    if isinstance(v, SetV):
        return {"set": [json_value(x) for x in v.ordered()]}
    if isinstance(v, SeqV):
        return {"seq": [json_value(x) for x in v]}
    if isinstance(v, BagV):
        return {"bag": [json_value(x) for x in v]}
    if isinstance(v, MapV):
        return {"map": [[json_value(k), json_value(x)] for k, x in v]}
    if isinstance(v, tuple):
        return {"tuple": [json_value(x) for x in v]}
    if isinstance(v, dict):
        return {k: json_value(x) for k, x in v.items()}
    if isinstance(v, RuleValue):
        return {"rule": v.rule.name}
    return show(v)


def choice_text(c) -> str:
    """A choice as a trace shows it (pass Choice records from :meth:`TraceStep.shown_choices`)."""
    if c.kind == "monitored":
        return f"{c.label} = {show(c.value)}"
    if isinstance(c.value, dict):
        text = ", ".join(f"{k} = {show(v)}" for k, v in c.value.items())
        return f"{c.label}: {text}"
    return f"{c.label}: {c.value!r}"


def key_order(machine, k):
    """The sort key of a location (domains of extend-made elements last)."""
    if is_dom_key(k):
        return ("~", 0, k[1])
    return location_sort_key(machine, k)


def location_name(machine, k) -> str:
    if is_dom_key(k):
        return k[1]
    return location_text(machine, k)


def value_text(k, v) -> str:
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
            ch = "; ".join(choice_text(c) for c in flat_choices(st.shown_choices()))
            out.append(bold(f"step {st.number}") + (dim(f"  [{ch}]") if ch else "") + ":")
        keys = sorted(st.changed, key=lambda k: key_order(machine, k))
        for k in keys:
            out.append(f"    {location_name(machine, k)} = {value_text(k, st.changed[k])}")
        if not keys and st.number > 0:
            out.append("    (no change)")
    if trace.failing is not None:
        ch = "; ".join(choice_text(c) for c in flat_choices(trace.failing))
        out.append(bold(f"step {len(trace.steps)}") + (dim(f"  [{ch}]") if ch else "") +
                   ": fails (the step cannot be made)")
    return out


def failing_json(trace: Trace) -> dict | None:
    """The inputs and choices of the step that fails at the end of an 'error' trace."""
    if trace.failing is None:
        return None
    return {"step": len(trace.steps),
            "choices": [{"kind": c.kind, "at": c.label, "value": json_value(c.value)} for c in trace.failing]}


def trace_json(machine, trace: Trace) -> list[dict]:
    entries = []
    for st in trace.steps:
        entries.append({
            "step": st.number,
            "choices": [{"kind": c.kind, "at": c.label, "value": json_value(c.value)} for c in st.shown_choices()],
            "changed": {location_name(machine, k): json_value(st.changed[k])
                        for k in sorted(st.changed, key=lambda k: key_order(machine, k))},
            "state": {location_name(machine, k): json_value(st.display[k])
                      for k in sorted(st.display, key=lambda k: key_order(machine, k))},
        })
    return entries


RENAMED = "(up to the names of the elements made by extend)"


def temporal_text(result, machine, color: bool = False) -> list[str]:
    """A temporal result as ``asmcheck explore`` prints it: the verdict, and the replayed
    counterexample (or witness), a lasso marked where its loop starts."""
    self = result
    where = ""
    span = getattr(self.prop, "span", None)
    if span is not None and getattr(span, "line", 0):
        where = f" ({span.short()})"
    fair = f", under fairness: {'; '.join(self.fairness)}" if self.fairness else ""
    kind = {"ltl": "LTL", "ctl": "CTL", "invariant": "invariant"}.get(self.kind, self.kind)
    if self.message:
        return [f"{self.name}{where} ({kind}) cannot be checked: {self.message}"]
    tr = self.trace()
    err = getattr(self, "relative_to", None)
    rel = ""
    if err is not None:
        span = getattr(err, "span", None)
        rel = ", relative to the run-time error" + (f" at {span.short()}" if span is not None and span.line else "")
    head = f"{self.name}{where} ({kind}) {'holds' if self.holds else 'is violated'}{rel}{fair}"
    if tr is None:
        return [head]
    trace, loop, inputs_step = tr
    steps = len(trace.steps) - 1
    what = "witness" if self.holds else "counterexample"
    if loop is not None:
        cyc = steps - loop
        desc = (f" -- {what}, a lasso: {loop} step{'s' if loop != 1 else ''} to the loop, then a loop of "
                f"{cyc} step{'s' if cyc != 1 else ''} repeated for ever:")
    else:
        desc = f" -- {what}, {steps} step{'s' if steps != 1 else ''}:"
    out = [head + desc]
    lines = trace_text(machine, trace, color)
    # mark the loop: the state after step `loop` is where the cycle starts
    back = f"   -> back to state {loop}"
    if loop is not None and trace.steps[-1].display != trace.steps[loop].display:
        # the same stored state, but the elements made by extend carry other display names
        back += " " + RENAMED
    marked = []
    for ln in lines:
        if loop is not None and (ln.startswith("state 0") and loop == 0 or _is_step(ln, loop)):
            ln = ln + f"   <- the loop starts here (state {loop})"
        if loop is not None and _is_step(ln, steps):
            ln = ln + back
        marked.append(ln)
    out += ["  " + ln for ln in marked]
    if inputs_step:
        out.append(f"  (step {steps} only shows the monitored inputs and choices of state {steps - 1}, "
                   f"which are part of its state for the property)")
    if trace.failing is not None:
        out.append(f"  (step {steps + 1} fails: {trace.message}; the run stops there and stays in state {steps} "
                   f"for ever)")
    return out


def temporal_json(result, machine) -> dict:
    """A temporal result as JSON (``docs/trace.schema.json``)."""
    self = result
    out = {"property": self.name, "kind": self.kind, "verdict": self.verdict}
    if self.fairness:
        out["fairness"] = list(self.fairness)
    if self.message:
        out["message"] = self.message
    err = getattr(self, "relative_to", None)
    if err is not None:
        span = getattr(err, "span", None)
        out["relative_to"] = str(span) if span is not None and span.line else ""
    tr = self.trace()
    if tr is not None:
        trace, loop, inputs_step = tr
        out["trace"] = trace_json(machine, trace)
        out["loop_start"] = loop          # the last entry is the same state as this one
        out["witness"] = self.holds
        if inputs_step:
            out["inputs_step"] = True     # the last step only shows the inputs of the state before
        if trace.failing is not None:
            # the path ends with a step that fails: the run stops in the last state for ever
            out["failing_step"] = failing_json(trace)
            out["failing_message"] = trace.message
    else:
        out["trace"] = []
        out["loop_start"] = None
    return out


def _is_step(line: str, n: int) -> bool:
    plain = re.sub(r"\x1b\[[0-9;]*m", "", line)
    return plain.startswith(f"step {n}") and (len(plain) == len(f"step {n}") or plain[len(f"step {n}")] in " :")
