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
no property at all                 no property checked                    error
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

from .describe import (Choice, ChooseIndex, Location, StepRecord, display_path, failing_record, flat_choices,  # noqa: F401
                       one_line, property_text, shown_inputs, source_text, span_location, step_inputs,
                       step_records, term_text)
from .trace import (RENAMED, cx_summary, failing_note, lasso_renamed, renamed_note, step_header, temporal_json,  # noqa: F401
                    temporal_text, trace_lines)

PASS, FAIL, INCOMPLETE, ERROR = "pass", "fail", "incomplete", "error"
EXIT_OK, EXIT_VIOLATED, EXIT_ERROR, EXIT_INCOMPLETE = 0, 1, 2, 3
TEMPORAL_KINDS = ("ltl", "ctl")


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
    failing: StepRecord | None = None   # property 'error': the step that fails after the last state
    inputs_step: bool = False       # the last step only shows the inputs of the state before it
    fairness: list = field(default_factory=list)    # the fairness constraints a temporal verdict assumed
    failing_note: str = ""           # a temporal path that ends with a step that fails: what then
    up_to: str = ""                  # lasso under symmetry reduction: its return is up to this renaming


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
    # a step of the spec fails: the verdict is relative to that run-time error (its location),
    # the property having been checked on the well-defined steps
    relative_to: Location | None = None
    # a temporal verdict decided on a partial state space: the states explored (None: the whole)
    decided_on: int | None = None

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
    # what the row is about: a spec, or an input of the whole gate ('property file', 'option')
    subject: str = "spec"

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
    elif v == "none":
        row.status, row.label = ERROR, "no property checked"
    elif row.kind == "input":
        row.status, row.label = ERROR, "input error"
    else:
        row.status, row.label = ERROR, "cannot be checked"
    if row.relative_to is not None and v in ("holds", "violated"):
        row.label += f", relative to the run-time error at {row.relative_to}"
    if row.decided_on is not None and v in ("holds", "violated"):
        row.label += f" (decided on the {row.decided_on:,} states explored)"
    return row


# ----------------------------------------------------------------- building
# '// asmcheck: expect violated NAME[, NAME...]' on one line (props.files._EXPECT also reads
# on over the following lines when they hold only words, commas and blanks)
_EXPECT_LINE = re.compile(r"//[ \t]*asmcheck:[ \t]*expect[ \t]+violated[ \t]+"
                          r"([A-Za-z_][A-Za-z0-9_]*(?:[ \t]*,[ \t]*[A-Za-z_][A-Za-z0-9_]*)*)")


def expect_lines(spec_path: str) -> dict:
    """Property name -> (line, column) of the ``// asmcheck: expect violated`` comment naming it."""
    from ..errors import AsmError
    from ..syntax.parser import decode_source, read_source_bytes
    try:
        text = decode_source(read_source_bytes(spec_path))
    except AsmError:
        return {}
    out = {}
    for n, line in enumerate(text.split("\n"), start=1):
        for m in _EXPECT_LINE.finditer(line):
            for x in m.group(1).split(","):
                out.setdefault(x.strip(), (n, m.start() + 1))
    return out


def build_outcome(path, spec, machine, explorer, result, temporal=(), temporal_results=(), *,
                  seconds=None, strict=False, root=None, avalla_dir=None, temporal_error: str = "",
                  expectations: bool = True) -> SpecOutcome:
    """A :class:`SpecOutcome` from one exploration (``run_exploration``'s results) and the
    temporal results; every counterexample is rebuilt, replayed and described."""
    from .trace import build_trace, failing_json, trace_json

    # explore judges no expectation (its exit code is the search's); the gate does
    exp_lines = expect_lines(path) if expectations else {}
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
    # the invariants, step properties and deadlock: decided when the search was complete, even if
    # a limit stopped the LTL/CTL phase after it
    search_incomplete = getattr(result, "search_stopped_early", incomplete)
    rows: list[PropertyOutcome] = []
    # where a step fails, the other verdicts are relative to that error (the first one found)
    err = bad.get("error")
    relative = span_location(getattr(err.prop, "span", None), root=root) if err is not None else None

    def counterexample(v) -> Counterexample:
        tr = build_trace(explorer, v)
        inputs = step_inputs(machine, tr)
        js = {"property": v.prop.name, "kind": tr.kind, "message": v.message,
              "trace": trace_json(machine, tr, chooses, inputs)}
        if failing_json(tr) is not None:
            js["failing_step"] = failing_json(tr)
        cx = Counterexample(tr.kind, v.message, step_records(machine, tr, chooses, root, inputs), js,
                            failing=failing_record(machine, tr, chooses, root))
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
                              "violated" if v else ("incomplete" if search_incomplete else "holds"),
                              p.name in expected, location=span_location(p.span, p.name, root),
                              expect_location=expect_loc(p.name), text=property_text(p))
        if v is not None:
            row.message = v.message
            row.counterexample = counterexample(v)
        elif not search_incomplete:
            row.relative_to = relative
        rows.append(row)
    for v in result.violations:
        if v.prop.name in ("deadlock", "error"):
            row = PropertyOutcome(v.prop.name, v.prop.kind, "violated", v.prop.name in expected,
                                  location=span_location(getattr(v.prop, "span", None), root=root),
                                  message=v.message, expect_location=expect_loc(v.prop.name))
            row.counterexample = counterexample(v)
            rows.append(row)
    if getattr(result, "deadlock_checked", False) and "deadlock" not in bad:
        rows.append(PropertyOutcome("deadlock", "deadlock", "incomplete" if search_incomplete else "holds",
                                    "deadlock" in expected, expect_location=expect_loc("deadlock"),
                                    relative_to=None if search_incomplete else relative))
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
        if not msg and getattr(t, "relative_to", None) is not None:
            row.relative_to = relative
        if not msg:
            row.decided_on = getattr(t, "decided_on", None)
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
    if incomplete:
        # a limit stopped the search before LTL/CTL ran: the properties stay in the report
        for prop in temporal:
            if getattr(prop, "kind", "") in TEMPORAL_KINDS and prop.name not in seen and prop.name not in expected:
                rows.append(PropertyOutcome(prop.name, prop.kind, "incomplete", False,
                                            location=span_location(prop.span, prop.name, root),
                                            text=property_text(prop), message="the exploration is incomplete"))
                seen.add(prop.name)
    if any(r.decided_on is not None for r in rows):
        # verdicts decided on a partial state space beside incomplete ones: in declaration order
        order = {getattr(p, "name", None): i for i, p in enumerate(temporal)}
        at = [i for i, r in enumerate(rows) if r.kind in TEMPORAL_KINDS and r.name in order]
        for i, r in zip(at, sorted((rows[i] for i in at), key=lambda r: order[r.name])):
            rows[i] = r
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
    got = t.trace() if callable(getattr(t, "trace", None)) else None
    inputs_step = bool(got[2]) if got and len(got) > 2 else False
    steps = step_records(machine, tr, chooses, root) if tr is not None else []
    try:
        js = temporal_json(t, machine)
    except Exception:       # pragma: no cover - a result that cannot describe itself
        js = {"property": t.name}
    try:
        text = list(temporal_text(t, machine, False))
    except Exception:       # pragma: no cover
        text = []
    cx = Counterexample("lasso" if loop is not None else "path", getattr(t, "message", "") or "", steps, js, loop,
                        text, inputs_step=inputs_step, fairness=list(getattr(t, "fairness", None) or ()),
                        up_to=getattr(tr, "up_to", "") if tr is not None else "")
    if tr is not None and getattr(tr, "failing", None) is not None and steps:
        # the path ends with a step that fails: the run halts in its last state
        cx.failing = failing_record(machine, tr, chooses, root)
        cx.failing_note = failing_note(tr)
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
