"""The JSON of verdicts decided on a partial state space follows the documented schemas: the
gate's rows and the explore report's violations carry 'decided_on', which docs/check.schema.json
did not allow (a consumer that validates the gate's JSON rejected it)."""
from __future__ import annotations

import json

import pytest

from asmcheck.cli import main
from test_report_formats import validator

pytestmark = pytest.mark.engines("both")

COUNT = """asm Count
import StandardLibrary
import CTLLibrary
signature:
	domain Cnt subsetof Integer
	dynamic controlled x: Cnt
	monitored inc: Boolean
definitions:
	domain Cnt = {0 : 9}
	CTLSPEC ag(x < 3)
	CTLSPEC ef(x = 2)
	main rule r_main =
		if inc then
			if x < 9 then x := x + 1 else x := 0 endif
		endif
default init s0:
	function x = 0
"""


def test_the_gate_json_with_decided_rows_validates(write_spec, capsys):
    path = write_spec(COUNT)
    assert main(["check", path, "--max-states", "5", "--json", "-"]) == 1
    doc = json.loads(capsys.readouterr().out)
    rows = doc["specs"][0]["properties"]
    assert [(r["property"], r["verdict"], r["decided_on"]) for r in rows] == [("ctl_1", "violated", 5),
                                                                               ("ctl_2", "holds", 5)]
    validator("check").validate(doc)


def test_the_explore_json_violations_with_decided_on_validate(write_spec, capsys):
    path = write_spec(COUNT)
    assert main(["explore", path, "--max-states", "5", "--format", "json"]) == 1
    doc = json.loads(capsys.readouterr().out)
    assert [(v["property"], v["decided_on"]) for v in doc["violations"]] == [("ctl_1", 5)]
    tv = validator("trace")
    for v in doc["violations"]:
        tv.validate(v)
