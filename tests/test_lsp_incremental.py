"""Parsing one declaration again after an edit gives what parsing the whole text gives."""
from __future__ import annotations

import dataclasses
import random

import pytest

from asmcheck.errors import AsmError, Span
from asmcheck.lsp.incremental import IncrementalParser
from asmcheck.syntax import ast as A
from asmcheck.syntax.parser import parse_text

from conftest import ROOT

pytestmark = pytest.mark.engines("none")

SPECS = ["specs/sb_async_master.asm", "specs/producer_consumer.asm", "specs/visual_servoing.asm",
         "specs/buggy/sb_sync_slave_clears_lock.asm"]


def dump(x):
    """Every field of a syntax tree, spans included."""
    if isinstance(x, A.Node):
        return (type(x).__name__,) + tuple(dump(getattr(x, f.name)) for f in dataclasses.fields(x))
    if isinstance(x, (list, tuple)):
        return tuple(dump(y) for y in x)
    if isinstance(x, Span):
        return (x.path, x.line, x.col, x.end_line, x.end_col)
    return repr(x)


def outcome(parse, text):
    try:
        return dump(parse(text)), None
    except AsmError as e:
        return None, (e.span, e.message)


def edit(rnd: random.Random, text: str) -> str:
    lines = text.split("\n")
    ln = rnd.randrange(len(lines))
    kind = rnd.choice(["space", "newline", "drop-empty", "tab", "letter", "digit", "comment"])
    s = lines[ln]
    c = rnd.randrange(len(s) + 1)
    if kind == "space":
        lines[ln] = s + " "
    elif kind == "newline":
        lines.insert(ln, "")
    elif kind == "drop-empty" and s.strip() == "":
        del lines[ln]
    elif kind == "tab":
        lines[ln] = "\t" + s
    elif kind == "letter":
        lines[ln] = s[:c] + "x" + s[c:]
    elif kind == "digit":
        lines[ln] = s[:c] + "7" + s[c:]
    elif kind == "comment":
        lines.insert(ln, "\t// a note")
    return "\n".join(lines)


@pytest.mark.parametrize("rel", SPECS)
def test_incremental_parse_equals_full_parse(rel):
    path = str(ROOT / rel)
    text = (ROOT / rel).read_text(encoding="utf-8")
    inc = IncrementalParser(path)
    assert outcome(inc.parse, text) == outcome(lambda t: parse_text(t, path), text)
    rnd = random.Random(rel)
    partial = 0
    good = text
    for i in range(30):
        new = edit(rnd, good)
        got = outcome(inc.parse, new)
        want = outcome(lambda t: parse_text(t, path), new)
        assert got == want, f"edit {i} of {rel}"
        partial += inc.last_was_partial
        if want[1] is None:
            good = new          # keep editing a text that parses; a broken one is dropped
        else:
            assert outcome(inc.parse, good) == outcome(lambda t: parse_text(t, path), good)
    assert partial >= 8, f"only {partial} of 30 edits were parsed one declaration at a time"


def test_edit_inside_a_rule_moves_what_follows(tmp_path):
    text = ("asm T\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
            "\trule r_a = x := 1\n\trule r_b = x := 2\n\tmain rule r_main = r_a[]\n"
            "default init s0:\n\tfunction x = 0\n")
    path = str(tmp_path / "T.asm")
    inc = IncrementalParser(path)
    inc.parse(text)
    new = text.replace("rule r_a = x := 1", "rule r_a =\n\t\tx := 1")
    spec = inc.parse(new)
    assert inc.last_was_partial
    assert dump(spec) == dump(parse_text(new, path))
    assert [(r.name, r.span.line) for r in spec.rules] == [("r_a", 6), ("r_b", 8), ("r_main", 9)]
    assert spec.inits[0].functions[0].span.line == 11


def test_edit_of_the_declaration_that_ends_the_file(tmp_path):
    text = ("asm T\nimport StandardLibrary\nsignature:\n\tcontrolled f: Boolean\ndefinitions:\n"
            "main rule r_main = f := true and false\n")
    path = str(tmp_path / "T.asm")
    inc = IncrementalParser(path)
    inc.parse(text)
    for new in (text.replace("main rule", "\nmain rule"), text.replace("false", "false\n\t\tor true")):
        spec = inc.parse(new)
        assert inc.last_was_partial
        assert dump(spec) == dump(parse_text(new, path))
        text = new
    assert (spec.span.end_line, spec.span.end_col) == (7, 10)      # after "\t\tor true" on line 7
