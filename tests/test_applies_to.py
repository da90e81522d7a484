"""The 'applies to' line of a property file: names separated by commas, over several lines if
need be; anything else is an error at its own line and column (a declaration with a misspelt
keyword on the next line was read as part of the names: "bad spec name 'cnt ltl l: g(x < 20)'",
at the 'applies to' keyword)."""
from __future__ import annotations

import pytest

from asmcheck.errors import AsmSyntaxError
from asmcheck.props.files import read_prop_file

pytestmark = pytest.mark.engines("none")


@pytest.mark.parametrize("text, line, col, message", [
    ("applies to cnt\nltl l: g(x < 20)\n", 2, 1,
     "unexpected 'ltl' after the spec names of 'applies to' (names are separated by commas; a declaration "
     "starts with 'invariant', 'step', 'LTLSPEC', 'CTLSPEC', 'JUSTICE' or 'COMPASSION')"),
    ("applies to cnt x\ninvariant i: true\n", 1, 16,
     "unexpected 'x' after the spec names of 'applies to' (names are separated by commas; a declaration "
     "starts with 'invariant', 'step', 'LTLSPEC', 'CTLSPEC', 'JUSTICE' or 'COMPASSION')"),
    ("applies to cnt,, x\ninvariant i: true\n", 1, 16, "expected a spec name or '*' before ',' in 'applies to'"),
    ("applies to cnt, \ninvariant i: true\n", 1, 16, "expected a spec name or '*' after ',' in 'applies to'"),
    ("applies to  cnt-1\ninvariant i: true\n", 1, 13, "bad spec name 'cnt-1' in 'applies to'"),
    ("applies to a,\n\t  b c\ninvariant i: true\n", 2, 6,
     "unexpected 'c' after the spec names of 'applies to' (names are separated by commas; a declaration "
     "starts with 'invariant', 'step', 'LTLSPEC', 'CTLSPEC', 'JUSTICE' or 'COMPASSION')"),
    ("applies to\ninvariant i: true\n", 1, 1, "'applies to' needs spec names or '*'"),
])
def test_a_bad_applies_to_line_is_an_error_where_it_goes_wrong(tmp_path, text, line, col, message):
    p = tmp_path / "a.prop"
    p.write_text(text)
    with pytest.raises(AsmSyntaxError) as exc:
        read_prop_file(str(p))
    assert (exc.value.span.line, exc.value.span.col, exc.value.message) == (line, col, message)


@pytest.mark.parametrize("text, names", [
    ("applies to cnt\ninvariant i: true\n", ["cnt"]),
    ("applies to a, b,*\ninvariant i: true\n", ["a", "b", "*"]),
    ("applies to a, // the first\n  b\ninvariant i: true\n", ["a", "b"]),
])
def test_good_applies_to_lines(tmp_path, text, names):
    p = tmp_path / "a.prop"
    p.write_text(text)
    assert read_prop_file(str(p)).applies == names
