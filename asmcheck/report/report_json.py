"""``asmcheck check --json``: the results as JSON (schema: docs/check.schema.json; each
counterexample of an invariant, step property, deadlock or error follows
docs/trace.schema.json, the format of ``asmcheck explore --format json``'s violations)."""
from __future__ import annotations

import json
from pathlib import Path

from ..version import __version__

GATE = {0: "pass", 1: "fail", 2: "error", 3: "incomplete"}


def _row(p) -> dict:
    cx = p.counterexample
    return {
        "property": p.name,
        "kind": p.kind,
        "verdict": p.verdict,
        "expected": p.expected,
        "status": p.status,
        "label": p.label,
        "location": p.location.json() if p.location else None,
        "expect_location": p.expect_location.json() if p.expect_location else None,
        "text": p.text,
        "message": p.message,
        "counterexample": cx.json if cx is not None else None,
        "avalla": cx.avalla_path if cx is not None else None,
        **({"relative_to": p.relative_to.json()} if getattr(p, "relative_to", None) is not None else {}),
        **({"decided_on": p.decided_on} if getattr(p, "decided_on", None) is not None else {}),
    }


def spec_json(o, timings: bool = True) -> dict:
    return {
        "path": o.path,
        "spec": o.name,
        "verdict": o.verdict,
        "status": o.status,
        "states": o.states,
        "transitions": o.transitions,
        "depth": o.depth,
        "seconds": round(o.seconds, 3) if timings else 0.0,
        "incomplete": o.reason or None,
        "error": o.error or None,
        "error_location": o.error_location.json() if o.error_location else None,
        "expected_violations": list(o.expected),
        "properties": [_row(p) for p in o.properties],
    }


def check_json(outcomes, code: int, timings: bool = True) -> dict:
    from .gate import counts
    return {
        "tool": "asmcheck",
        "version": __version__,
        "gate": GATE[code],
        "exit_code": code,
        "summary": counts(outcomes),
        "specs": [spec_json(o, timings) for o in outcomes],
    }


def dumps(doc) -> str:
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def dump(stream, doc) -> None:
    stream.write(dumps(doc))


def write(path: str, doc) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(dumps(doc), encoding="utf-8")
