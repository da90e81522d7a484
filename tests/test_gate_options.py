"""The gate gives one set of options to many specs: --fair and --monitored apply to the specs
that declare the names (--fair ended the whole gate with an error that named no spec), and a
name that no checked spec declares is an input error (a typo passed the gate with nothing
constrained)."""
from __future__ import annotations

import json

import pytest

from asmcheck.cli import main

pytestmark = pytest.mark.engines("both")

# a choice between two: without fairness WB may be chosen for ever (f(done(WA)) is violated)
PICK = """asm Pick
import StandardLibrary
import LTLLibrary
signature:
	enum domain Who = {WA | WB}
	dynamic controlled done: Who -> Boolean
definitions:
	LTLSPEC f(done(WA))
	main rule r_main =
		choose $w in Who with true do done($w) := true
default init s0:
	function done($w in Who) = false
"""

TOGGLE = """asm Toggle
import StandardLibrary
signature:
	dynamic controlled x: Boolean
	monitored go: Boolean
definitions:
	invariant over x: x or not x
	main rule r_main = if go then x := not x endif
default init s0:
	function x = false
"""


def specs(tmp_path):
    d = tmp_path / "specs"
    d.mkdir()
    (d / "Pick.asm").write_text(PICK)
    (d / "Toggle.asm").write_text(TOGGLE)
    return d


def gate(args, capsys):
    code = main(["check", *args, "--json", "-"])
    return code, json.loads(capsys.readouterr().out)


def rows(doc):
    return [(s["path"].rsplit("/", 1)[-1], p["property"], p["verdict"], p["status"])
            for s in doc["specs"] for p in s["properties"]]


def test_fair_applies_to_the_specs_with_the_domain(tmp_path, capsys):
    d = specs(tmp_path)
    code, doc = gate([str(d)], capsys)
    assert code == 1
    assert rows(doc) == [("Pick.asm", "ltl_1", "violated", "fail"),
                         ("Toggle.asm", "invariant_1", "holds", "pass")]
    code, doc = gate([str(d), "--fair", "Who"], capsys)
    assert code == 0
    assert rows(doc) == [("Pick.asm", "ltl_1", "holds", "pass"),
                         ("Toggle.asm", "invariant_1", "holds", "pass")]


@pytest.mark.parametrize("flag, value, message", [
    ("--fair", "Whoo", "--fair Whoo: none of the checked specs has a domain Whoo"),
    ("--monitored", "gg=true", "--monitored gg: none of the checked specs has a function gg"),
])
def test_a_name_no_spec_declares_is_an_input_error(tmp_path, capsys, flag, value, message):
    d = specs(tmp_path)
    code, doc = gate([str(d), "--fair", "Who", flag, value], capsys)
    assert code == 2 and doc["gate"] == "error"
    assert rows(doc)[:2] == [("Pick.asm", "ltl_1", "holds", "pass"),
                             ("Toggle.asm", "invariant_1", "holds", "pass")]
    last = doc["specs"][-1]
    assert last["path"] == f"{flag} {value.split('=')[0]}"
    assert [(p["property"], p["status"], p["message"]) for p in last["properties"]] == [
        ("(input)", "error", message)]


def test_the_text_says_what_does_not_apply(tmp_path, capsys):
    d = specs(tmp_path)
    assert main(["check", str(d), "--monitored", "gg=true"]) == 2
    out = capsys.readouterr().out
    assert "ERROR --monitored gg: the option does not apply\n  --monitored gg: none of the checked specs has a " \
           "function gg\n" in out
    assert "gate: ERROR (exit 2)" in out


def test_the_sarif_notification_of_an_option_has_no_file(tmp_path, capsys):
    """(it was located at 'file' --fair Whoo, line 1, column 1)"""
    d = specs(tmp_path)
    out = tmp_path / "gate.sarif"
    assert main(["check", str(d), "--fair", "Whoo", "--sarif", str(out)]) == 2
    capsys.readouterr()
    inv = json.loads(out.read_text())["runs"][0]["invocations"][0]
    assert inv["toolExecutionNotifications"] == [
        {"level": "error", "message": {"text": "--fair Whoo: none of the checked specs has a domain Whoo"},
         "descriptor": {"id": "input-error"}}]
