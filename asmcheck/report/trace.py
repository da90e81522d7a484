"""Counterexample traces rendered: text (as ``asmcheck explore`` prints them) and JSON
(``docs/trace.schema.json``).  The traces themselves are :mod:`asmcheck.explore.trace`."""
from __future__ import annotations

from dataclasses import dataclass

from ..explore.trace import (Trace, TraceStep, build_trace, display_choices, display_names,  # noqa: F401
                             state_elements, trace_steps)
from .describe import (ChooseIndex, failing_record, flat_choices as all_choices, key_order,  # noqa: F401
                       location_name, property_text, shown_inputs, step_inputs, step_records, value_text)
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


def flat_choices(choices) -> list:
    """The choices of a step, with the monitored values read inside choose bodies."""
    out = []
    for c in choices:
        out.append(c)
        for n in (getattr(c, "nested", None) or ()):
            out.extend(x for x in flat_choices([n]) if x.kind == "monitored" or x is not n)
    return out


def trace_text(machine, trace: Trace, color: bool = False, loop: int | None = None,
               inputs_step: bool = False) -> list[str]:
    """The steps of a replayed trace as every text report shows them (:func:`trace_lines`):
    per step the rule, its choices and the monitored values it read, then the locations that
    changed (``loop``: a lasso's loop start)."""
    return trace_lines(describe_trace(machine, trace, loop=loop, inputs_step=inputs_step), color)


def failing_json(trace: Trace) -> dict | None:
    """The inputs and choices of the step that fails at the end of an 'error' trace."""
    if trace.failing is None:
        return None
    return {"step": len(trace.steps),
            "choices": [{"kind": c.kind, "at": c.label, "value": json_value(c.value)} for c in trace.failing]}


def _choice_json(c, chooses=None) -> dict:
    out = {"kind": c.kind, "at": c.label, "value": json_value(c.value)}
    if c.kind == "choose" and chooses is not None:
        rule = chooses.rule(c.label)
        if rule:
            out["rule"] = rule          # the rule the choose rule is in
    return out


def _located(machine, step, locs: dict) -> dict:
    """Location key -> value (canonical names of the state before ``step``) as JSON, under the
    trace's display names, in the order of the locations."""
    shown = shown_inputs(step, locs)
    return {location_name(machine, k): json_value(shown[k]) for k in sorted(shown, key=lambda k: key_order(machine, k))}


def trace_json(machine, trace: Trace, chooses=None, inputs=None) -> list[dict]:
    """The steps of a trace as JSON (docs/trace.schema.json): per step the main rule, the
    choices (a choose rule's with the rule it is in; those made inside a choose body after it),
    the monitored values the step read, its update set, the locations it changed and the state."""
    if chooses is None:
        chooses = ChooseIndex(machine.spec)
    if inputs is None:
        inputs = step_inputs(machine, trace)
    entries = []
    for st, mon in zip(trace.steps, inputs):
        entry = {"step": st.number}
        if st.number > 0:
            entry["rule"] = chooses.main
        entry["choices"] = [_choice_json(c, chooses) for c in all_choices(st.shown_choices())]
        if st.number > 0:
            entry["reads"] = _located(machine, st, mon or {})
            ups = getattr(st.updates, "locs", None)
            if ups is not None:
                entry["updates"] = _located(machine, st, {k: u.value for k, u in ups.items()})
        entry["changed"] = {location_name(machine, k): json_value(st.changed[k])
                            for k in sorted(st.changed, key=lambda k: key_order(machine, k))}
        entry["state"] = {location_name(machine, k): json_value(st.display[k])
                          for k in sorted(st.display, key=lambda k: key_order(machine, k))}
        entries.append(entry)
    return entries


# ----------------------------------------------------------------- one renderer of a replayed trace
@dataclass
class TraceView:
    """A replayed trace described for people (what :func:`trace_lines` renders): the gate's
    Counterexample has the same fields."""
    kind: str                       # state: the last state violates; step: the last step; lasso; path
    steps: list                     # [describe.StepRecord]
    loop_start: int | None = None   # lasso: the state the last step goes back to
    failing: object = None          # property 'error': the StepRecord of the step that fails
    inputs_step: bool = False       # the last step only shows the inputs of the state before it
    failing_note: str = ""          # a temporal path that ends with a step that fails: what then
    up_to: str = ""                 # lasso under symmetry reduction: its return is up to this renaming


def describe_trace(machine, trace: Trace, *, kind: str | None = None, loop: int | None = None,
                   inputs_step: bool = False, chooses=None, root=None, inputs=None) -> TraceView:
    """A replayed trace as a :class:`TraceView`: per step the rule, its choices, the monitored
    values it read and what changed."""
    if chooses is None:
        chooses = ChooseIndex(machine.spec)
    recs = step_records(machine, trace, chooses, root, inputs)
    if kind is None:
        kind = "lasso" if loop is not None else trace.kind
    return TraceView(kind, recs, loop, failing_record(machine, trace, chooses, root), inputs_step,
                     up_to=getattr(trace, "up_to", "") or "")


def step_header(rec) -> str:
    """``step 3: r_main chooses $t = master; reads timeUp(master) = true``"""
    if rec.number == 0:
        return "state 0 (initial)"
    parts = []
    rules: dict = {}
    for c in rec.choices:
        if c.kind == "choose":
            rules.setdefault(c.rule or "choose", []).append(c.text)
    for r, items in rules.items():
        parts.append(f"{r} chooses " + ", ".join(items))
    if not parts:
        parts.append(rec.rule)
    reads = [c.text for c in rec.choices if c.kind == "monitored"]
    if reads:
        parts.append("reads " + ", ".join(reads))
    return f"step {rec.number}: " + "; ".join(p for p in parts if p)


def _plural(n: int, word: str = "step") -> str:
    return f"{n} {word}{'s' if n != 1 else ''}"


def cx_summary(cx, what: str = "counterexample") -> str:
    """'shortest counterexample, 3 steps (the last step breaks it)' and the like."""
    n = len(cx.steps) - 1
    steps = _plural(n)
    if cx.kind == "lasso" and cx.loop_start is not None:
        return (f"{what}, {steps}: a lasso, {_plural(cx.loop_start)} to the loop, then a loop of "
                f"{_plural(n - cx.loop_start)} repeated for ever")
    fails = f", then step {n + 1} fails" if getattr(cx, "failing", None) is not None else ""
    if cx.kind in ("lasso", "path"):
        return f"{what}, {steps}{fails}"
    return f"shortest {what}, {steps}" + (fails or (" (the last step breaks it)" if cx.kind == "step" else ""))


def lasso_renamed(cx) -> bool:
    """A lasso whose last state is its loop's first state (as the explorer stores states)
    but shows the elements made by extend under other names (as a simulation names them), or,
    under symmetry reduction, under a renaming of the interchangeable elements."""
    if cx.kind != "lasso" or cx.loop_start is None or not cx.steps:
        return False
    first = next((r for r in cx.steps if r.number == cx.loop_start), None)
    return first is not None and first is not cx.steps[-1] and first.state != cx.steps[-1].state


def step_mark(cx, rec) -> str:
    """What a step is in its trace: the violation, where a lasso's loop starts, where it goes back."""
    last = cx.steps[-1].number
    lasso = cx.kind == "lasso" and cx.loop_start is not None
    if lasso and rec.number == last:
        return f"<- back to state {cx.loop_start}" + (" " + renamed_note(cx) if lasso_renamed(cx) else "")
    if lasso and rec.number == cx.loop_start:
        return f"<- the loop starts here (state {cx.loop_start})"
    if rec.number == last and getattr(cx, "failing", None) is None:
        if cx.kind == "step":
            return "<- breaks the property"
        if cx.kind == "state":
            return "<- violates the property"
    return ""


def no_change_text(cx, rec) -> str:
    """The line of a step that changed no location: in a lasso the state repeats, and the
    trace says so."""
    if cx.kind != "lasso" or cx.loop_start is None:
        return "(no change)"
    if rec.number == cx.steps[-1].number and cx.loop_start == rec.number - 1:
        return "(no change: the state repeats for ever)"
    return f"(no change: the state repeats, state {rec.number} = state {rec.number - 1})"


def trace_lines(cx, color: bool = False) -> list[str]:
    """Per step the rule, its choices and the inputs it read, then only the locations that
    changed; the violation, a lasso's loop start and its way back are marked.  The text of
    ``asmcheck explore``, ``asmcheck check`` and the JUnit report; the HTML report shows the same
    step text (:func:`step_header`, :func:`step_mark`, :func:`no_change_text`)."""
    if not cx.steps:
        return list(getattr(cx, "text", None) or [])
    bold = (lambda s: f"\x1b[1m{s}\x1b[0m") if color else (lambda s: s)
    red = (lambda s: f"\x1b[1;31m{s}\x1b[0m") if color else (lambda s: s)
    yellow = (lambda s: f"\x1b[33m{s}\x1b[0m") if color else (lambda s: s)
    out = []
    last = cx.steps[-1].number
    for rec in cx.steps:
        mark = step_mark(cx, rec)
        bad = rec.number == last and mark and cx.kind in ("state", "step")
        out.append((red if bad else bold)(step_header(rec)) + (yellow("  " + mark) if mark else ""))
        for k, v in rec.changed.items():
            out.append(f"    {k} = {v}")
        if not rec.changed and rec.number > 0:
            out.append("    " + no_change_text(cx, rec))
    failing = getattr(cx, "failing", None)
    if failing is not None:
        out.append(red(step_header(failing)) + yellow("  <- fails (the step cannot be made)"))
    if getattr(cx, "inputs_step", False) and len(cx.steps) > 1:
        n = last
        out.append(f"(step {n} only shows the monitored inputs and choices of state {n - 1}, "
                   f"which are part of its state for the property)")
    if getattr(cx, "failing_note", ""):
        out.append(cx.failing_note)
    return out


def violation_lines(head: str, cx, color: bool = False, formula: str = "", fairness=(),
                    what: str = "counterexample") -> list[str]:
    """A violated property with its counterexample: ``head`` (what is violated, where), the
    summary, the formula, the fairness assumed, then the trace indented."""
    out = [f"{head} -- {cx_summary(cx, what)}:" if cx.steps else head]
    if formula:
        out.append(f"  formula: {formula}")
    if fairness:
        out.append(f"  under fairness: {'; '.join(fairness)}")
    out += ["  " + ln for ln in trace_lines(cx, color)]
    return out


def violation_head(name: str, kind: str, where: str = "", message: str = "", relative: str | None = None) -> str:
    """'inv_x (f.prop:3:11) is violated', 'deadlock', 'a step fails (f.asm:9:14)', with the message;
    ``relative``: the verdict is relative to the run-time error there (' at f.asm:16:25')."""
    if kind == "deadlock" or name == "deadlock":
        text = "deadlock"
    elif kind == "error" or name == "error":
        text = f"a step fails{where}"
    else:
        text = f"{name}{where} is violated"
    if relative is not None:
        text += f", relative to the run-time error{relative}"
    return text + (f": {message}" if message else "")


def failing_note(trace) -> str:
    """A temporal path that ends with a step that fails: the run halts in its last state."""
    if getattr(trace, "failing", None) is None:
        return ""
    n = len(trace.steps) - 1
    return (f"(step {n + 1} fails: {trace.message}; the run stops there and stays in state {n} "
            f"for ever)")


def explore_violation_lines(machine, violation, trace: Trace, color: bool = False) -> list[str]:
    """A safety violation (an invariant, a step property, a deadlock, a step that fails) with its
    shortest trace, as ``asmcheck explore`` prints it."""
    p = violation.prop
    span = getattr(p, "span", None)
    where = f" ({span.short()})" if span is not None and getattr(span, "line", 0) else ""
    head = violation_head(p.name, getattr(p, "kind", ""), where, violation.message)
    formula = property_text(p) if p.name not in ("deadlock", "error") else ""
    return violation_lines(head, describe_trace(machine, trace), color, formula)


RENAMED = "(up to the names of the elements made by extend)"


def renamed_note(cx) -> str:
    """How a lasso whose last state shows its loop's first state under other names says so."""
    up_to = getattr(cx, "up_to", "")
    return f"(up to {up_to})" if up_to else RENAMED


def temporal_text(result, machine, color: bool = False) -> list[str]:
    """A temporal result as ``asmcheck explore`` prints it: the verdict, the formula and the
    replayed counterexample (or witness), a lasso marked where its loop starts."""
    self = result
    where = ""
    span = getattr(self.prop, "span", None)
    if span is not None and getattr(span, "line", 0):
        where = f" ({span.short()})"
    kind = {"ltl": "LTL", "ctl": "CTL", "invariant": "invariant"}.get(self.kind, self.kind)
    if self.message:
        return [f"{self.name}{where} ({kind}) cannot be checked: {self.message}"]
    tr = self.trace()
    err = getattr(self, "relative_to", None)
    rel = None
    if err is not None:
        span = getattr(err, "span", None)
        rel = f" at {span.short()}" if span is not None and span.line else ""
    head = f"{self.name}{where} {'holds' if self.holds else 'is violated'}" + \
        (f", relative to the run-time error{rel}" if rel is not None else "")
    formula = property_text(self.prop)
    if tr is None:
        return [head] + ([f"  formula: {formula}"] if formula else [])
    trace, loop, inputs_step = tr
    view = describe_trace(machine, trace, kind="lasso" if loop is not None else "path", loop=loop,
                          inputs_step=inputs_step)
    view.failing_note = failing_note(trace)
    return violation_lines(head, view, color, formula, self.fairness, "witness" if self.holds else "counterexample")


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
        up_to = getattr(trace, "up_to", "")
        if up_to and loop is not None and trace.steps and trace.steps[loop].state != trace.steps[-1].state:
            # (symmetry reduction: the same state up to a renaming of the interchangeable elements)
            out["loop_up_to"] = up_to
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
