"""Imports found through -I / ASMCHECK_PATH, and the agent check of updatedBy."""
from asmcheck.cli import main
import pytest

pytestmark = pytest.mark.engines("both")

MOD = """module M
import StandardLibrary
export *
signature:
	dynamic controlled x: Integer
definitions:
"""
TOP = """asm T
import StandardLibrary
import sub/M
signature:
definitions:
	main rule r_main = x := 1
default init s0:
	function x = 0
"""


def _tree(tmp_path):
    (tmp_path / "lib" / "sub").mkdir(parents=True)
    (tmp_path / "lib" / "sub" / "M.asm").write_text(MOD, encoding="utf-8")
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "T.asm").write_text(TOP, encoding="utf-8")
    return str(tmp_path / "a" / "T.asm"), str(tmp_path / "lib")


def test_import_not_found_without_search_path(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("ASMCHECK_PATH", raising=False)
    top, _ = _tree(tmp_path)
    assert main(["parse", top]) == 2
    out = capsys.readouterr().out
    assert out.startswith(f"{top}:3:1: import not found: ")
    assert "also looked in" not in out


def test_import_found_through_option_before_or_after_the_command(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("ASMCHECK_PATH", raising=False)
    top, lib = _tree(tmp_path)
    assert main(["parse", top, "-I", lib]) == 0
    assert main(["-I", lib, "parse", top]) == 0
    assert main(["parse", top, "--import-path", str(tmp_path), "--import-path", lib]) == 0
    assert capsys.readouterr().out == f"{top}: OK\n" * 3
    # the option does not stick to later calls
    assert main(["parse", top]) == 2


def test_import_found_through_environment(tmp_path, capsys, monkeypatch):
    top, lib = _tree(tmp_path)
    monkeypatch.setenv("ASMCHECK_PATH", str(tmp_path / "nowhere") + ":" + lib)
    assert main(["simulate", top, "-n", "1", "--format", "json"]) == 0
    monkeypatch.setenv("ASMCHECK_PATH", str(tmp_path / "nowhere"))
    assert main(["parse", top]) == 2
    assert f"(also looked in: {tmp_path / 'nowhere'})" in capsys.readouterr().out


def test_missing_import_folder_is_a_usage_error(tmp_path, capsys):
    top, _ = _tree(tmp_path)
    assert main(["parse", top, "-I", str(tmp_path / "nope")]) == 2
    assert capsys.readouterr().err == f"asmcheck: error: --import-path {tmp_path / 'nope'}: no such folder\n"


UB = """asm Ub
import StandardLibrary
signature:
	abstract domain Task
	static t1: Task
	dynamic controlled x: Integer
definitions:
	main rule r_main = x := 1
default init s0:
	function x = 0
"""


def test_updated_by_needs_an_agent(tmp_path, capsys):
    (tmp_path / "Ub.asm").write_text(UB, encoding="utf-8")
    bad = tmp_path / "bad.prop"
    bad.write_text("step s1: updatedBy(t1, x)\n", encoding="utf-8")
    assert main(["explore", str(tmp_path / "Ub.asm"), "--properties", str(bad)]) == 2
    out = capsys.readouterr().err
    assert out.startswith(f"{bad}:1:20: updatedBy needs an agent (an element of Agent or of a domain that is a "
                          f"subset of it), not a value of Task\n")
    good = tmp_path / "good.prop"
    good.write_text("step s2: updatedBy(self, x)\n", encoding="utf-8")
    assert main(["explore", str(tmp_path / "Ub.asm"), "--properties", str(good)]) == 0
