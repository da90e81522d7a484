"""The command layer keeps its promises: a verdict is never vacuous, options are checked
against the spec, limits are limits (time for the whole command, memory), interrupted work
is reported, outputs are checked before the search, a closed stdout keeps the exit code."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from asmcheck.cli import main

from helpers import warm_native, write

from asmcheck.explore.bfs import memory_text

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
ENV.pop("ASMCHECK_DEBUG", None)

NOPROP = """asm NoProp
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	main rule r_main = if x < 3 then x := x + 1 endif
default init s0:
	function x = 0
"""

# one path that never ends: every state is new; inv_small breaks at depth 30, inv_pos never
COUNTER = """asm Counter
import StandardLibrary
signature:
	controlled x: Integer
	controlled y: Integer
definitions:
	invariant inv_small over x: x < {bound}
	invariant inv_pos over x: x >= 0
	main rule r_main = par
		x := x + 1
		y := y + 2
	endpar
default init s0:
	function x = 0
	function y = 0
"""

MONITORED = """asm Mon
import StandardLibrary
signature:
	enum domain Mode = {ON | OFF | IDLE}
	domain Small subsetof Integer
	monitored mode: Mode
	monitored timeUp: Boolean
	monitored n: Integer
	monitored k: Small
	controlled last: Mode
definitions:
	domain Small = {1 : 4}
	invariant inv_any over last: last = ON or last = OFF or last = IDLE or isUndef(last)
	main rule r_main = if timeUp and n >= 0 and k > 0 then last := mode endif
"""

# one step enumerates 64 million bindings of a choose
SLOW_STEP = """asm SlowStep
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	invariant inv_x over x: x >= 0
	main rule r_main = choose $a in {0 : 8000}, $b in {0 : 8000} with $a + $b = 15999 + x do x := $a
default init s0:
	function x = 0
"""

LTL = """asm Ltl
import StandardLibrary
import LTLLibrary
signature:
	controlled x: Integer
definitions:
	invariant inv_x over x: x >= 0
	LTLSPEC ltlSpec_grows: g(x >= 0)
	main rule r_main = x := (x + 1) mod 50
default init s0:
	function x = 0
"""


def run_cli(*args, timeout=120, **kw):
    return subprocess.run([sys.executable, "-m", "asmcheck", *args], capture_output=True, text=True, env=ENV,
                          timeout=timeout, cwd=kw.get("cwd"))


def clean(text: str) -> None:
    assert "Traceback" not in text and "internal error" not in text, text


# ----------------------------------------------------------------- 1, 2: no vacuous verdicts
def test_check_of_a_spec_without_properties_is_an_error_not_a_pass(tmp_path, capsys):
    path = write(tmp_path, NOPROP)
    assert main(["check", path]) == 2
    got = capsys.readouterr()
    clean(got.out + got.err)
    assert "no property checked" in got.out and "gate: ERROR (exit 2)" in got.out
    assert main(["check", path, "--json", "-"]) == 2
    doc = json.loads(capsys.readouterr().out)
    assert doc["gate"] == "error"
    [row] = doc["specs"][0]["properties"]
    assert (row["verdict"], row["status"], row["label"]) == ("none", "error", "no property checked")


def test_explore_says_no_property_checked_and_names_the_files_that_would_apply(tmp_path, capsys, monkeypatch):
    lib = tmp_path / "lib"
    lib.mkdir()
    path = write(lib, NOPROP)
    proj = tmp_path / "proj"
    (proj / "properties").mkdir(parents=True)
    (proj / "properties" / "noprop.prop").write_text("applies to NoProp\ninvariant inv_x: x <= 3\n")
    monkeypatch.chdir(proj)
    assert main(["explore", path]) == 0
    out = capsys.readouterr().out
    assert "verdict: holds" not in out
    assert out.endswith("no property checked\nproperty files that name NoProp (give them with --properties):\n"
                        f"  {proj / 'properties' / 'noprop.prop'}\nverdict: no property checked\n")
    assert main(["explore", path, "--properties", "properties/noprop.prop", "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert (doc["verdict"], [r["property"] for r in doc["properties"]]) == ("holds", ["inv_x"])


# ----------------------------------------------------------------- 3: a property file must apply
def test_a_given_property_file_that_does_not_apply_is_an_error(tmp_path, capsys):
    path = write(tmp_path, NOPROP)
    typo = tmp_path / "typo.prop"
    typo.write_text("applies to NoPorp\ninvariant inv_x: x <= 3\n")
    assert main(["explore", path, "--properties", str(typo)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{typo}:1:1: the property file {typo} applies to NoPorp, not to NoProp")
    assert main(["check", path, "--properties", str(typo)]) == 2
    out = capsys.readouterr().out
    assert f"the property file {typo} applies to NoPorp: none of the checked specs has that name" in out
    assert "gate: ERROR (exit 2)" in out


# ----------------------------------------------------------------- 4, 20: options checked against the spec
@pytest.mark.parametrize("args, message", [
    (["--monitored", "nope=1..2"], "--monitored nope: nope is not a function of the spec; the monitored functions "
                                   "are: k, mode, n, timeUp"),
    (["--monitored", "last=ON"], "--monitored last: last is a controlled function"),
    (["--monitored", "timeUp=1..2"], "--monitored timeUp: 1..2 is not within timeUp's codomain Boolean"),
    (["--monitored", "timeUp=yes"], "--monitored timeUp: 'yes' is not a value of timeUp's codomain Boolean"),
    (["--monitored", "mode=ON,DOWN"], "--monitored mode: 'DOWN' is not a value of mode's codomain Mode"),
    (["--monitored", "n=abc"], "--monitored n: 'abc' is not an integer"),
    (["--monitored", "n=2..1"], "--monitored n 2..1: the range is empty"),
    (["--monitored", "k=0..2"], "--monitored k: 0..2 is not within k's codomain Small"),
    (["--monitored", "n=0..100000000"], "--monitored n 0..100000000: 100,000,001 values"),
    (["--monitored", "n=1", "--monitored", "n=2"], "--monitored n is given twice"),
    (["--int-range", "5..1"], "--int-range 5..1: the range is empty"),
    (["--int-range", "abc"], "--int-range 'abc': expected LO..HI"),
    (["--int-range", "0..123456789012345678901"], "--int-range: 123456789012345678901 is outside the 64-bit"),
])
def test_bad_domain_options_are_usage_errors(tmp_path, capsys, args, message):
    path = write(tmp_path, MONITORED)
    assert main(["explore", path, *args]) == 2
    got = capsys.readouterr()
    clean(got.out + got.err)
    assert got.err.startswith(f"asmcheck: error: {message}"), got.err


def test_monitored_values_are_read_against_the_codomain(tmp_path, capsys):
    path = write(tmp_path, MONITORED)
    # an enum value names the element (it was a string that matched nothing)
    assert main(["explore", path, "--monitored", "mode=ON", "--monitored", "timeUp=true", "--monitored", "n=0",
                 "--monitored", "k=1", "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert (doc["states"], doc["transitions"]) == (2, 2)
    assert main(["explore", path, "--monitored", "mode=ON,OFF", "--monitored", "n=-1..0", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["states"] == 3


def test_every_unbounded_monitored_integer_is_reported_at_once(tmp_path, capsys):
    path = write(tmp_path, MONITORED.replace("monitored k: Small", "monitored k: Integer"))
    assert main(["explore", path]) == 2
    err = capsys.readouterr().err
    first = err.splitlines()[0]
    assert first == (f"{path}:8:12: 2 monitored functions range over infinite domains (n, k): give their values "
                     f"with --monitored n=LO..HI --monitored k=LO..HI (or --int-range LO..HI)")
    assert f"{path}:9:12: note: monitored function k ranges over Integer" in err
    # a negative bound after the option, without '='
    assert main(["explore", path, "--int-range", "-3..3", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["states"] == 4
    assert main(["explore", path, "--int-range", "-1000..1000", "--monitored", "mode=ON", "--monitored",
                 "timeUp=true", "--monitored", "n=-2", "--monitored", "k=-1", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["states"] == 1


# ----------------------------------------------------------------- 6: a closed stdout keeps the verdict
@pytest.mark.engines("python")
def test_a_closed_stdout_keeps_the_exit_code_of_the_verdict(tmp_path):
    path = write(tmp_path, COUNTER.format(bound=30))
    proc = subprocess.Popen([sys.executable, "-m", "asmcheck", "explore", path, "--engine", "python",
                             "--max-depth", "60", "--no-default-properties"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV)
    first = proc.stdout.readline()
    proc.stdout.close()                      # as `| head -1` does
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=60) == 1, err   # inv_small is violated
    assert first.startswith(b"Counter.asm: 61 states")
    clean(err)


# ----------------------------------------------------------------- 10, 11: limits
@pytest.mark.engines("python")
def test_max_seconds_bounds_the_whole_command_even_inside_one_step(tmp_path):
    path = write(tmp_path, SLOW_STEP)
    t0 = time.monotonic()
    res = run_cli("explore", path, "--max-seconds", "2", "--engine", "python")
    wall = time.monotonic() - t0
    clean(res.stdout + res.stderr)
    assert res.returncode == 3
    assert "inv_x                                    incomplete" in res.stdout
    assert "incomplete: time limit 2.0 s reached" in res.stdout
    assert wall < 2 + 4, wall                 # the step alone runs for minutes


def sequences_before_the_limit(stdout: str, seconds: str, after_a: str, a_values: str = "2,001") -> int:
    """The report's 'incomplete:' line for a time limit met inside state 0's enumeration of the
    inputs a and b (``a_values`` values each; ``after_a``: the pattern of what the line names
    after a): the number of sequences of choices it gives."""
    import re
    line = next(ln for ln in stdout.splitlines() if ln.startswith("incomplete:"))
    m = re.fullmatch(rf"incomplete: time limit {re.escape(seconds)} s reached, while enumerating the successors "
                     rf"of state 0 \(([\d,]+) sequences of choices so far; its step chooses among "
                     rf"a \({a_values} values\){after_a}\); bound the monitored inputs with --monitored "
                     rf"NAME=LO\.\.HI or NAME=V1,V2", line)
    assert m, line
    return int(m.group(1).replace(",", ""))


WIDE_INPUTS = """asm WideInputs
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled x: Integer
	monitored a: D
	monitored b: D
definitions:
	domain D = {0 : 2000}
	invariant inv_x over x: x >= 0
	main rule r_main = x := a + b
default init s0:
	function x = 0
"""


@pytest.mark.engines("python")
def test_a_time_limit_inside_a_wide_branching_names_the_inputs_that_multiply(tmp_path):
    # 2,001 x 2,001 sequences of inputs from the initial state: the limit stops the search
    # inside that one state's enumeration, and the report says so, with the way to bound them
    path = write(tmp_path, WIDE_INPUTS)
    res = run_cli("explore", path, "--max-seconds", "2", "--engine", "python")
    clean(res.stdout + res.stderr)
    assert res.returncode == 3
    assert sequences_before_the_limit(res.stdout, "2.0", r"(, b \(2,001 values\))?") >= 1000


WIDE_HEAVY = """asm WideHeavy
import StandardLibrary
signature:
	domain D subsetof Integer
	controlled x: Integer
	controlled s: D -> Integer
	monitored a: D
	monitored b: D
definitions:
	domain D = {0 : 999}
	invariant inv_x over x: x >= 0
	main rule r_main = par
		x := a + b
		forall $i in D with $i < a do s($i) := b
	endpar
default init s0:
	function x = 0
"""


@pytest.mark.engines("native")
def test_the_native_engine_also_names_the_inputs_that_multiply_at_a_time_limit(tmp_path):
    # the same diagnosis from the compiled search, stopped inside state 0's 1,000,000 sequences of
    # inputs (each with up to 1,000 updates: the time limit comes far before the last of them; a
    # state whose choice sizes multiply beyond 1,000,000 is refused before its enumeration)
    path = write(tmp_path, WIDE_HEAVY)
    warm_native(path)
    res = run_cli("explore", path, "--max-seconds", "3", "--engine", "native")
    clean(res.stdout + res.stderr)
    assert res.returncode == 3
    assert "native engine" in res.stdout.splitlines()[0]
    assert 1000 <= sequences_before_the_limit(res.stdout, "3.0", r", b \(1,000 values\)", "1,000") < 1_000_000


def test_a_limit_keeps_every_property_in_every_report(tmp_path, capsys):
    path = write(tmp_path, LTL)
    assert main(["explore", path, "--max-states", "5"]) == 3
    out = capsys.readouterr().out
    assert "  ltlSpec_grows                            incomplete\n" in out
    assert main(["explore", path, "--max-states", "5", "--format", "json"]) == 3
    rows = json.loads(capsys.readouterr().out)["properties"]
    assert rows == [{"property": "inv_x", "kind": "invariant", "verdict": "incomplete"},
                    {"property": "ltlSpec_grows", "kind": "ltl", "verdict": "incomplete"}]
    junit = tmp_path / "out.xml"
    assert main(["check", path, "--max-states", "5", "--junit", str(junit)]) == 3
    assert f"INCOMPLETE {path}: ltlSpec_grows: incomplete (state limit 5 reached)" in capsys.readouterr().out
    xml = junit.read_text()
    assert '<testcase name="ltlSpec_grows"' in xml and xml.count("<skipped") == 2
    assert main(["explore", path, "--format", "json"]) == 0
    assert [r["verdict"] for r in json.loads(capsys.readouterr().out)["properties"]] == ["holds", "holds"]


# ----------------------------------------------------------------- 12: Ctrl-C
def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def interrupt(args, cpu=2.5, sig=signal.SIGINT):
    """Run the command, send SIGINT (or ``sig``) once it has used ``cpu`` seconds of CPU (well
    into the search, however loaded the machine), return (exit code, stdout, stderr, seconds it
    took to end after the signal)."""
    proc = subprocess.Popen([sys.executable, "-m", "asmcheck", *args], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, env=ENV, text=True)
    while proc.poll() is None and cpu_seconds(proc.pid) < cpu:
        time.sleep(0.1)
    t0 = time.monotonic()
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=60)
    return proc.returncode, out, err, time.monotonic() - t0


@pytest.mark.engines("python")
def test_ctrl_c_during_explore_prints_the_partial_report(tmp_path):
    path = write(tmp_path, COUNTER.format(bound=10**9))
    code, out, err, after = interrupt(["explore", path, "--engine", "python"])
    clean(out + err)
    assert code == 3
    assert after < 3, after
    assert "  inv_small                                incomplete" in out
    assert out.endswith("incomplete: interrupted (Ctrl-C)\nverdict: incomplete\n")


@pytest.mark.parametrize("engine", ["python", "native"])
@pytest.mark.engines("native")
def test_sigterm_ends_like_ctrl_c_with_the_partial_report(tmp_path, engine):
    """SIGTERM (``timeout``, a CI runner's cancel) once ended the run with no report at all."""
    if engine == "native":
        from asmcheck.explore.native_build import compiler
        if compiler() is None:
            pytest.skip("no C compiler: the native explorer cannot run here")
    path = write(tmp_path, COUNTER.format(bound=10**9))
    code, out, err, after = interrupt(["explore", path, "--engine", engine], cpu=1.5, sig=signal.SIGTERM)
    clean(out + err)
    assert code == 3, err
    assert after < 3, after
    assert "  inv_small                                incomplete" in out
    assert out.endswith("incomplete: interrupted (SIGTERM)\nverdict: incomplete\n")


@pytest.mark.engines("python")
def test_ctrl_c_after_a_violation_exits_1_with_its_trace(tmp_path):
    path = write(tmp_path, COUNTER.format(bound=30))
    html = tmp_path / "r.html"
    code, out, err, _ = interrupt(["explore", path, "--engine", "python", "--html", str(html)])
    clean(out + err)
    assert code == 1
    assert "inv_small (Counter.asm:7:" in out and "shortest counterexample, 30 steps" in out
    assert "incomplete: interrupted (Ctrl-C)" in out and out.endswith("verdict: violated\n")
    assert html.exists() and "inv_small" in html.read_text()


@pytest.mark.engines("python")
def test_ctrl_c_during_check_writes_the_reports(tmp_path):
    path = write(tmp_path, COUNTER.format(bound=10**9))
    report = tmp_path / "gate.json"
    code, out, err, _ = interrupt(["check", path, "--engine", "python", "--json", str(report)])
    clean(out + err)
    assert code == 3
    doc = json.loads(report.read_text())
    assert doc["gate"] == "incomplete" and doc["specs"][0]["incomplete"] == "interrupted (Ctrl-C)"


# ----------------------------------------------------------------- 13: memory
@pytest.mark.engines("python")
def test_max_memory_stops_the_search_with_a_partial_report(tmp_path):
    path = write(tmp_path, COUNTER.format(bound=10**9))
    res = run_cli("explore", path, "--engine", "python", "--max-memory", "120M", "--format", "json", timeout=300)
    clean(res.stdout + res.stderr)
    assert res.returncode == 3
    doc = json.loads(res.stdout)
    assert doc["incomplete"] == "memory limit 120 MB reached" and doc["states"] > 1000


@pytest.mark.engines("native")
@pytest.mark.parametrize("engine", ["python", "native"])
@pytest.mark.parametrize("limit, text", [("1", "1 byte"), ("1000", "1,000 bytes"), ("3M", "3 MB")])
def test_a_memory_limit_below_a_megabyte_is_named_in_bytes(tmp_path, engine, limit, text):
    """--max-memory 1 said "memory limit 0 MB reached"."""
    from asmcheck.explore.native_build import compiler
    if engine == "native" and compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    path = write(tmp_path, COUNTER.format(bound=10**9))
    res = run_cli("explore", path, "--engine", engine, "--max-memory", limit, "--format", "json", timeout=300)
    assert res.returncode == 3
    assert json.loads(res.stdout)["incomplete"] == f"memory limit {text} reached"
    assert memory_text(2**20) == "1 MB" and memory_text(2**20 - 1) == "1,048,575 bytes"


@pytest.mark.engines("python")
def test_running_out_of_memory_ends_with_a_partial_report(tmp_path):
    """A hard address-space limit on the child: MemoryError is a partial report, exit 3."""
    path = write(tmp_path, COUNTER.format(bound=10**9))
    code = ("import resource, sys; resource.setrlimit(resource.RLIMIT_AS, (700 * 2**20, 700 * 2**20)); "
            "from asmcheck.cli import main; sys.exit(main(sys.argv[1:]))")
    res = subprocess.run([sys.executable, "-c", code, "explore", path, "--engine", "python", "--max-memory", "0"],
                         capture_output=True, text=True, env=ENV, timeout=600)
    clean(res.stdout + res.stderr)
    assert res.returncode == 3, res.stderr
    assert "incomplete: out of memory" in res.stdout and res.stdout.endswith("verdict: incomplete\n")


def test_max_memory_takes_sizes(capsys, tmp_path):
    path = write(tmp_path, NOPROP)
    assert main(["explore", path, "--max-memory", "lots"]) == 2
    assert "--max-memory 'lots': expected a size such as 2G" in capsys.readouterr().err


# ----------------------------------------------------------------- 16: errors on stderr, JSON on stdout
def test_input_errors_go_to_stderr_and_json_stays_json(tmp_path, capsys):
    path = write(tmp_path, NOPROP.replace("x := x + 1", "x := "))
    for cmd in (["explore"], ["bmc", "-k", "2"], ["simulate"]):
        assert main([*cmd, path]) == 2
        got = capsys.readouterr()
        assert got.out == "" and got.err.startswith(f"{path}:7:1: unexpected 'default'")
        assert main([*cmd, path, "--format", "json"]) == 2
        got = capsys.readouterr()
        err = json.loads(got.out)["error"]
        assert (err["file"], err["line"], err["col"]) == (path, 7, 1) and err["message"].startswith("unexpected")


# ----------------------------------------------------------------- 17: outputs checked before the search
@pytest.mark.engines("python")
@pytest.mark.parametrize("opt", ["--graph", "--html", "--avalla"])
def test_an_output_onto_a_folder_fails_before_the_search(tmp_path, opt):
    path = write(tmp_path, SLOW_STEP)
    folder = tmp_path / "out.dot"
    folder.mkdir()
    target = folder if opt != "--avalla" else tmp_path / "x.avalla"
    if opt == "--avalla":
        target.mkdir()
    t0 = time.monotonic()
    res = run_cli("explore", path, opt, str(target), "--engine", "python")
    assert time.monotonic() - t0 < 10          # the search would take minutes
    clean(res.stdout + res.stderr)
    assert res.returncode == 2 and res.stdout == ""
    assert res.stderr == f"asmcheck: error: {opt} {target}: is a folder; give a file name\n"


@pytest.mark.engines("python")
def test_output_into_a_missing_folder_is_created_and_said(tmp_path, capsys):
    path = write(tmp_path, COUNTER.format(bound=5))
    out = tmp_path / "new" / "deeper" / "g.dot"
    assert main(["explore", path, "--engine", "python", "--max-depth", "6", "--graph", str(out)]) == 1
    err = capsys.readouterr().err
    assert err == f"asmcheck: created the folder {out.parent} for --graph\n" and out.exists()
    assert main(["explore", path, "--graph", str(tmp_path / "g.png")]) == 2
    assert "--graph: write a .dot or .graphml file" in capsys.readouterr().err
    plain = tmp_path / "plain.txt"
    plain.write_text("")
    assert main(["check", path, "--junit", str(plain / "sub" / "x.xml")]) == 2
    assert capsys.readouterr().err == f"asmcheck: error: --junit {plain / 'sub' / 'x.xml'}: {plain} is not a folder\n"


# ----------------------------------------------------------------- 22: --graph for people
GRAPH = """asm Graph
import StandardLibrary
signature:
	enum domain Light = {RED | GREEN}
	monitored go: Boolean
	controlled light: Light
	controlled c: Integer
definitions:
	invariant inv_c over c: c < 3
	main rule r_main = if go then par light := GREEN c := (c + 1) mod 4 endpar
		else choose $l in Light with true do light := $l endif
default init s0:
	function light = RED
	function c = 0
"""


@pytest.mark.engines("python")
def test_the_graph_names_choices_marks_the_counterexample_and_is_valid_graphml(tmp_path, capsys):
    import networkx as nx
    path = write(tmp_path, GRAPH)
    dot, gml = tmp_path / "g.dot", tmp_path / "g.graphml"
    assert main(["explore", path, "--graph", str(dot)]) == 1
    text = dot.read_text()
    assert '  s0 -> s1 [label="r_main chooses $l = GREEN; reads go = false"];' in text
    assert '  s0 -> s2 [label="r_main; reads go = true", color=red, fontcolor=red, penwidth=2];' in text
    assert text.count(", color=red") == 4 + 3        # the 4 states and 3 steps to c = 3
    assert main(["explore", path, "--graph", str(gml)]) == 1
    xml = gml.read_text()
    assert '<data key="n_initial">true</data>' in xml and "True" not in xml
    ids = [line.split('"')[1] for line in xml.splitlines() if line.strip().startswith("<edge ")]
    assert len(ids) == len(set(ids)) == 24
    g = nx.read_graphml(gml)
    assert g.nodes["s0"]["initial"] is True and g.nodes["s1"]["counterexample"] is False
    capsys.readouterr()
    big = write(tmp_path, COUNTER.format(bound=10**6))
    assert main(["explore", big, "--engine", "python", "--max-depth", "600", "--graph", str(tmp_path / "b.dot")]) == 3
    assert "asmcheck: warning: the graph in " in capsys.readouterr().err


@pytest.mark.engines("python")
def test_explore_html_has_one_verdict(tmp_path, capsys):
    """The title and the rows agree: explore does not judge expectations, so an expected
    violation is a failing row under a FAIL title (the gate's check judges them)."""
    path = write(tmp_path, "// asmcheck: expect violated inv_small\n" + COUNTER.format(bound=3))
    html = tmp_path / "r.html"
    assert main(["explore", path, "--engine", "python", "--max-depth", "5", "--html", str(html)]) == 1
    text = html.read_text()
    assert "FAIL</span> (exit 1)" in text and "violated (expected)" not in text
    assert '<td><a href="#cx1">inv_small</a></td><td class="verdict">VIOLATED</td>' in text
