"""A usage error of the command line is one line on stderr, naming the command and where its options
are listed, with exit 2 (argparse printed the command's whole usage first: a dozen lines for
explore, before the line that said what was wrong)."""
from __future__ import annotations

import pytest

from asmcheck.cli import main

pytestmark = pytest.mark.engines("none")


@pytest.mark.parametrize("argv, line", [
    (["explore", "X.asm", "--format", "xml"],
     "asmcheck explore: error: argument --format: invalid choice: 'xml' (choose from 'text', 'json', 'itf'); "
     "see asmcheck explore --help"),
    (["explore"], "asmcheck explore: error: the following arguments are required: FILE; see asmcheck explore --help"),
    (["explore", "X.asm", "-o", "out.txt"],
     "asmcheck explore: error: unrecognized arguments: -o out.txt; see asmcheck explore --help"),
    (["explore", "X.asm", "--max-states", "1e3"],
     "asmcheck explore: error: argument --max-states: invalid int value: '1e3'; see asmcheck explore --help"),
    (["bmc", "X.asm", "-k", "abc"], "asmcheck bmc: error: argument -k: invalid int value: 'abc'; see asmcheck bmc --help"),
    (["check", "--traces", "some"],
     "asmcheck check: error: argument --traces: invalid choice: 'some' (choose from 'failing', 'all', 'none'); "
     "see asmcheck check --help"),
    (["frob"], "asmcheck: error: argument COMMAND: invalid choice: 'frob' (choose from 'parse', 'simulate', "
               "'conform', 'scenario', 'explore', 'bmc', 'check', 'advise', 'testgen', 'lsp'); see asmcheck --help"),
])
def test_a_usage_error_is_one_line(capsys, argv, line):
    assert main(argv) == 2
    assert capsys.readouterr() == ("", line + "\n")


def test_help_is_still_the_whole_usage(capsys):
    assert main(["explore", "--help"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: asmcheck explore [-h] ") and "--max-states N" in out
