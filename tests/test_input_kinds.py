"""A file of inputs (simulate --input) that is a folder or not a regular file is refused in plain
words ('not an input file': it said 'not a input file')."""
from __future__ import annotations

import os

import pytest

from asmcheck.cli import main

from helpers import write

pytestmark = pytest.mark.engines("none")

COUNT = """asm Count
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	main rule r_main = x := x + 1
default init s0:
	function x = 0
"""


def test_a_folder_given_as_inputs(tmp_path, capsys, monkeypatch):
    spec = write(tmp_path, COUNT)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "inputs").mkdir()
    assert main(["simulate", spec, "--input", "inputs"]) == 2
    assert capsys.readouterr() == ("", "inputs: is a folder, not an input file\n")
    assert main(["explore", "inputs"]) == 2
    assert capsys.readouterr() == ("", "inputs: is a folder, not a spec\n")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes here")
def test_a_named_pipe_given_as_inputs(tmp_path, capsys, monkeypatch):
    spec = write(tmp_path, COUNT)
    monkeypatch.chdir(tmp_path)
    os.mkfifo(tmp_path / "pipe")
    assert main(["simulate", spec, "--input", "pipe"]) == 2
    assert capsys.readouterr() == ("", "pipe:1:1: cannot read pipe: it is a FIFO (named pipe); asmcheck reads "
                                       "regular files only\n")
