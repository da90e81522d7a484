"""The command line under attack: arbitrary options (hypothesis), hostile output paths and
input files, deep nesting, limits under a wall clock, Ctrl-C at any moment, memory caps.
Whatever happens, the exit code is one of 0-3 and no output holds a Traceback or an
'internal error'."""
from __future__ import annotations

import contextlib
import io
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from asmcheck.cli import main

from helpers import write

pytestmark = pytest.mark.engines("both")

ROOT = Path(__file__).resolve().parents[1]
ENV = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
ENV.pop("ASMCHECK_DEBUG", None)

SMALL = """asm Small
import StandardLibrary
signature:
	enum domain Light = {RED | GREEN}
	monitored go: Boolean
	monitored n: Integer
	controlled light: Light
	controlled c: Integer
definitions:
	invariant inv_c over c: c < 3
	main rule r_main = if go then par light := GREEN c := (c + 1) mod 4 endpar else light := RED endif
default init s0:
	function light = RED
	function c = 0
"""

COUNTER = """asm Counter
import StandardLibrary
signature:
	controlled x: Integer
definitions:
	invariant inv_pos over x: x >= 0
	main rule r_main = x := x + 1
default init s0:
	function x = 0
"""


def clean(text: str) -> None:
    assert "Traceback" not in text, text
    assert "internal error" not in text, text


def run_main(argv) -> tuple[int, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue() + err.getvalue()


# ----------------------------------------------------------------- options
NUMBERS = st.one_of(st.integers(-10**22, 10**22).map(str), st.sampled_from(["", "-", "1e9", "nan", "inf", "0x10",
                                                                             " 3", "3 ", "--", "-0"]))
RANGES = st.one_of(
    st.tuples(st.integers(-10**21, 10**21), st.integers(-10**21, 10**21)).map(lambda t: f"{t[0]}..{t[1]}"),
    st.sampled_from(["..", "1..", "..2", "a..b", "1...3", "1..2..3", "-3..3", "0..0", ""]),
    st.text(max_size=12))
MONITORED = st.one_of(
    st.tuples(st.sampled_from(["go", "n", "light", "c", "nope", "", "1x", "go go"]),
              st.one_of(RANGES, st.sampled_from(["true", "false", "true,false", "RED", "GREEN,RED", "\"s\"",
                                                 "1,2,3", ",", "true,"])))
    .map(lambda t: f"{t[0]}={t[1]}"),
    st.text(max_size=10))

OPTION = st.one_of(
    st.tuples(st.sampled_from(["--max-states", "--max-depth", "--max-seconds"]), NUMBERS),
    st.tuples(st.just("--max-memory"), st.one_of(NUMBERS, st.sampled_from(["1K", "2G", "0", "1.5M", "x"]))),
    st.tuples(st.just("--int-range"), RANGES),
    st.tuples(st.just("--monitored"), MONITORED),
    st.tuples(st.just("--engine"), st.sampled_from(["auto", "python", "native", "jit", ""])),
    st.tuples(st.just("--fair"), st.sampled_from(["all", "Light", "Nope", ""])),
    st.tuples(st.sampled_from(["--deadlock", "--no-default-properties"]), st.just(None)),
    st.tuples(st.just("--format"), st.sampled_from(["text", "json", "xml"])),
)


def flatten(opts):
    out = []
    for name, value in opts:
        out.append(name)
        if value is not None:
            out.append(value)
    return out


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.lists(OPTION, max_size=5))
def test_explore_with_any_options_ends_well(tmp_path, opts):
    path = write(tmp_path, SMALL)
    argv = ["explore", path, "--max-seconds", "20", *flatten(opts)]
    code, text = run_main(argv)
    clean(text)
    assert code in (0, 1, 2, 3), (argv, code, text)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.sampled_from(["check", "bmc", "simulate"]), st.lists(OPTION, max_size=4))
def test_other_commands_with_any_options_end_well(tmp_path, command, opts):
    path = write(tmp_path, SMALL)
    argv = [command, path, *flatten(opts)]
    if command == "bmc":
        argv = [a for a in argv if a not in ("--max-states", "--max-depth", "--engine", "--fair", "--deadlock",
                                             "--max-memory")]
        argv += ["-k", "2"]
    if command == "simulate":
        argv += ["-n", "3"]
    code, text = run_main(argv)
    clean(text)
    assert code in (0, 1, 2, 3), (argv, code, text)


# ----------------------------------------------------------------- output paths
def output_targets(tmp_path: Path) -> list[str]:
    folder = tmp_path / "folder"
    folder.mkdir(exist_ok=True)
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    return [str(folder), str(plain / "below.dot"), "/dev/full", "/dev/null", "/proc/self/status",
            str(tmp_path / "new" / "g.dot"), str(tmp_path / "a.graphml"), str(tmp_path / "x.html"),
            str(tmp_path / ".."), ""]


@pytest.mark.parametrize("opt", ["--graph", "--html", "--avalla"])
def test_explore_outputs_anywhere_end_well(tmp_path, opt, monkeypatch):
    monkeypatch.chdir(tmp_path)     # an empty target means the working folder: keep it out of the checkout
    path = write(tmp_path, SMALL)
    for target in output_targets(tmp_path):
        code, text = run_main(["explore", path, "--monitored", "n=0", opt, target])
        clean(text)
        assert code in (0, 1, 2), (target, code, text)


@pytest.mark.parametrize("opt", ["--junit", "--sarif", "--json", "--html", "--avalla"])
def test_check_outputs_anywhere_end_well(tmp_path, opt, monkeypatch):
    monkeypatch.chdir(tmp_path)     # an empty target means the working folder: keep it out of the checkout
    path = write(tmp_path, SMALL)
    for target in output_targets(tmp_path):
        code, text = run_main(["check", path, "--monitored", "n=0", opt, target])
        clean(text)
        assert code in (1, 2), (target, code, text)


# ----------------------------------------------------------------- input files
def hostile_inputs(tmp_path: Path) -> list[str]:
    fifo = tmp_path / "fifo.asm"
    if not fifo.exists():
        os.mkfifo(fifo)
    env = tmp_path / "env.asm"
    if not env.exists():
        env.symlink_to("/proc/self/environ")
    binary = tmp_path / "bin.asm"
    binary.write_bytes(bytes(range(256)) * 4)
    empty = tmp_path / "empty.asm"
    empty.write_text("")
    dangling = tmp_path / "dangling.asm"
    if not dangling.is_symlink():
        dangling.symlink_to(tmp_path / "nowhere.asm")
    return [str(fifo), str(env), str(binary), str(empty), str(dangling), str(tmp_path), "/dev/null", "/dev/zero",
            "/etc/passwd", str(tmp_path / "missing.asm"), "-"]


@pytest.mark.parametrize("command", ["parse", "explore", "check", "simulate", "bmc"])
def test_hostile_input_files_end_well(tmp_path, command):
    for target in hostile_inputs(tmp_path):
        t0 = time.monotonic()
        code, text = run_main([command, target])
        clean(text)
        ok = {2}
        if target.endswith("empty.asm") and command == "parse":
            ok = {0}                             # an empty file is no error for the parser
        if target == str(tmp_path) and command == "check":
            ok = {0, 1, 2}                       # a folder is what check walks
        assert code in ok, (target, code, text)
        assert time.monotonic() - t0 < 30        # a fifo or /dev/zero is never read


def test_conform_and_scenario_with_hostile_files_end_well(tmp_path):
    path = write(tmp_path, SMALL)
    for target in hostile_inputs(tmp_path):
        for argv in (["conform", path, target], ["scenario", target], ["simulate", path, "--input", target]):
            code, text = run_main(argv)
            clean(text)
            # an input file with no usable line leaves the monitored values to the simulator
            assert code in ((0, 1, 2) if argv[0] == "simulate" else (1, 2)), (argv, code, text)


# ----------------------------------------------------------------- deep nesting
@pytest.mark.parametrize("depth", [200, 800])
def test_deeply_nested_specs_end_well(tmp_path, depth):
    body = "x := 1"
    for i in range(depth):
        body = f"if x = {i} then {body} endif"
    text = ("asm Deep\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
            f"\tmain rule r_main = {body}\ndefault init s0:\n\tfunction x = 0\n")
    path = write(tmp_path, text)
    code, out = run_main(["explore", path, "--max-seconds", "30"])
    clean(out)
    assert code in (0, 2, 3), out


# ----------------------------------------------------------------- limits under a wall clock
@pytest.mark.engines("python")
@pytest.mark.parametrize("limit", ["1", "2.5"])
def test_time_limits_hold_under_a_wall_clock(tmp_path, limit):
    path = write(tmp_path, COUNTER)
    t0 = time.monotonic()
    res = subprocess.run([sys.executable, "-m", "asmcheck", "explore", path, "--engine", "python",
                          "--max-seconds", limit], capture_output=True, text=True, env=ENV, timeout=120)
    wall = time.monotonic() - t0
    clean(res.stdout + res.stderr)
    assert res.returncode == 3 and f"incomplete: time limit {float(limit)} s reached" in res.stdout
    assert wall < float(limit) + 4, wall


# ----------------------------------------------------------------- Ctrl-C at any moment
def sigint_default() -> None:
    """(In the child, before the program:) Ctrl-C as a terminal's foreground program has it,
    whatever this process has (a test run started in the background ignores it, and so would
    the program, as it should)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


@pytest.mark.engines("python")
@pytest.mark.parametrize("cpu", [0.0, 0.3, 1.0, 2.0])
@pytest.mark.parametrize("command", ["explore", "check"])
def test_sigint_at_any_moment_ends_well(tmp_path, command, cpu):
    path = write(tmp_path, COUNTER)
    argv = [sys.executable, "-m", "asmcheck", command, path, "--engine", "python"]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV,
                            preexec_fn=sigint_default)
    try:
        while proc.poll() is None and cpu_seconds(proc.pid) < cpu:
            time.sleep(0.05)
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:     # (the counter never stops: a run the signal missed is ended here)
            proc.kill()
            proc.communicate()
    if proc.returncode == 1 and err.startswith(INTERPRETER_START):
        # the signal came while the interpreter ran the site packages' .pth lines, before any
        # line of the program (its own report, which the program cannot replace)
        assert cpu == 0.0 and out == ""
        return
    clean(out + err)
    if proc.returncode == -signal.SIGINT:
        # the signal came before the interpreter had set up its handler: killed, silently
        assert cpu == 0.0 and out == "" and err == ""
    else:
        assert proc.returncode == 3, (out, err)
        assert out or err in ("asmcheck: interrupted before any result\n", "")


# the interpreter's own report of a Ctrl-C while it imports the site module (before the program)
INTERPRETER_START = "Fatal Python error: init_import_site: Failed to import the site module\n"



# ----------------------------------------------------------------- memory caps
def capped(limit_mb: int):
    def pre():
        resource.setrlimit(resource.RLIMIT_AS, (limit_mb * 2**20, limit_mb * 2**20))
    return pre


@pytest.mark.engines("python")
@pytest.mark.parametrize("limit_mb", [600, 800])
def test_memory_caps_end_well(tmp_path, limit_mb):
    path = write(tmp_path, COUNTER)
    res = subprocess.run([sys.executable, "-m", "asmcheck", "explore", path, "--engine", "python",
                          "--max-seconds", "60"], capture_output=True, text=True, env=ENV, timeout=300,
                         preexec_fn=capped(limit_mb))
    clean(res.stdout + res.stderr)
    assert res.returncode == 3, res.stderr
    assert "incomplete: " in res.stdout or "out of memory" in res.stderr


@pytest.mark.engines("python")
@pytest.mark.parametrize("limit_mb", [260, 300, 340])
def test_a_small_memory_cap_leaves_room_for_a_small_search(limit_mb):
    """The deep-call stack is sized to the room under an address-space cap: at 300 MB it once
    took 256 MB of it, and a 267-state search ended 'out of memory' where 250 MB sufficed."""
    res = subprocess.run([sys.executable, "-m", "asmcheck", "explore", str(ROOT / "specs" / "sb_sync_slave.asm"),
                          "--engine", "python", "--format", "json"], capture_output=True, text=True, env=ENV,
                         timeout=300, preexec_fn=capped(limit_mb))
    clean(res.stdout + res.stderr)
    assert res.returncode == 0, res.stderr
    import json
    assert json.loads(res.stdout)["states"] == 267


@pytest.mark.engines("python")
def test_deep_nesting_under_a_memory_cap(tmp_path):
    """800 nested ifs resolve under a 300 MB cap (a smaller stack, a recursion limit to match)."""
    body = "x := 0"
    for i in range(800):
        body = f"if x = {i % 7} then {body} endif"
    path = write(tmp_path, "asm Ifs\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
                           f"\tmain rule r_main = {body}\ndefault init s0:\n\tfunction x = 0\n")
    res = subprocess.run([sys.executable, "-m", "asmcheck", "explore", path, "--engine", "python"],
                         capture_output=True, text=True, env=ENV, timeout=300, preexec_fn=capped(300))
    clean(res.stdout + res.stderr)
    assert res.returncode == 0, res.stderr
    assert "2 states" in res.stdout or "1 state" in res.stdout, res.stdout


@pytest.mark.engines("python")
def test_a_time_bound_beyond_the_platform_timer_ends_well(tmp_path):
    """--max-seconds 9223372036 once stopped with an internal error (the alarm's timer overflowed)."""
    path = write(tmp_path, COUNTER)
    code, out = run_main(["explore", path, "--engine", "python", "--max-seconds", "9223372036", "--max-states", "50"])
    clean(out)
    assert code == 3
    assert out.endswith("incomplete: state limit 50 reached\nverdict: incomplete\n"), out


@pytest.mark.engines("python")
def test_a_program_started_with_ctrl_c_ignored_keeps_ignoring_it(tmp_path):
    """As `nohup` and a script's `cmd &` start it: a Ctrl-C to the terminal's programs does not end
    it (SIGTERM still does, with the partial report)."""
    path = write(tmp_path, COUNTER)
    argv = [sys.executable, "-m", "asmcheck", "explore", path, "--engine", "python"]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN))
    try:
        for moment in (0.0, 0.5, 1.5):            # the start-up, the imports, the search
            while proc.poll() is None and cpu_seconds(proc.pid) < moment:
                time.sleep(0.02)
            proc.send_signal(signal.SIGINT)
        time.sleep(0.5)
        assert proc.poll() is None
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()
    clean(out + err)
    assert proc.returncode == 3 and "interrupted (SIGTERM)" in out, (out, err)
