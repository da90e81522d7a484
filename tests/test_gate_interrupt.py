"""A Ctrl-C during the gate: the specs checked so far are the report, and the specs not reached
are listed as not checked (they were left out: the report did not show that they exist)."""
from __future__ import annotations

import json

import pytest

from asmcheck import api
from asmcheck.cli import main

pytestmark = pytest.mark.engines("python")

SPEC = """asm NAME
import StandardLibrary
signature:
	dynamic controlled x: Boolean
definitions:
	invariant over x: x or not x
	main rule r_main = x := not x
default init s0:
	function x = false
"""


def test_the_specs_not_reached_are_listed_unchecked(tmp_path, capsys, monkeypatch):
    for name in ("A", "B", "C", "D"):
        (tmp_path / f"{name}.asm").write_text(SPEC.replace("NAME", name))
    real = api.Model.explore

    def explore(self, *a, **kw):
        if self.name == "B":
            raise KeyboardInterrupt
        return real(self, *a, **kw)
    monkeypatch.setattr(api.Model, "explore", explore)
    assert main(["check", str(tmp_path), "--json", "-"]) == 3
    doc = json.loads(capsys.readouterr().out)
    got = [(s["path"].rsplit("/", 1)[-1], s["status"], [(p["property"], p["verdict"], p["message"])
                                                        for p in s["properties"]]) for s in doc["specs"]]
    assert got == [
        ("A.asm", "pass", [("invariant_1", "holds", "")]),
        ("B.asm", "incomplete", [("(not checked)", "incomplete", "interrupted (Ctrl-C)")]),
        ("C.asm", "incomplete", [("(not checked)", "incomplete", "interrupted (Ctrl-C) before this spec")]),
        ("D.asm", "incomplete", [("(not checked)", "incomplete", "interrupted (Ctrl-C) before this spec")]),
    ]
    assert doc["gate"] == "incomplete"


def test_the_table_shows_no_count_for_the_specs_not_reached(tmp_path, capsys, monkeypatch):
    for name in ("A", "B", "C"):
        (tmp_path / f"{name}.asm").write_text(SPEC.replace("NAME", name))
    real = api.Model.explore

    def explore(self, *a, **kw):
        if self.name == "B":
            raise KeyboardInterrupt
        return real(self, *a, **kw)
    monkeypatch.setattr(api.Model, "explore", explore)
    assert main(["check", str(tmp_path)]) == 3
    rows = [ln.split() for ln in capsys.readouterr().out.splitlines()[1:4]]
    assert [(r[0].rsplit("/", 1)[-1], r[1], r[2], r[3]) for r in rows] == [
        ("A.asm", "invariant_1", "holds", "2"), ("B.asm", "(not", "checked)", "incomplete"),
        ("C.asm", "(not", "checked)", "incomplete")]
    assert [r[4] for r in rows[1:]] == ["-", "-"]
