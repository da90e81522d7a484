"""The outcome of checking specs, as plain data: what ``asmcheck check`` prints and every
report format (JSON, JUnit, SARIF, HTML) is made from.

A :class:`SpecOutcome` holds one row (:class:`PropertyOutcome`) per property checked on a
spec, each with the raw verdict of the search, whether the spec declares it expected to be
violated (``// asmcheck: expect violated NAME``), and the resulting gate status:

================================  =====================================  ==========
raw verdict                        label                                  status
================================  =====================================  ==========
holds                              holds                                  pass
violated                           violated                               fail
violated, declared expected        violated (expected)                    pass
violated, spec declares others     violated (tolerated)                   pass [#]_
holds, declared expected           holds (expected to be violated)        fail
incomplete                         incomplete                             incomplete
not checked, declared expected     not checked (expected to be violated)  incomplete
no such property, declared         no such property                       error
================================  =====================================  ==========

.. [#] A spec that declares expected violations is a seeded-bug spec: the gate checks that
   the bug is found.  Other properties it breaks are consequences of the same bug
   (specs/README.md lists them) and are reported as *tolerated*; with ``strict`` (the
   ``--strict-expect`` option) they fail the gate like any unexpected violation.  In a spec
   that declares nothing, every violation fails.

The exit code of a run: 2 when any row is an input error, else 1 when any row fails, else 3
when any row is incomplete, else 0.
"""
from __future__ import annotations

import os
import re
from dataclasses import dataclass, field
from pathlib import Path

PASS, FAIL, INCOMPLETE, ERROR = "pass", "fail", "incomplete", "error"
EXIT_OK, EXIT_VIOLATED, EXIT_ERROR, EXIT_INCOMPLETE = 0, 1, 2, 3
TEMPORAL_KINDS = ("ltl", "ctl")


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


@dataclass
class Counterexample:
    kind: str                       # state: the last state violates; step: the last step; lasso
    message: str
    steps: list                     # [StepRecord]
    json: object                    # the trace as the JSON format has it (docs/trace.schema.json)
    loop_start: int | None = None   # lasso: the step the cycle goes back to
    text: list | None = None        # lines of a temporal result's own text, when it has no steps
    avalla: str | None = None       # the Avalla scenario text
    avalla_path: str | None = None  # where it was written


@dataclass
class PropertyOutcome:
    name: str
    kind: str                       # invariant step ltl ctl deadlock error input
    verdict: str                    # holds violated incomplete not-checked unknown error
    expected: bool = False          # declared with '// asmcheck: expect violated'
    status: str = PASS
    label: str = ""
    location: Location | None = None      # the property's declaration
    expect_location: Location | None = None   # the '// asmcheck: expect violated' line
    text: str = ""                  # the property's term, on one line
    message: str = ""
    counterexample: Counterexample | None = None

    @property
    def tolerated(self) -> bool:
        return self.verdict == "violated" and not self.expected and self.status == PASS


@dataclass
class SpecOutcome:
    path: str                       # as given or found (relative to the working folder if below it)
    name: str                       # the asm name ('' when it could not be read)
    verdict: str                    # the search's: holds violated incomplete, or error
    states: int = 0
    transitions: int = 0
    depth: int = 0
    seconds: float = 0.0
    reason: str = ""                # why incomplete
    error: str = ""                 # an input error, rendered
    error_location: Location | None = None
    expected: list = field(default_factory=list)
    properties: list = field(default_factory=list)   # [PropertyOutcome]
    header: Location | None = None  # the 'asm NAME' header
    main: Location | None = None    # the main rule's declaration

    @property
    def status(self) -> str:
        return worst([p.status for p in self.properties])


def worst(statuses) -> str:
    s = set(statuses)
    for x in (ERROR, FAIL, INCOMPLETE):
        if x in s:
            return x
    return PASS


def exit_code(outcomes) -> int:
    return {PASS: EXIT_OK, FAIL: EXIT_VIOLATED, ERROR: EXIT_ERROR, INCOMPLETE: EXIT_INCOMPLETE}[
        worst([o.status for o in outcomes] or [PASS])]


def counts(outcomes) -> dict:
    rows = [p for o in outcomes for p in o.properties]
    return {
        "specs": len(outcomes),
        "properties": len(rows),
        "holds": sum(1 for p in rows if p.status == PASS and p.verdict == "holds"),
        "expected": sum(1 for p in rows if p.status == PASS and p.verdict == "violated" and p.expected),
        "tolerated": sum(1 for p in rows if p.tolerated),
        "failed": sum(1 for p in rows if p.status == FAIL),
        "incomplete": sum(1 for p in rows if p.status == INCOMPLETE),
        "errors": sum(1 for p in rows if p.status == ERROR),
    }


# ----------------------------------------------------------------- verdicts
def judge(row: PropertyOutcome, declares_expectations: bool, strict: bool) -> PropertyOutcome:
    """Set the row's status and label from its verdict and expectation."""
    v, exp = row.verdict, row.expected
    if v == "violated":
        if row.kind == "error":
            row.status, row.label = FAIL, "error"
        elif exp:
            row.status, row.label = PASS, "violated (expected)"
        elif declares_expectations and not strict:
            row.status, row.label = PASS, "violated (tolerated)"
        else:
            row.status, row.label = FAIL, "VIOLATED"
    elif v == "holds":
        if exp:
            row.status, row.label = FAIL, "holds (expected to be violated)"
        else:
            row.status, row.label = PASS, "holds"
    elif v == "incomplete":
        row.status, row.label = INCOMPLETE, "incomplete" + (" (expected to be violated)" if exp else "")
    elif v == "not-checked":
        row.status, row.label = INCOMPLETE, "not checked" + (" (expected to be violated)" if exp else "")
    elif v == "unknown":
        row.status, row.label = ERROR, "no such property"
    elif row.kind == "input":
        row.status, row.label = ERROR, "input error"
    else:
        row.status, row.label = ERROR, "cannot be checked"
    return row


# ----------------------------------------------------------------- building
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


# '// asmcheck: expect violated NAME[, NAME...]' on one line (props.files._EXPECT also reads
# on over the following lines when they hold only words, commas and blanks)
_EXPECT_LINE = re.compile(r"//[ \t]*asmcheck:[ \t]*expect[ \t]+violated[ \t]+"
                          r"([A-Za-z_][A-Za-z0-9_]*(?:[ \t]*,[ \t]*[A-Za-z_][A-Za-z0-9_]*)*)")


def expect_lines(spec_path: str) -> dict:
    """Property name -> (line, column) of the ``// asmcheck: expect violated`` comment naming it."""
    from ..syntax.parser import decode_source
    try:
        text = decode_source(Path(spec_path).read_bytes())
    except OSError:
        return {}
    out = {}
    for n, line in enumerate(text.split("\n"), start=1):
        for m in _EXPECT_LINE.finditer(line):
            for x in m.group(1).split(","):
                out.setdefault(x.strip(), (n, m.start() + 1))
    return out


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
            out.append(dict(ctx.mon))
        except Exception:    # a step that fails (an error trace): no inputs known
            out.append({})
    return out


def shown_inputs(step, mon: dict) -> dict:
    """The monitored values a step read (as :func:`step_inputs` finds them, in the canonical
    names of the state before it) under the trace's display names."""
    if not mon or not getattr(step, "names", None):
        return mon
    return {(k if type(k) is not tuple else (k[0], step.show(k[1]))): step.show(v) for k, v in mon.items()}


def step_records(machine, trace, chooses: ChooseIndex, root=None, inputs=None) -> list[StepRecord]:
    from .trace import _key_order, _loc, _val
    from ..semantics.printer import location_text
    from ..semantics.values import show
    if inputs is None:
        inputs = step_inputs(machine, trace)
    recs = []
    for st, mon in zip(trace.steps, inputs):
        choices = []
        if st.number > 0:
            for c in flat_choices(st.shown_choices()):
                if c.kind != "choose":
                    continue
                if isinstance(c.value, dict):
                    text = ", ".join(f"{k} = {show(v)}" for k, v in c.value.items())
                else:
                    text = show(c.value)
                choices.append(Choice("choose", text, chooses.rule(c.label),
                                      span_location(chooses.span(c.label), root=root)))
            mon = shown_inputs(st, mon)
            for k in sorted(mon, key=lambda k: _key_order(machine, k)):
                choices.append(Choice("monitored", f"{location_text(machine, k)} = {show(mon[k])}"))
        keys = sorted(st.changed, key=lambda k: _key_order(machine, k))
        recs.append(StepRecord(st.number, chooses.main, choices,
                               {_loc(machine, k): _val(k, st.changed[k]) for k in keys},
                               {_loc(machine, k): _val(k, st.display[k])
                                for k in sorted(st.display, key=lambda k: _key_order(machine, k))}))
    return recs


def step_header(rec: StepRecord) -> str:
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


def cx_summary(cx: Counterexample) -> str:
    """'shortest counterexample, 3 steps (the last step breaks it)' and the like."""
    n = len(cx.steps) - 1
    steps = f"{n} step{'s' if n != 1 else ''}"
    if cx.kind == "lasso":
        return f"counterexample, {steps}: a lasso, back to state {cx.loop_start} for ever"
    if cx.kind == "path":
        return f"counterexample, {steps}"
    return f"shortest counterexample, {steps}" + (" (the last step breaks it)" if cx.kind == "step" else "")


RENAMED = "(up to the names of the elements made by extend)"


def lasso_renamed(cx: Counterexample) -> bool:
    """A lasso whose last state is its loop's first state (as the explorer stores states)
    but shows the elements made by extend under other names (as a simulation names them)."""
    if cx.kind != "lasso" or cx.loop_start is None or not cx.steps:
        return False
    first = next((r for r in cx.steps if r.number == cx.loop_start), None)
    return first is not None and first is not cx.steps[-1] and first.state != cx.steps[-1].state


def trace_lines(cx: Counterexample, color: bool = False) -> list[str]:
    """Per step the rule, its choices and inputs, then only the locations that changed."""
    if not cx.steps:
        return list(cx.text or [])
    bold = (lambda s: f"\x1b[1m{s}\x1b[0m") if color else (lambda s: s)
    red = (lambda s: f"\x1b[1;31m{s}\x1b[0m") if color else (lambda s: s)
    yellow = (lambda s: f"\x1b[33m{s}\x1b[0m") if color else (lambda s: s)
    out = []
    last = cx.steps[-1].number
    for rec in cx.steps:
        head = step_header(rec)
        mark = ""
        if rec.number == last:
            mark = "  <- breaks the property" if cx.kind == "step" else "  <- violates the property"
            if cx.kind == "lasso":
                mark = f"  <- back to state {cx.loop_start}" if cx.loop_start is not None else ""
                if mark and lasso_renamed(cx):
                    mark += " " + RENAMED
        if cx.kind == "lasso" and cx.loop_start is not None and rec.number == cx.loop_start and rec.number != last:
            mark = "  <- the cycle starts here"
        out.append((red if rec.number == last and mark and cx.kind != "lasso" else bold)(head) +
                   (yellow(mark) if mark else ""))
        for k, v in rec.changed.items():
            out.append(f"    {k} = {v}")
        if not rec.changed and rec.number > 0:
            out.append("    (no change)")
    return out


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


def build_outcome(path, spec, machine, explorer, result, temporal=(), temporal_results=(), *,
                  seconds=None, strict=False, root=None, avalla_dir=None, temporal_error: str = "") -> SpecOutcome:
    """A :class:`SpecOutcome` from one exploration (``run_exploration``'s results) and the
    temporal results; every counterexample is rebuilt, replayed and described."""
    from .trace import build_trace, trace_json

    exp_lines = expect_lines(path)
    expected = set(exp_lines)
    chooses = ChooseIndex(spec)
    out = SpecOutcome(display_path(path, root), spec.name, result.verdict, result.states, result.transitions,
                      result.depth, result.seconds if seconds is None else seconds, result.reason,
                      expected=sorted(expected))
    spec_file = display_path(path, root)
    syn = getattr(spec.root_module, "syntax", None)
    out.header = span_location(getattr(syn, "name_span", None) or getattr(syn, "span", None), root=root)
    if spec.main is not None:
        out.main = span_location(spec.main.span, root=root)

    def expect_loc(name):
        if name in exp_lines:
            ln, col = exp_lines[name]
            return Location(spec_file, ln, col)
        return None

    bad = {v.prop.name: v for v in result.violations}
    incomplete = result.stopped_early
    rows: list[PropertyOutcome] = []

    def counterexample(v) -> Counterexample:
        tr = build_trace(explorer, v)
        cx = Counterexample(tr.kind, v.message, step_records(machine, tr, chooses, root),
                            {"property": v.prop.name, "kind": tr.kind, "message": v.message,
                             "trace": trace_json(machine, tr)})
        if avalla_dir is not None:
            from .avalla_export import scenario_file_name, trace_scenario
            target = os.path.join(avalla_dir, scenario_file_name(spec.name, v.prop.name))
            cx.avalla = trace_scenario(machine, tr, spec_path=path, out_path=target, prop=v.prop,
                                       chooses=chooses)
            cx.avalla_path = display_path(target, root)
        return cx

    for p in result.checked:
        v = bad.get(p.name)
        row = PropertyOutcome(p.name, getattr(p, "kind", "invariant"),
                              "violated" if v else ("incomplete" if incomplete else "holds"),
                              p.name in expected, location=span_location(p.span, p.name, root),
                              expect_location=expect_loc(p.name), text=property_text(p))
        if v is not None:
            row.message = v.message
            row.counterexample = counterexample(v)
        rows.append(row)
    for v in result.violations:
        if v.prop.name in ("deadlock", "error"):
            row = PropertyOutcome(v.prop.name, v.prop.kind, "violated", v.prop.name in expected,
                                  location=span_location(getattr(v.prop, "span", None), root=root),
                                  message=v.message, expect_location=expect_loc(v.prop.name))
            row.counterexample = counterexample(v)
            rows.append(row)
    if getattr(result, "deadlock_checked", False) and "deadlock" not in bad:
        rows.append(PropertyOutcome("deadlock", "deadlock", "incomplete" if incomplete else "holds",
                                    "deadlock" in expected, expect_location=expect_loc("deadlock")))
    by_name = {getattr(p, "name", None): p for p in temporal}
    seen = {r.name for r in rows}
    for t in temporal_results:
        prop = by_name.get(t.name) or getattr(t, "prop", None)     # the declaration as written
        msg = getattr(t, "message", "") or ""
        verdict = "error" if msg else ("holds" if t.holds else "violated")
        row = PropertyOutcome(t.name, t.kind, verdict, t.name in expected,
                              location=span_location(getattr(prop, "span", None), t.name, root),
                              expect_location=expect_loc(t.name), message=msg,
                              text=property_text(prop) if prop is not None else "")
        if verdict == "violated":
            row.counterexample = temporal_counterexample(machine, t, chooses, root, spec_path=path,
                                                         avalla_dir=avalla_dir, spec_name=spec.name)
        rows.append(row)
        seen.add(t.name)
    seen |= {r.name for r in rows}
    if temporal_error:
        for prop in temporal:
            if getattr(prop, "kind", "") in TEMPORAL_KINDS and prop.name not in seen:
                rows.append(PropertyOutcome(prop.name, prop.kind, "error", prop.name in expected,
                                            location=span_location(prop.span, prop.name, root),
                                            expect_location=expect_loc(prop.name), text=property_text(prop),
                                            message=temporal_error))
                seen.add(prop.name)
    for name in sorted(expected - seen):
        prop = by_name.get(name)
        if prop is not None and getattr(prop, "kind", "") in TEMPORAL_KINDS:
            why = "the exploration is incomplete" if incomplete else "no result for it (LTL/CTL checking)"
            rows.append(PropertyOutcome(name, prop.kind, "not-checked", True,
                                        location=span_location(prop.span, name, root),
                                        expect_location=expect_loc(name), text=property_text(prop),
                                        message=why))
        else:
            rows.append(PropertyOutcome(name, "unknown", "unknown", True, location=expect_loc(name),
                                        expect_location=expect_loc(name),
                                        message=f"the spec expects {name} to be violated, but no property "
                                                f"{name} is checked on it"))
    for r in rows:
        judge(r, bool(expected), strict)
    out.properties = rows
    return out


def temporal_trace(t):
    """A temporal result's path: (Trace, loop index or None), or (None, None)."""
    tr = getattr(t, "trace", None)
    loop = getattr(t, "loop_start", None)
    if callable(tr):            # temporal.TemporalResult.trace() -> (Trace, loop, inputs_step) | None
        got = tr()
        if not got:
            return None, None
        tr, loop = got[0], got[1]
    if tr is None or not getattr(tr, "steps", None):
        return None, None
    if loop is None:
        loop = getattr(tr, "loop_start", None)
    return tr, loop


def temporal_counterexample(machine, t, chooses, root=None, *, spec_path=None, avalla_dir=None,
                            spec_name="") -> Counterexample:
    """A temporal result's counterexample: its JSON and text, and its steps (a lasso when the
    path ends with a cycle back to an earlier state)."""
    tr, loop = temporal_trace(t)
    steps = step_records(machine, tr, chooses, root) if tr is not None else []
    try:
        js = t.json(machine)
    except Exception:       # pragma: no cover - a result that cannot describe itself
        js = {"property": t.name}
    try:
        text = list(t.text(machine, False))
    except Exception:       # pragma: no cover
        text = []
    cx = Counterexample("lasso" if loop is not None else "path", getattr(t, "message", "") or "", steps, js, loop,
                        text)
    if avalla_dir is not None and tr is not None and spec_path is not None:
        from .avalla_export import scenario_file_name, trace_scenario
        prop = getattr(t, "prop", None)
        target = os.path.join(avalla_dir, scenario_file_name(spec_name or machine.spec.name, t.name))
        cx.avalla = trace_scenario(machine, tr, spec_path=spec_path, out_path=target, prop=prop, chooses=chooses,
                                   loop=loop)
        cx.avalla_path = display_path(target, root)
    return cx


def error_outcome(path: str, err, root=None, seconds=0.0) -> SpecOutcome:
    """A spec that could not be loaded or explored (an input error)."""
    from ..errors import AsmError
    if isinstance(err, AsmError):
        text = err.render()
        loc = span_location(err.span, root=root)
        msg = err.message
    else:
        text = msg = str(err)
        loc = None
    o = SpecOutcome(display_path(path, root), "", "error", seconds=seconds, error=text, error_location=loc)
    row = PropertyOutcome("(input)", "input", "error", location=loc, message=msg)
    judge(row, False, False)
    o.properties = [row]
    return o
