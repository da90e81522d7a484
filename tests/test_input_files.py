"""Reading spec files: regular files only, one echoed line, no terminal control characters;
errors as JSON objects; a runaway recursion located at the rules that cause it."""
import json
import os
import sys
from pathlib import Path

import pytest

from asmcheck.errors import AsmError, QUOTE_WIDTH, located_recursion_error
from asmcheck.semantics.resolve import check_file

pytestmark = pytest.mark.engines("both")

sys.path.insert(0, str(Path(__file__).parent))


def _error(path):
    with pytest.raises(AsmError) as info:
        check_file(str(path))
    return info.value


@pytest.mark.skipif(not os.path.exists("/proc/self/environ"), reason="no /proc on this system")
def test_symlink_to_proc_environ_is_refused(tmp_path, monkeypatch):
    monkeypatch.setenv("ASMCHECK_TEST_SECRET", "s3cr3t-value")
    link = tmp_path / "Env.asm"
    link.symlink_to("/proc/self/environ")
    err = _error(link)
    assert (err.span.path, err.span.line, err.span.col) == (str(link), 1, 1)
    assert "a special file of the system" in err.message and "regular files only" in err.message
    assert "s3cr3t-value" not in err.render() and "s3cr3t-value" not in json.dumps(err.to_json())


def test_fifo_is_refused_without_blocking(tmp_path):
    fifo = tmp_path / "Pipe.asm"
    os.mkfifo(fifo)
    err = _error(fifo)
    assert (err.span.line, err.span.col) == (1, 1)
    assert "it is a FIFO (named pipe)" in err.message


def test_import_of_a_special_file_is_located_at_the_import(tmp_path):
    os.mkfifo(tmp_path / "Pipe.asm")
    (tmp_path / "Zero.asm").symlink_to("/dev/zero")
    (tmp_path / "Dir.asm").mkdir()
    for name, kind in (("Pipe", "a FIFO"), ("Zero", "a character device"), ("Dir", "a folder")):
        main = tmp_path / "Main.asm"
        main.write_text(f"asm Main\nimport StandardLibrary\nimport {name}\nsignature:\ndefinitions:\n")
        err = _error(main)
        assert (err.span.path, err.span.line, err.span.col) == (str(main), 3, 1), err.render()
        assert kind in err.message, err.message


def test_control_characters_are_not_echoed(tmp_path):
    p = tmp_path / "T.asm"
    p.write_bytes(b"asm T\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
                  b"\tmain rule r_main = x := \x1b[2J\x07 1\n")
    err = _error(p)
    text = err.render()
    assert (err.span.line, err.span.col) == (6, 26)
    assert not any(ord(c) < 32 and c not in "\n\t" or 0x7f <= ord(c) < 0xa0 for c in text), repr(text)
    lines = text.splitlines()
    assert lines[1] == "    \tmain rule r_main = x := ?[2J? 1"
    assert lines[2].index("^") == lines[1].index("?[2J")


def test_only_a_window_of_a_long_erroneous_line_is_echoed(tmp_path):
    p = tmp_path / "T.asm"
    filler = "x + " * 20000
    p.write_text("asm T\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
                 f"\tmain rule r_main = x := {filler}# 1\n")
    err = _error(p)
    col = len("\tmain rule r_main = x := ") + len(filler) + 1
    assert (err.span.line, err.span.col) == (6, col)
    lines = err.render().splitlines()
    assert len(lines) == 3
    assert all(len(line) <= QUOTE_WIDTH + 20 for line in lines[1:])
    assert lines[1][lines[2].index("^")] == "#"


def test_error_as_json(tmp_path):
    p = tmp_path / "T.asm"
    p.write_text("asm T\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
                 "\tmain rule r_main = x := y + 1\n")
    err = _error(p)
    assert err.to_json() == {"error": {"file": str(p), "line": 6, "col": 26, "message": "unknown function 'y'"}}
    assert json.loads(json.dumps(err.to_json())) == err.to_json()
    assert AsmError(None, "no position").to_json() == {
        "error": {"file": None, "line": None, "col": None, "message": "no position"}}


@pytest.mark.parametrize("rules,line,col,fragment", [
    ("\trule r_a = r_b[]\n\trule r_b = r_a[]\n\tmain rule r_main = r_a[]\n", 6, 7,
     "the rules r_a -> r_b -> r_a call one another without end"),
    ("\trule r_a($n in Integer) = if $n > 0 then r_a[$n + 1] endif\n\tmain rule r_main = r_a[1]\n", 6, 7,
     "the rule r_a calls itself without end"),
])
def test_runaway_recursion_is_located(tmp_path, rules, line, col, fragment):
    import helpers
    p = tmp_path / "Rec.asm"
    p.write_text("asm Rec\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n" + rules
                 + "default init s0:\n\tfunction x = 0\n")
    m = helpers.Machine(check_file(str(p)), {})
    with pytest.raises(RecursionError) as info:
        helpers.run(m, 1)
    err = located_recursion_error(info.value, str(p))
    assert (err.span.path, err.span.line, err.span.col) == (str(p), line, col), err.render()
    assert fragment in err.message


@pytest.mark.parametrize("command", [["simulate", "--steps", "1"], ["explore", "--engine", "python"]])
def test_runaway_recursion_on_the_command_line(tmp_path, command):
    import subprocess
    p = tmp_path / "Rec.asm"
    p.write_text("asm Rec\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
                 "\trule r_a = r_b[]\n\trule r_b = r_a[]\n\tmain rule r_main = r_a[]\n"
                 "default init s0:\n\tfunction x = 0\n")
    root = Path(__file__).resolve().parent.parent
    env = dict(os.environ, PYTHONPATH=str(root))
    r = subprocess.run([sys.executable, "-m", "asmcheck", *command, str(p)], capture_output=True, text=True,
                       env=env, timeout=300, cwd=str(tmp_path))
    out = r.stdout + r.stderr
    assert r.returncode == 2, out
    assert f"{p}:6:7: the rules r_a -> r_b -> r_a call one another without end" in out, out
    assert "Traceback" not in out and "internal error" not in out


def test_fifo_in_a_checked_folder_and_as_a_property_file(tmp_path):
    """Nothing blocks on a FIFO: a spec folder holding one, a property file that is one."""
    import subprocess
    (tmp_path / "specs").mkdir()
    os.mkfifo(tmp_path / "specs" / "Pipe.asm")
    good = tmp_path / "specs" / "Ok.asm"
    good.write_text("asm Ok\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
                    "\tinvariant inv_a over x: x >= 0\n\tmain rule r_main = x := 1\ndefault init s0:\n"
                    "\tfunction x = 0\n")
    os.mkfifo(tmp_path / "P.prop")
    root = Path(__file__).resolve().parent.parent
    env = dict(os.environ, PYTHONPATH=str(root))
    for args in (["check", str(tmp_path / "specs")], ["check", "--properties", str(tmp_path / "P.prop"), str(good)]):
        r = subprocess.run([sys.executable, "-m", "asmcheck", *args], capture_output=True, text=True, env=env,
                           timeout=120, cwd=str(tmp_path))
        out = r.stdout + r.stderr
        assert r.returncode == 2, out
        assert "Traceback" not in out and "internal error" not in out
    assert "P.prop" in out and "regular file" in out, out


def test_scenario_that_is_a_fifo(tmp_path):
    import subprocess
    os.mkfifo(tmp_path / "S.avalla")
    root = Path(__file__).resolve().parent.parent
    r = subprocess.run([sys.executable, "-m", "asmcheck", "scenario", str(tmp_path / "S.avalla")],
                       capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=str(root)), timeout=120,
                       cwd=str(tmp_path))
    out = r.stdout + r.stderr
    assert r.returncode == 2, out
    assert f"{tmp_path / 'S.avalla'}:1:1: cannot read" in out and "a FIFO (named pipe)" in out, out
