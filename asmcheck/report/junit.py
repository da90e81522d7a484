"""``asmcheck check --junit``: a JUnit XML report, the format CI servers read.

One ``<testsuite>`` per spec (named by its path), one ``<testcase>`` per property (its
``classname`` is the spec's path with dots, as Java class names, so CI servers group the specs
by folder).  A case

* passes when the property holds, is violated as the spec expects, or is a tolerated
  violation (its counterexample is then in ``<system-out>``);
* has a ``<failure>`` when the property is violated unexpectedly (the message says where it
  is declared, the text is the counterexample) or when an expected violation does not happen;
* has an ``<error>`` on an input error (the spec's only case is then ``(input)``);
* is ``<skipped>`` when the exploration was incomplete (the message says which limit).
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

from .gate import ERROR, FAIL, INCOMPLETE, cx_summary, trace_lines


def _classname(path: str) -> str:
    p = path[:-4] if path.endswith(".asm") else path
    return p.replace("\\", "/").strip("/").replace("/", ".").lstrip(".") or p


def _cx_text(p) -> str:
    cx = p.counterexample
    if cx is None:
        return ""
    lines = []
    if p.location:
        lines.append(f"{p.name} is declared at {p.location}")
    if p.text:
        lines.append(f"formula: {p.text}")
    if cx.fairness:
        lines.append(f"under fairness: {'; '.join(cx.fairness)}")
    if cx.steps:
        lines.append(cx_summary(cx) + ":")
    lines.extend(trace_lines(cx, False))
    if cx.avalla_path:
        lines.append(f"Avalla scenario: {cx.avalla_path}")
    return "\n".join(lines) + "\n"


def junit_xml(outcomes, timings: bool = True) -> str:
    root = ET.Element("testsuites", name="asmcheck check")
    tot = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
    total_time = 0.0
    for o in outcomes:
        n = {"tests": 0, "failures": 0, "errors": 0, "skipped": 0}
        suite = ET.SubElement(root, "testsuite", name=o.path)
        props = ET.SubElement(suite, "properties")
        for k, v in (("spec", o.name), ("verdict", o.verdict), ("states", o.states),
                     ("transitions", o.transitions), ("depth", o.depth),
                     ("expected_violations", ",".join(o.expected))):
            ET.SubElement(props, "property", name=k, value=str(v))
        for p in o.properties:
            n["tests"] += 1
            # a property declared in a property file points there (file and line), one of the spec at the spec
            where = p.location if p.location else None
            case = ET.SubElement(suite, "testcase", name=p.name, classname=_classname(o.path),
                                 file=where.path if where else o.path)
            if where:
                case.set("line", str(where.line))
            if p.status == FAIL:
                n["failures"] += 1
                if p.verdict == "violated":
                    msg = f"{p.name} is violated" + (f": {p.message}" if p.message else "")
                    if getattr(p, "relative_to", None) is not None:
                        msg += f" (relative to the run-time error at {p.relative_to})"
                    typ = "violated"
                else:
                    msg = f"{p.name} holds, but the spec expects it to be violated"
                    if p.expect_location:
                        msg += f" ({p.expect_location})"
                    typ = "expected-violation-missing"
                el = ET.SubElement(case, "failure", message=msg, type=typ)
                el.text = _cx_text(p) or None
            elif p.status == ERROR:
                n["errors"] += 1
                el = ET.SubElement(case, "error", message=p.message or "input error", type="input-error")
                el.text = (o.error + "\n") if o.error else None
            elif p.status == INCOMPLETE:
                n["skipped"] += 1
                ET.SubElement(case, "skipped", message=f"{p.label}: {o.reason or p.message}")
            elif p.counterexample is not None:
                out = ET.SubElement(case, "system-out")
                note = "violated, as the spec expects" if p.expected else \
                    "violated; tolerated: the spec declares other expected violations"
                out.text = note + "\n" + _cx_text(p)
            elif getattr(p, "relative_to", None) is not None:
                # the property holds on the well-defined steps: say so beside the passing case
                ET.SubElement(case, "system-out").text = p.label + "\n"
        for k in tot:
            suite.set(k, str(n[k]))
            tot[k] += n[k]
        if timings:
            suite.set("time", f"{o.seconds:.3f}")
        total_time += o.seconds
    for k, v in tot.items():
        root.set(k, str(v))
    if timings:
        root.set("time", f"{total_time:.3f}")
    ET.indent(root, space="  ")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write(path: str, text: str) -> None:
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    Path(path).write_text(text, encoding="utf-8")
