"""How a counterexample is described to people: locations in the source, the choose rules of
a spec, and per step the rule, its choices, the inputs it read and what changed.  The gate
(:mod:`.gate`) and the Avalla export (:mod:`.avalla_export`) both build on it."""
from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

from ..semantics.printer import location_sort_key, location_text
from ..semantics.state import is_dom_key
from ..semantics.values import show


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



@dataclass
class Location:
    path: str
    line: int
    column: int
    end_column: int = 0             # 0: unknown

    def json(self) -> dict:
        out = {"path": self.path, "line": self.line, "column": self.column}
        if self.end_column:
            out["end_column"] = self.end_column
        return out

    def __str__(self) -> str:
        return f"{self.path}:{self.line}:{self.column}"


@dataclass
class Choice:
    """One choice of a step: a choose rule's bindings, or a monitored value read."""
    kind: str                       # choose | monitored
    text: str                       # "$t = master" / "timeUp(master) = true"
    rule: str = ""                  # the rule the choose rule is in
    at: Location | None = None      # the choose rule's position


@dataclass
class StepRecord:
    number: int                     # 0: the initial state
    rule: str                       # the main rule
    choices: list                   # [Choice]: chooses (nested ones too), then monitored values
    changed: dict                   # location text -> value text
    state: dict                     # location text -> value text


def display_path(path: str, root: str | None = None) -> str:
    """``path`` relative to ``root`` (the working folder) when it lies below it, with '/'."""
    root = os.path.abspath(root or os.getcwd())
    ap = os.path.abspath(path)
    try:
        rel = os.path.relpath(ap, root)
    except ValueError:
        return Path(ap).as_posix()
    if rel.startswith(".."):
        return Path(ap).as_posix()
    return Path(rel).as_posix()


def span_location(span, name: str | None = None, root: str | None = None) -> Location | None:
    if span is None or not getattr(span, "line", 0):
        return None
    end = 0
    if name:
        from ..errors import SOURCES
        text = SOURCES.line(span.path, span.line)
        if text is not None:
            start = max(span.col - 1, 0)
            i = text.find(name, start)
            # the name itself, or a keyword and the name ('invariant inv_x', 'LTLSPEC ltl_x')
            if i >= 0 and re.fullmatch(r"(?:[A-Za-z]+\s+)?", text[start:i]):
                end = i + len(name) + 1
    return Location(display_path(span.path, root), span.line, span.col, end)


def source_text(path: str, line: int, col: int, end_line: int, end_col: int) -> str | None:
    """The source text from (line, col) to (end_line, end_col), the end exclusive."""
    from ..errors import SOURCES
    lines = []
    for ln in range(line, end_line + 1):
        text = SOURCES.line(path, ln)
        if text is None:
            return None
        lines.append(text)
    if not lines:
        return None
    lines[-1] = lines[-1][:max(end_col - 1, 0)]
    lines[0] = lines[0][max(col - 1, 0):]
    return "\n".join(lines)


def term_text(span) -> str:
    """The source text of a term (by its span), comments removed, on one line."""
    if span is None or not span.line or not span.end_line:
        return ""
    return one_line(source_text(span.path, span.line, span.col, span.end_line, span.end_col) or "")


def one_line(text: str) -> str:
    """AsmetaL text without comments, its blanks (outside strings) squeezed to one space."""
    out = []
    i, n = 0, len(text)
    blank = False
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
            blank = True
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            i = n if j < 0 else j + 2
            blank = True
            continue
        if c in " \t\r\n\f":
            blank = True
            i += 1
            continue
        if blank and out:
            out.append(" ")
        blank = False
        if c == '"':
            j = text.find('"', i + 1)
            j = n if j < 0 else j + 1
            out.append(text[i:j])
            i = j
            continue
        out.append(c)
        i += 1
    return "".join(out)


class ChooseIndex:
    """Choose rules of a spec by the label the machine gives them (``choose at f.asm:l:c``)."""

    def __init__(self, spec):
        from ..semantics import ir
        self.by_label: dict = {}
        self.main = spec.main.name if spec.main is not None else ""
        for rd in spec.rules:
            if rd.body is None:
                continue
            for node in _walk(rd.body):
                if isinstance(node, ir.Choose):
                    label = f"choose at {node.span.short()}"
                    self.by_label.setdefault(label, (rd, node))

    def rule(self, label: str) -> str:
        hit = self.by_label.get(label)
        return hit[0].name if hit else ""

    def span(self, label: str):
        hit = self.by_label.get(label)
        return hit[1].span if hit else None

    def node(self, label: str):
        hit = self.by_label.get(label)
        return hit if hit else (None, None)


def _walk(node):
    """Every IR term and rule below ``node`` (not the bodies of called rules)."""
    from dataclasses import fields, is_dataclass
    from ..semantics import ir
    stack = [node]
    seen = set()
    while stack:
        x = stack.pop()
        if isinstance(x, (list, tuple)):
            stack.extend(reversed(x))
            continue
        if not is_dataclass(x) or isinstance(x, (type, ir.RuleDecl, ir.Function, ir.Var)) or id(x) in seen:
            continue
        seen.add(id(x))
        yield x
        for f in fields(x):
            if f.name not in ("type", "span"):
                stack.append(getattr(x, f.name))


def flat_choices(log) -> list:
    """A step's choices in order, those made inside a choose rule's body after it."""
    out = []
    for c in log or ():
        out.append(c)
        if getattr(c, "nested", None):
            out.extend(flat_choices(c.nested))
    return out


def step_inputs(machine, trace) -> list[dict]:
    """Per step of ``trace``: the monitored values it read (location key -> value), found by
    running the step again with its recorded choices.  Step 0: the initialisation's."""
    from ..semantics.machine import ScriptChooser
    out = [dict(getattr(machine, "init_mon", {}) or {})]
    for prev, st in zip(trace.steps, trace.steps[1:]):
        try:
            _, _, ctx = machine.step(prev.state, ScriptChooser([c.pick for c in st.choices]))
            # with the values only a temporal property's atoms read (TraceStep.atom_reads)
            out.append({**ctx.mon, **(getattr(st, "atom_reads", None) or {})})
        except Exception:    # a step that fails (an error trace): no inputs known
            out.append({})
    return out


def shown_inputs(step, mon: dict) -> dict:
    """The monitored values a step read (as :func:`step_inputs` finds them, in the canonical
    names of the state before it) under the trace's display names."""
    if not mon or not getattr(step, "names", None):
        return mon
    return {(k if type(k) is not tuple else (k[0], step.show(k[1]))): step.show(v) for k, v in mon.items()}


def choose_records(log, chooses: ChooseIndex, root=None) -> list[Choice]:
    """The choose rules' choices of a step's log (nested ones after theirs), each with the rule it is in."""
    from ..semantics.values import show
    out = []
    for c in flat_choices(log):
        if c.kind != "choose":
            continue
        if isinstance(c.value, dict):
            text = ", ".join(f"{k} = {show(v)}" for k, v in c.value.items())
        else:
            text = show(c.value)
        out.append(Choice("choose", text, chooses.rule(c.label), span_location(chooses.span(c.label), root=root)))
    return out


def read_records(machine, mon: dict) -> list[Choice]:
    """The monitored values a step read (location key -> value), in the order of the locations."""
    from ..semantics.printer import location_text
    from ..semantics.values import show
    return [Choice("monitored", f"{location_text(machine, k)} = {show(mon[k])}")
            for k in sorted(mon, key=lambda k: key_order(machine, k))]


def step_records(machine, trace, chooses: ChooseIndex, root=None, inputs=None) -> list[StepRecord]:
    if inputs is None:
        inputs = step_inputs(machine, trace)
    recs = []
    for st, mon in zip(trace.steps, inputs):
        choices = []
        if st.number > 0:
            choices = choose_records(st.shown_choices(), chooses, root) + read_records(machine, shown_inputs(st, mon))
        keys = sorted(st.changed, key=lambda k: key_order(machine, k))
        recs.append(StepRecord(st.number, chooses.main, choices,
                               {location_name(machine, k): value_text(k, st.changed[k]) for k in keys},
                               {location_name(machine, k): value_text(k, st.display[k])
                                for k in sorted(st.display, key=lambda k: key_order(machine, k))}))
    return recs


def failing_record(machine, trace, chooses: ChooseIndex, root=None) -> StepRecord | None:
    """The step that fails at the end of an 'error' trace, as a StepRecord: the choices and
    monitored values it had taken when it failed (it changes nothing)."""
    from ..semantics.values import show
    failing = getattr(trace, "failing", None)
    if failing is None:
        return None
    choices = choose_records(failing, chooses, root)
    reads = [Choice("monitored", f"{c.label} = {show(c.value)}") for c in flat_choices(failing)
             if c.kind == "monitored"]
    last = trace.steps[-1] if trace.steps else None
    return StepRecord(len(trace.steps), chooses.main, choices + reads, {},
                      {} if last is None else {location_name(machine, k): value_text(k, last.display[k])
                                               for k in sorted(last.display, key=lambda k: key_order(machine, k))})


def property_text(prop) -> str:
    """The term of a property's declaration, on one line: the source text from after the ':'
    that follows its name to the end of its body."""
    inner = getattr(prop, "prop", prop)
    span = getattr(inner, "span", None)
    bodies = [getattr(getattr(inner, a, None), "span", None) for a in ("body", "body2")]
    bodies = [b for b in bodies if b is not None and b.line and b.end_line]
    if not bodies:
        return ""
    end = max(bodies, key=lambda b: (b.end_line, b.end_col))
    if span is None or not span.line or span.path != end.path or (span.line, span.col) > (end.line, end.col):
        return term_text(end)
    text = source_text(span.path, span.line, span.col, end.end_line, end.end_col)
    if text is None:
        return term_text(end)
    clean = one_line(text)
    name = getattr(inner, "name", "") or ""
    i = clean.find(name) if name else -1
    j = clean.find(":", i + len(name) if i >= 0 else 0)
    if j < 0:
        return term_text(end)
    return clean[j + 1:].strip()
