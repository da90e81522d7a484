"""The report formats read back by their own tools: the JSON against docs/*.schema.json, the
JUnit XML by junitparser, the SARIF log against the SARIF 2.1.0 schema (a subset written for
these tests: tests/data/sarif-2.1.0-subset.schema.json), the HTML as one self-contained file."""
from __future__ import annotations

import json
import re
from html.parser import HTMLParser
from pathlib import Path

import jsonschema
import pytest
from junitparser import Error, Failure, JUnitXml, Skipped
from referencing import Registry, Resource

from asmcheck.cli import main

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parent.parent
DATA = Path(__file__).resolve().parent / "data"
CHECK = DATA / "check"
DOCS = ROOT / "docs"


def load(path: Path) -> dict:
    return json.loads(path.read_text(encoding="utf-8"))


def validator(name: str):
    trace = load(DOCS / "trace.schema.json")
    check = load(DOCS / "check.schema.json")
    reg = Registry().with_resources([(trace["$id"], Resource.from_contents(trace)),
                                     (check["$id"], Resource.from_contents(check))])
    schema = {"trace": trace, "check": check}[name]
    cls = jsonschema.validators.validator_for(schema)
    cls.check_schema(schema)
    return cls(schema, registry=reg, format_checker=cls.FORMAT_CHECKER)


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """`asmcheck check` on tests/data/check plus a spec with an input error, every report."""
    import os
    out = tmp_path_factory.mktemp("reports")
    specs = out / "specs"
    specs.mkdir()
    for f in CHECK.glob("*.asm"):
        (specs / f.name).write_text(f.read_text())
    (specs / "properties").mkdir()
    (specs / "properties" / "tiny.prop").write_text((CHECK / "properties" / "tiny.prop").read_text())
    (specs / "zz_broken.asm").write_text("asm zz_broken\nsignature:\n\tcontrolled x Integer\n")
    old = os.getcwd()
    os.chdir(out)
    try:
        code = main(["check", "specs", "--junit", "r/check.xml", "--sarif", "r/check.sarif", "--json", "r/check.json",
                     "--html", "r/check.html", "--avalla", "r/avalla"])
    finally:
        os.chdir(old)
    return code, out


def test_exit_code_with_an_input_error(reports):
    code, _ = reports
    assert code == 2


def test_json_validates_against_the_documented_schemas(reports):
    _, out = reports
    doc = load(out / "r" / "check.json")
    validator("check").validate(doc)
    tv = validator("trace")
    cxs = [p["counterexample"] for s in doc["specs"] for p in s["properties"] if p["counterexample"]]
    assert len(cxs) == 4
    for cx in cxs:
        tv.validate(cx)
    broken = doc["specs"][-1]
    assert broken["status"] == "error" and broken["error_location"]["line"] == 3
    assert doc["gate"] == "error" and doc["summary"]["errors"] == 1


def test_the_schemas_reject_what_they_should():
    tv = validator("trace")
    good = {"property": "p", "kind": "state", "message": "",
            "trace": [{"step": 0, "choices": [], "changed": {"x": 0}, "state": {"x": 0}},
                      {"step": 1, "choices": [{"kind": "choose", "at": "choose at a.asm:1:1", "value": {"$t": "a"}},
                                              {"kind": "monitored", "at": "go", "value": True}],
                       "changed": {"s": {"set": ["a", "b"]}}, "state": {"x": 0, "s": {"set": ["a", "b"]}}}]}
    tv.validate(good)
    for bad in ({**good, "kind": "lasso"}, {**good, "trace": []},
                {**good, "trace": [{"step": 0, "choices": [{"kind": "choose", "at": "c", "value": 3}],
                                    "changed": {}, "state": {}}]},
                {**good, "extra": 1}):
        with pytest.raises(jsonschema.ValidationError):
            tv.validate(bad)


def test_explore_json_violations_follow_the_trace_schema(capsys):
    code = main(["explore", str(CHECK / "tiny_mutex.asm"), "--format", "json"])
    assert code == 1
    doc = json.loads(capsys.readouterr().out)
    tv = validator("trace")
    assert {v["property"] for v in doc["violations"]} == {"inv_mutex", "inv_last_is_critical", "stp_no_reentry"}
    for v in doc["violations"]:
        tv.validate(v)


def test_junit_reads_back_with_junitparser(reports):
    _, out = reports
    xml = JUnitXml.fromfile(str(out / "r" / "check.xml"))
    suites = {s.name: s for s in xml}
    assert list(suites) == ["specs/tiny_counter.asm", "specs/tiny_mutex.asm", "specs/tiny_mutex_fixed.asm",
                            "specs/zz_broken.asm"]
    assert (xml.tests, xml.failures, xml.errors, xml.skipped) == (7, 2, 1, 0)
    cases = {(s.name, c.name): c for s in xml for c in s}
    below = cases["specs/tiny_counter.asm", "inv_below_3"]
    (failure,) = below.result
    assert isinstance(failure, Failure) and failure.type == "violated"
    assert "step 3: r_main; reads go = true  <- violates the property" in failure.text
    assert below.classname == "specs.tiny_counter"
    assert cases["specs/tiny_counter.asm", "inv_nonnegative"].is_passed
    expected = cases["specs/tiny_mutex.asm", "inv_mutex"]
    assert expected.is_passed and "violated, as the spec expects" in expected.system_out
    fixed = cases["specs/tiny_mutex_fixed.asm", "inv_mutex"]
    assert fixed.result[0].type == "expected-violation-missing"
    (err,) = cases["specs/zz_broken.asm", "(input)"].result
    assert isinstance(err, Error) and "zz_broken.asm:3:" in err.text


def test_junit_incomplete_is_skipped(tmp_path, capsys):
    out = tmp_path / "j.xml"
    assert main(["check", str(CHECK / "tiny_mutex.asm"), "--max-states", "2", "--junit", str(out)]) == 3
    capsys.readouterr()
    xml = JUnitXml.fromfile(str(out))
    results = [r for s in xml for c in s for r in c.result]
    assert results and all(isinstance(r, Skipped) for r in results)
    assert "state limit 2 reached" in results[0].message


def test_sarif_validates_against_the_sarif_schema(reports):
    _, out = reports
    log = load(out / "r" / "check.sarif")
    schema = load(DATA / "sarif-2.1.0-subset.schema.json")
    jsonschema.Draft7Validator.check_schema(schema)
    jsonschema.Draft7Validator(schema, format_checker=jsonschema.Draft7Validator.FORMAT_CHECKER).validate(log)
    run = log["runs"][0]
    rules = [r["id"] for r in run["tool"]["driver"]["rules"]]
    for r in run["results"]:
        assert rules[r["ruleIndex"]] == r["ruleId"]
    by = {(r["ruleId"], r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]): r for r in run["results"]}
    # each violation is located at the property's declaration
    below = by["inv_below_3", "specs/tiny_counter.asm"]
    assert below["level"] == "error"
    assert below["locations"][0]["physicalLocation"]["region"] == {"startLine": 18, "startColumn": 2, "endColumn": 23}
    flow = below["codeFlows"][0]["threadFlows"][0]["locations"]
    assert [f["executionOrder"] for f in flow] == [0, 1, 2, 3]
    assert flow[-1]["state"] == {"x": {"text": "3"}}
    reentry = by["stp_no_reentry", "specs/properties/tiny.prop"]
    assert reentry["level"] == "warning"
    assert reentry["locations"][0]["physicalLocation"]["region"]["startLine"] == 10
    # the step's choose rule is the thread-flow location of a step
    step1 = reentry["codeFlows"][0]["threadFlows"][0]["locations"][1]["location"]
    assert step1["physicalLocation"]["region"]["startLine"] == 38     # choose $p in Proc ...
    mutex = by["inv_mutex", "specs/tiny_mutex.asm"]
    assert mutex["suppressions"][0]["kind"] == "inSource"
    missing = by["inv_mutex", "specs/tiny_mutex_fixed.asm"]
    assert missing["level"] == "error" and missing["locations"][0]["physicalLocation"]["region"]["startLine"] == 1
    assert missing["relatedLocations"][0]["physicalLocation"]["region"]["startLine"] == 30
    inv = run["invocations"][0]
    assert inv["executionSuccessful"] is False and inv["exitCode"] == 2
    assert inv["toolExecutionNotifications"][0]["locations"][0]["physicalLocation"]["region"]["startLine"] == 3


def test_sarif_schema_rejects_what_it_should():
    schema = load(DATA / "sarif-2.1.0-subset.schema.json")
    v = jsonschema.Draft7Validator(schema)
    ok = {"version": "2.1.0", "runs": [{"tool": {"driver": {"name": "x"}}, "results": [
        {"message": {"text": "m"}, "level": "error", "locations": [
            {"physicalLocation": {"artifactLocation": {"uri": "a.asm"}, "region": {"startLine": 1}}}]}]}]}
    v.validate(ok)
    bad = [
        {**ok, "version": "2.0.0"},
        {"version": "2.1.0", "runs": [{"tool": {"driver": {}}}]},
        {"version": "2.1.0", "runs": [{"tool": {"driver": {"name": "x"}}, "results": [{"message": {}}]}]},
        {"version": "2.1.0", "runs": [{"tool": {"driver": {"name": "x"}}, "results": [
            {"message": {"text": "m"}, "level": "fatal"}]}]},
        {"version": "2.1.0", "runs": [{"tool": {"driver": {"name": "x"}}, "results": [
            {"message": {"text": "m"}, "locations": [{"physicalLocation": {"region": {"startLine": 0}}}]}]}]},
        {"version": "2.1.0", "runs": [{"tool": {"driver": {"name": "x"}}, "results": [
            {"message": {"text": "m"}, "colour": "red"}]}]},
    ]
    for b in bad:
        assert not v.is_valid(b)


class _Refs(HTMLParser):
    def __init__(self):
        super().__init__()
        self.refs = []
        self.tags = []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        for k, val in attrs:
            if k in ("src", "href", "xlink:href") and val and not val.startswith("#"):
                self.refs.append((tag, k, val))
            if tag == "link":
                self.refs.append((tag, k, val))


def test_html_is_self_contained(reports):
    _, out = reports
    text = (out / "r" / "check.html").read_text()
    p = _Refs()
    p.feed(text)
    assert p.refs == []
    assert "script" not in p.tags and "img" not in p.tags
    assert not re.search(r"url\((?!#)", text)          # no external resources in CSS or SVG
    assert text.count("<svg") == 4 and text.count("<section") == 4
    assert 'class="chg"' in text
    assert "zz_broken.asm:3:" in text


def test_html_marks_the_violation(reports):
    _, out = reports
    text = (out / "r" / "check.html").read_text()
    sec = text[text.index("<h2>stp_no_reentry"):]
    sec = sec[:sec.index("</section>")]
    assert "r_main chooses $p = PA; reads want(PA) = true  &lt;- breaks the property" in sec and 'stroke="#cf222e"' in sec
    sec = text[text.index("<h2>inv_below_3"):]
    assert "state 3 violates the property" in sec[:sec.index("</section>")]
