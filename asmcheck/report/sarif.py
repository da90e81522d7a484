"""``asmcheck check --sarif``: a SARIF 2.1.0 log (the format of GitHub code scanning).

* one rule per property name (``tool.driver.rules``), its description the property's text;
* one result per violation, located at the property's declaration (the spec, or the property
  file), with the spec checked as a related location and the counterexample as a code flow:
  one thread-flow location per step, at the choose rule that made the step's choice (or the
  spec's main rule), its message the step's choices and its ``state`` the locations it
  changed;
* an unexpected violation has level ``error``; an expected one (``// asmcheck: expect
  violated NAME``) is reported with an ``inSource`` suppression (code scanning hides it); a
  tolerated one (another violation of a spec that expects some) has level ``warning``;
* an expected violation that does not happen is an ``error`` result located at the
  ``// asmcheck: expect violated`` line, with the property's declaration as related location;
* input errors and incomplete explorations are tool execution notifications of the
  invocation.

File locations are URIs relative to the working folder (``uriBaseId`` ``%SRCROOT%``) when
the file lies below it.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

from ..version import __version__
from .gate import ERROR, FAIL, INCOMPLETE, PASS, cx_summary, step_header

SCHEMA = "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
INFO_URI = "https://github.com/asmcheck/asmcheck"


def _artifact(path: str) -> dict:
    p = Path(path)
    if p.is_absolute():
        return {"uri": p.as_uri()}
    return {"uri": p.as_posix(), "uriBaseId": "%SRCROOT%"}


def _dir_uri(path: str) -> str:
    uri = Path(os.path.abspath(path)).as_uri()
    return uri if uri.endswith("/") else uri + "/"


def _physical(loc) -> dict:
    region = {"startLine": loc.line, "startColumn": max(loc.column, 1)}
    if loc.end_column:
        region["endColumn"] = loc.end_column
    return {"artifactLocation": _artifact(loc.path), "region": region}


def _location(loc, message: str | None = None, id_: int | None = None) -> dict:
    out = {}
    if id_ is not None:
        out["id"] = id_
    out["physicalLocation"] = _physical(loc)
    if message:
        out["message"] = {"text": message}
    return out


def _spec_location(o):
    from .gate import Location
    return o.header or Location(o.path, 1, 1)


def _code_flow(o, p) -> dict | None:
    from .gate import Location
    cx = p.counterexample
    if cx is None or not cx.steps:
        return None
    locs = []
    for rec in cx.steps:
        at = next((c.at for c in rec.choices if c.kind == "choose" and c.at is not None), None)
        if at is None:
            at = (o.header if rec.number == 0 else o.main) or _spec_location(o)
        tfl = {"location": _location(at, step_header(rec)), "executionOrder": rec.number,
               "state": {k: {"text": v} for k, v in rec.changed.items()}}
        if rec.number == cx.steps[-1].number:
            tfl["importance"] = "essential"
        locs.append(tfl)
    return {"message": {"text": f"{p.name}: {cx_summary(cx)}"},
            "threadFlows": [{"locations": locs}]}


def _result_for(o, p, rule_index: dict) -> dict | None:
    if p.verdict == "violated":
        if p.kind == "error":
            text = f"{o.path}: a step fails: {p.message}"
        elif p.kind == "deadlock":
            text = f"{o.path} ({o.name}) has a deadlock" + (f": {p.message}" if p.message else "")
        else:
            text = f"{p.name} is violated by {o.name} ({o.path})" + (f": {p.message}" if p.message else "")
            if getattr(p, "relative_to", None) is not None:
                text += f" (relative to the run-time error at {p.relative_to})"
        cx = p.counterexample
        if cx is not None and cx.steps:
            text += f"; {cx_summary(cx)}"
            if cx.avalla_path:
                text += f" (Avalla scenario {cx.avalla_path})"
        if p.expected:
            level = "note"
        elif p.status == PASS:
            level = "warning"
            text += " (tolerated: the spec declares other expected violations)"
        else:
            level = "error"
        loc = p.location or _spec_location(o)
        res = {"ruleId": p.name, "ruleIndex": rule_index[p.name], "kind": "fail", "level": level,
               "message": {"text": text}, "locations": [_location(loc)]}
        related = [_location(_spec_location(o), f"the spec checked: {o.name}", 1)]
        if p.expect_location:
            related.append(_location(p.expect_location, "the spec expects this violation", 2))
        res["relatedLocations"] = related
        flow = _code_flow(o, p)
        if flow is not None:
            res["codeFlows"] = [flow]
        if p.expected:
            sup = {"kind": "inSource", "status": "accepted",
                   "justification": f"{o.path} declares '// asmcheck: expect violated {p.name}'"}
            if p.expect_location:
                sup["location"] = _location(p.expect_location)
            res["suppressions"] = [sup]
        res["partialFingerprints"] = {"asmcheck/v1": f"{o.path}:{p.name}:violated"}
        bag = {"spec": o.name, "specPath": o.path, "status": p.status}
        if cx is not None:
            bag["counterexampleKind"] = cx.kind
            if cx.steps:
                bag["steps"] = len(cx.steps) - 1
            if cx.avalla_path:
                bag["avalla"] = cx.avalla_path
        res["properties"] = bag
        return res
    if p.verdict == "holds" and p.expected:
        loc = p.expect_location or p.location or _spec_location(o)
        res = {"ruleId": p.name, "ruleIndex": rule_index[p.name], "kind": "fail", "level": "error",
               "message": {"text": f"{o.name} ({o.path}) expects {p.name} to be violated, but it holds"},
               "locations": [_location(loc)]}
        if p.location:
            res["relatedLocations"] = [_location(p.location, f"the declaration of {p.name}", 1)]
        res["partialFingerprints"] = {"asmcheck/v1": f"{o.path}:{p.name}:expected"}
        res["properties"] = {"spec": o.name, "specPath": o.path, "status": p.status}
        return res
    return None


def sarif_log(outcomes, code: int, root: str | None = None, command_line: str | None = None) -> dict:
    rules: list[dict] = []
    rule_index: dict = {}
    for o in outcomes:
        for p in o.properties:
            if p.kind == "input" or p.name in rule_index:
                continue
            rule_index[p.name] = len(rules)
            desc = p.text or {"deadlock": "every reachable state has a successor other than itself",
                              "error": "every step can be computed"}.get(p.kind, p.name)
            rule = {"id": p.name, "name": p.name,
                    "shortDescription": {"text": f"{p.kind} {p.name}"},
                    "fullDescription": {"text": desc},
                    "defaultConfiguration": {"level": "error"},
                    "properties": {"kind": p.kind}}
            if p.location:
                rule["properties"]["declaredAt"] = str(p.location)
            rules.append(rule)
    results = []
    notes = []
    for o in outcomes:
        if o.error:
            n = {"level": "error", "message": {"text": o.error.splitlines()[0] if o.error else "input error"},
                 "descriptor": {"id": "input-error"}}
            if o.error_location:
                n["locations"] = [_location(o.error_location)]
            elif getattr(o, "subject", "spec") != "option":
                # (an option of the whole gate, --fair NAME, is in no file)
                n["locations"] = [_location(_spec_location(o))]
            notes.append(n)
            continue
        if any(p.status == INCOMPLETE for p in o.properties):
            why = o.reason or next((p.message for p in o.properties if p.status == INCOMPLETE and p.message), "")
            notes.append({"level": "warning", "message": {"text": f"{o.path}: incomplete" + (f": {why}" if why else "")},
                          "descriptor": {"id": "incomplete"}, "locations": [_location(_spec_location(o))]})
        for p in o.properties:
            if p.status == ERROR and p.verdict == "unknown":
                notes.append({"level": "error", "message": {"text": f"{o.path}: {p.message}"},
                              "descriptor": {"id": "unknown-property"},
                              "locations": [_location(p.expect_location or _spec_location(o))]})
                continue
            r = _result_for(o, p, rule_index)
            if r is not None:
                results.append(r)
    invocation = {"executionSuccessful": code != 2, "exitCode": code}
    if command_line:
        invocation["commandLine"] = command_line
    if notes:
        invocation["toolExecutionNotifications"] = notes
    run = {
        "tool": {"driver": {"name": "asmcheck", "version": __version__, "semanticVersion": __version__,
                            "informationUri": INFO_URI, "rules": rules}},
        "invocations": [invocation],
        "originalUriBaseIds": {"%SRCROOT%": {"uri": _dir_uri(root or os.getcwd())}},
        "columnKind": "unicodeCodePoints",
        "results": results,
    }
    return {"$schema": SCHEMA, "version": "2.1.0", "runs": [run]}


def write(path: str, doc: dict) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(json.dumps(doc, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
