"""`asmcheck check`: the gate's verdicts and exit codes, and golden outputs of every report
format (text, JSON, JUnit, SARIF, HTML, Avalla) on the fixed specs of tests/data/check.

Set ASMCHECK_UPDATE_GOLDEN=1 to rewrite the golden files (then review the diff)."""
from __future__ import annotations

import json
import os
import re
from pathlib import Path

import pytest

from asmcheck import __version__, api
from asmcheck.cli import main

pytestmark = pytest.mark.engines("both")

DATA = Path(__file__).resolve().parent / "data"
CHECK = DATA / "check"
GOLDEN = DATA / "golden"
UPDATE = bool(os.environ.get("ASMCHECK_UPDATE_GOLDEN"))


class FakeClock:
    """Every call is 0.25 s after the one before: each spec takes 0.25 s."""

    def __init__(self):
        self.t = 0.0

    def __call__(self):
        self.t += 0.25
        return self.t


@pytest.fixture
def fixed_clock(monkeypatch):
    monkeypatch.setattr(api, "CLOCK", FakeClock())


def normalize(text: str, out: Path) -> str:
    text = text.replace(str(out), "@OUT@")
    text = text.replace(CHECK.as_uri(), "file:///@DATA@")
    text = text.replace(str(CHECK), "@DATA@")
    text = re.sub(r"^load .*?([A-Za-z0-9_]+\.asm)$", r"load @DATA@/\1", text, flags=re.M)
    return text.replace(__version__, "@VERSION@")


def golden(name: str, actual: str) -> None:
    path = GOLDEN / name
    if UPDATE or not path.exists():
        if not UPDATE:
            pytest.fail(f"no golden file {path}: run with ASMCHECK_UPDATE_GOLDEN=1 to write it")
        path.write_text(actual, encoding="utf-8")
        return
    expected = path.read_text(encoding="utf-8")
    assert actual == expected, f"{name} differs from its golden file (ASMCHECK_UPDATE_GOLDEN=1 rewrites it)"


@pytest.fixture
def golden_run(tmp_path, monkeypatch, capsys, fixed_clock):
    """`asmcheck check .` in tests/data/check with every report, once per test."""
    out = tmp_path / "out"
    monkeypatch.chdir(CHECK)
    code = main(["check", ".", "--traces", "all",
                 "--junit", str(out / "check.xml"), "--sarif", str(out / "check.sarif"),
                 "--json", str(out / "check.json"), "--html", str(out / "check.html"),
                 "--avalla", str(out / "avalla")])
    stdout = capsys.readouterr().out
    return code, stdout, out


def test_golden_text(golden_run):
    code, stdout, out = golden_run
    assert code == 1
    golden("check.txt", normalize(stdout, out))


def test_golden_json(golden_run):
    _, _, out = golden_run
    golden("check.json", normalize((out / "check.json").read_text(), out))


def test_golden_junit(golden_run):
    _, _, out = golden_run
    golden("check.xml", normalize((out / "check.xml").read_text(), out))


def test_golden_sarif(golden_run):
    _, _, out = golden_run
    golden("check.sarif", normalize((out / "check.sarif").read_text(), out))


def test_golden_html(golden_run):
    _, _, out = golden_run
    golden("check.html", normalize((out / "check.html").read_text(), out))


def test_golden_avalla(golden_run):
    _, _, out = golden_run
    files = sorted((out / "avalla").glob("*.avalla"))
    assert [f.name for f in files] == ["tiny_counter.inv_below_3.avalla", "tiny_mutex.inv_last_is_critical.avalla",
                                       "tiny_mutex.inv_mutex.avalla", "tiny_mutex.stp_no_reentry.avalla"]
    for f in files:
        golden(f.name, normalize(f.read_text(), out))


# ----------------------------------------------------------------- the gate
def write(tmp_path: Path, name: str, text: str) -> str:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return str(p)


COUNTER = """{head}asm {name}
import StandardLibrary
signature:
	domain Small subsetof Integer
	controlled x: Small
	monitored go: Boolean
definitions:
	domain Small = {{0 : 3}}
	invariant inv_small over x: x <= {bound}
	main rule r_main = if go then if x < 3 then x := x + 1 else x := 0 endif endif
default init s0:
	function x = 0
"""


def counter(tmp_path, name="counter", bound=3, head="") -> str:
    return write(tmp_path, f"{name}.asm", COUNTER.format(name=name, bound=bound, head=head))


def run_check(capsys, *argv):
    code = main(["check", *argv])
    return code, capsys.readouterr()


def test_all_hold_exits_0(tmp_path, capsys):
    code, out = run_check(capsys, counter(tmp_path))
    assert code == 0
    assert "gate: PASS (exit 0)" in out.out
    assert re.search(r"counter\.asm\s+inv_small\s+holds\s+4\s", out.out)


def test_unexpected_violation_exits_1_with_its_counterexample(tmp_path, capsys):
    code, out = run_check(capsys, counter(tmp_path, bound=2))
    assert code == 1
    assert "FAIL " in out.out and "inv_small" in out.out and "shortest counterexample, 3 steps" in out.out
    assert "step 3: r_main; reads go = true  <- violates the property" in out.out


def test_expected_violation_passes_and_missing_one_fails(tmp_path, capsys):
    bad = counter(tmp_path, "bad", 2, "// asmcheck: expect violated inv_small\n")
    good = counter(tmp_path, "good", 3, "// asmcheck: expect violated inv_small\n")
    code, out = run_check(capsys, bad)
    assert code == 0 and "violated (expected)" in out.out
    code, out = run_check(capsys, good)
    assert code == 1 and "holds (expected to be violated)" in out.out
    assert "good.asm:1:1" in out.out


def test_tolerated_violations_and_strict_expect(capsys, monkeypatch):
    monkeypatch.chdir(CHECK)
    code, out = run_check(capsys, "tiny_mutex.asm")
    assert code == 0
    assert "violated (tolerated)" in out.out
    code, out = run_check(capsys, "tiny_mutex.asm", "--strict-expect")
    assert code == 1
    assert out.out.count("VIOLATED") == 2


def test_unknown_expected_property_is_an_input_error(tmp_path, capsys):
    p = counter(tmp_path, "typo", 3, "// asmcheck: expect violated inv_smal\n")
    code, out = run_check(capsys, p)
    assert code == 2
    assert "no such property" in out.out
    assert "the spec expects inv_smal to be violated, but no property inv_smal is checked on it" in out.out


def test_input_error_exits_2_and_other_specs_still_run(tmp_path, capsys):
    counter(tmp_path, "ok")
    write(tmp_path, "broken.asm", "asm broken\nsignature:\n\tcontrolled x Integer\n")
    code, out = run_check(capsys, str(tmp_path))
    assert code == 2
    assert "ERROR " in out.out and "broken.asm:3:" in out.out
    assert re.search(r"ok\.asm\s+inv_small\s+holds", out.out)


def test_limit_exits_3(tmp_path, capsys):
    code, out = run_check(capsys, counter(tmp_path), "--max-states", "2")
    assert code == 3
    assert "incomplete" in out.out and "state limit 2 reached" in out.out


def test_violation_wins_over_incomplete(tmp_path, capsys):
    d = tmp_path / "d"
    d.mkdir()
    counter(d, "a", 0)          # violated at depth 1
    counter(d, "b", 3)          # incomplete at depth 1
    code, out = run_check(capsys, str(d), "--max-depth", "1")
    assert code == 1
    assert re.search(r"b\.asm\s+inv_small\s+incomplete", out.out)


def test_missing_path_and_empty_folder_are_input_errors(tmp_path, capsys):
    code, out = run_check(capsys, str(tmp_path / "nope"))
    assert code == 2 and "no such file or folder" in out.err
    code, out = run_check(capsys, str(tmp_path))
    assert code == 2 and "no .asm specs" in out.err


def test_folders_are_walked_sorted_and_modules_skipped(tmp_path):
    (tmp_path / "sub").mkdir()
    counter(tmp_path / "sub", "b")
    counter(tmp_path, "a")
    write(tmp_path, "lib.asm", "// a module\nmodule lib\nimport StandardLibrary\nsignature:\ndefinitions:\n")
    found = api.find_specs([str(tmp_path)])
    assert [Path(f).name for f in found] == ["a.asm", "b.asm"]


def test_json_to_stdout(tmp_path, capsys):
    code, out = run_check(capsys, counter(tmp_path, bound=2), "--json", "-")
    doc = json.loads(out.out)
    assert code == 1 and doc["gate"] == "fail" and doc["exit_code"] == 1
    row = doc["specs"][0]["properties"][0]
    assert (row["property"], row["status"], row["counterexample"]["kind"]) == ("inv_small", "fail", "state")


def test_default_paths_is_specs(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "specs").mkdir()
    counter(tmp_path / "specs")
    code, out = run_check(capsys)
    assert code == 0 and "specs/counter.asm" in out.out


def test_colour_only_on_a_terminal():
    from asmcheck.report.gate import Counterexample, StepRecord, trace_lines
    cx = Counterexample("state", "", [StepRecord(0, "r_main", [], {"x": "0"}, {"x": "0"}),
                                      StepRecord(1, "r_main", [], {"x": "1"}, {"x": "1"})], [])
    plain = trace_lines(cx, False)
    assert plain == ["state 0 (initial)", "    x = 0", "step 1: r_main  <- violates the property", "    x = 1"]
    coloured = trace_lines(cx, True)
    assert any("\x1b[" in ln for ln in coloured)
    assert [re.sub(r"\x1b\[[0-9;]*m", "", ln) for ln in coloured] == plain
