"""Text and JSON reports of a scenario run."""
from __future__ import annotations

from ..errors import AsmError
from .runner import Event, Outcome


def _where(ev: Event) -> str:
    return str(ev.span) if ev.span is not None and ev.span.line else "-"


def _state(n: int) -> str:
    return f"state {n}"


def text_report(out: Outcome, verbose: bool = False) -> list[str]:
    lines = []
    for ev in out.events:
        via = "".join(f"\n    (run by execblock at {s})" for s in ev.via) if (ev.via and (not ev.ok or verbose)) else ""
        vals = ", ".join(f"{k} = {v}" for k, v in ev.values)
        if ev.kind == "check":
            status = "passed" if ev.ok else "FAILED"
            line = f"{_where(ev)}: check {status} ({_state(ev.state)}): {ev.text}"
            if not ev.ok and ev.message:
                line += f"\n    {ev.message}"
            if vals and (not ev.ok or verbose):
                line += f"\n    {vals}"
            lines.append(line + via)
        elif ev.kind in ("invariant", "error") or (ev.kind in ("until", "pick") and not ev.ok):
            line = f"{_where(ev)}: {ev.kind if ev.kind != 'until' else 'step until'}: {ev.message}" \
                if ev.kind in ("until", "pick") else f"{_where(ev)}: {ev.message}"
            if ev.error is not None and ev.error.span is not None and ev.error.span.line and ev.error.span != ev.span:
                line += f"\n    {ev.error.render().replace(chr(10), chr(10) + '    ')}"
            if vals:
                line += f"\n    {vals}"
            if ev.note:
                line += f"\n    note: {ev.note}"
            lines.append(line + via)
        elif verbose:
            if ev.kind == "step":
                lines.append(f"{_where(ev)}: step -> {_state(ev.state)}{via}")
            elif ev.kind == "until":
                lines.append(f"{_where(ev)}: step until {ev.text}: {ev.message} -> {_state(ev.state)}{via}")
            else:
                lines.append(f"{_where(ev)}: {ev.kind} {ev.text}{via}")
    n = len(out.checks)
    summary = f"scenario {out.scenario}: {'PASS' if out.ok else 'FAIL'}: {out.passed} of {n} check(s) passed"
    if out.failed:
        summary += f", {out.failed} failed"
    summary += f"; {out.steps} step(s)"
    if out.execs:
        summary += f", {out.execs} exec(s)"
    if out.stopped:
        summary += f"; stopped early ({out.stopped})"
    lines.append(summary)
    return lines


def _span_json(sp) -> dict:
    if sp is None or not sp.line:
        return {"path": None, "line": None, "column": None}
    return {"path": sp.path, "line": sp.line, "column": sp.col}


def json_report(out: Outcome) -> dict:
    events = []
    for ev in out.events:
        d = {"kind": ev.kind, **_span_json(ev.span), "state": ev.state, "text": ev.text, "ok": ev.ok}
        if ev.values or ev.kind == "check":
            d["values"] = {k: v for k, v in ev.values}
        if ev.message:
            d["message"] = ev.message
        if ev.note:
            d["note"] = ev.note
        if ev.via:
            d["via"] = [_span_json(s) for s in ev.via]
        if ev.error is not None:
            d["error"] = error_json(ev.error)
        events.append(d)
    return {
        "scenario": out.scenario,
        "file": out.path,
        "spec": out.spec_path,
        "result": out.result,
        "steps": out.steps,
        "execs": out.execs,
        "checks": {"total": len(out.checks), "passed": out.passed, "failed": out.failed},
        "stopped": out.stopped,
        "events": events,
    }


def error_json(err: AsmError) -> dict:
    sp = err.span
    return {"path": sp.path if sp else None, "line": sp.line if sp and sp.line else None,
            "column": sp.col if sp and sp.line else None, "message": err.message}
