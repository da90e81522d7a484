"""An output folder (explore --avalla DIR, check --avalla DIR, testgen --out DIR) is checked before the
work, as an output file is: an existing file there, a file where a parent folder should be, or '-'
is a one-line usage error (check and testgen stopped on an internal error, FileExistsError or
NotADirectoryError, and explore found it only after the search)."""
from __future__ import annotations

import pytest

from asmcheck.cli import main

from helpers import write

pytestmark = pytest.mark.engines("python")

VIOL = """asm Viol
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	invariant inv_x over x: x < 3
	main rule r_main = if x < 7 then x := x + 1 endif
default init s0:
	function x = 0
"""

COMMANDS = {"explore": ["explore", "SPEC", "--avalla", "OUT"], "check": ["check", "--avalla", "OUT", "SPEC"],
            "testgen": ["testgen", "SPEC", "--out", "OUT"]}


def argv(command: str, spec: str, out: str) -> list[str]:
    return [spec if a == "SPEC" else out if a == "OUT" else a for a in COMMANDS[command]]


@pytest.mark.parametrize("command", COMMANDS)
def test_an_existing_file_is_no_output_folder(tmp_path, capsys, monkeypatch, command):
    spec = write(tmp_path, VIOL)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "notes.txt").write_text("kept\n")
    flag = COMMANDS[command][COMMANDS[command].index("OUT") - 1]
    assert main(argv(command, spec, "notes.txt")) == 2
    assert capsys.readouterr() == ("", f"asmcheck: error: {flag} notes.txt: is a file, not a folder; give a "
                                       f"folder name\n")
    assert main(argv(command, spec, "Viol.asm/sub")) == 2
    assert capsys.readouterr() == ("", f"asmcheck: error: {flag} Viol.asm/sub: {tmp_path / 'Viol.asm'} is not a "
                                       f"folder\n")
    assert main(argv(command, spec, "-")) == 2
    assert capsys.readouterr() == ("", f"asmcheck: error: {flag} -: only --json and --format print a report on "
                                       f"standard output; give a folder name\n")
    assert (tmp_path / "notes.txt").read_text() == "kept\n"


@pytest.mark.parametrize("command", COMMANDS)
def test_a_new_folder_is_made_for_the_scenarios(tmp_path, capsys, monkeypatch, command):
    spec = write(tmp_path, VIOL)
    monkeypatch.chdir(tmp_path)
    flag = COMMANDS[command][COMMANDS[command].index("OUT") - 1]
    assert main(argv(command, spec, "new/sub")) == (0 if command == "testgen" else 1)
    assert capsys.readouterr().err == f"asmcheck: created the folder {tmp_path / 'new'} for {flag}\n"
    made = sorted(p.name for p in (tmp_path / "new" / "sub").iterdir())
    assert made == (["Viol_test1.avalla"] if command == "testgen" else ["Viol.inv_x.avalla"])
