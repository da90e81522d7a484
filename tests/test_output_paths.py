"""A report never overwrites a spec or a property file (`explore s.asm --html s.asm` replaced the
spec with the HTML report), and '-' is standard output only for --json (--junit -, --sarif -,
--html - wrote a file named '-')."""
from __future__ import annotations

import pytest

from asmcheck.cli import main

pytestmark = pytest.mark.engines("python")

SPEC = """asm Tiny
import StandardLibrary
signature:
	dynamic controlled x: Boolean
definitions:
	invariant over x: x or not x
	main rule r_main = x := not x
default init s0:
	function x = false
"""


@pytest.mark.parametrize("args", [
    ["explore", "SPEC", "--html", "VICTIM"],
    ["explore", "SPEC", "--coverage", "VICTIM"],
    ["check", "SPEC", "--junit", "VICTIM"],
    ["check", "SPEC", "--sarif", "VICTIM"],
    ["check", "SPEC", "--html", "VICTIM"],
    ["check", "SPEC", "--json", "VICTIM"],
])
@pytest.mark.parametrize("victim, what", [("Other.asm", "a spec"), ("p.prop", "a property file")])
def test_a_report_never_overwrites_an_input(tmp_path, capsys, args, victim, what):
    spec = tmp_path / "Tiny.asm"
    spec.write_text(SPEC)
    target = tmp_path / victim
    target.write_text("keep me\n")
    argv = [str(spec) if a == "SPEC" else str(target) if a == "VICTIM" else a for a in args]
    assert main(argv) == 2
    cap = capsys.readouterr()
    assert cap.err == (f"asmcheck: error: {args[2]} {target}: is {what}; asmcheck does not write a report over "
                       f"it (give another file name)\n")
    assert target.read_text() == "keep me\n"


@pytest.mark.parametrize("opt", ["--junit", "--sarif", "--html"])
def test_only_json_prints_on_standard_output(tmp_path, capsys, monkeypatch, opt):
    spec = tmp_path / "Tiny.asm"
    spec.write_text(SPEC)
    monkeypatch.chdir(tmp_path)
    assert main(["check", str(spec), opt, "-"]) == 2
    assert capsys.readouterr().err == (f"asmcheck: error: {opt} -: only --json and --format print a report on "
                                       f"standard output; give a file name\n")
    assert not (tmp_path / "-").exists()


def test_a_report_file_is_still_written(tmp_path, capsys):
    spec = tmp_path / "Tiny.asm"
    spec.write_text(SPEC)
    assert main(["check", str(spec), "--junit", str(tmp_path / "r.xml")]) == 0
    assert (tmp_path / "r.xml").read_text().startswith("<?xml")
