"""The native engine against the Python engine (the reference) over the ASMETA corpus, specs/
and tests/rtpattern: for every spec the Python explorer finishes within the bound below, the
native engine must give the same states, transitions, depth, verdicts and shortest traces (the
whole ``explore --format json`` report but the timings and the engine name).  Specs the native
engine refuses are listed with its reason; the share that runs native may only go up.

Engines: both (python is the reference, native is checked)."""
from __future__ import annotations

import contextlib
import io
import json
import signal
import sys
import time
from pathlib import Path

import pytest

from asmcheck.cli import main

from conftest import ASMETA, ROOT

pytestmark = [pytest.mark.slow, pytest.mark.corpus]

MAX_STATES = 3000         # a spec that needs more is outside the comparison
MAX_SECONDS = 2           # the Python explorer's time bound per spec (a hard stop 3 s later)
# the share of the compared specs that ran native when this test was last tuned: it may only go up
MIN_NATIVE_SHARE = 0.0
IGNORED_KEYS = ("seconds", "engine", "compile_seconds", "engine_reason")


def corpus() -> list[Path]:
    out = []
    manifest = ASMETA / "MANIFEST.tsv"
    if manifest.exists():
        for line in manifest.read_text().splitlines()[1:]:
            path, verdict = line.split("\t")[:2]
            if verdict == "accepts":
                out.append(ASMETA / path)
    for folder in ("specs", "specs/buggy", "specs/temporal", "tests/rtpattern"):
        out += sorted((ROOT / folder).glob("*.asm"))
    return out


class _Stop(BaseException):      # not an Exception: the CLI's error handler must not catch it
    pass


def _alarm(signum, frame):
    raise _Stop()


def run_cli(args: list[str], hard_stop: float) -> tuple[int | None, str, str]:
    """``asmcheck ARGS`` in this process: (exit code or None when stopped, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, hard_stop)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(args)
    except _Stop:
        code = None
    except RecursionError:
        code = None
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    return code, out.getvalue(), err.getvalue()


def extra_args(path: Path) -> list[str]:
    if path.parent == ROOT / "tests" / "rtpattern":
        return ["-I", str(ASMETA / "asm_examples")]
    return []


def _strip(report: dict) -> dict:
    return {k: v for k, v in report.items() if k not in IGNORED_KEYS}


def compare(path: Path) -> tuple[str, str]:
    """(outcome, detail): outcome is 'skip' (the Python explorer does not finish within the
    bound, or refuses the spec), 'native' (same report), 'refused' (the native engine refuses
    it; detail is its reason) or 'differs' (detail says how)."""
    base = ["explore", str(path), "--format", "json", "--max-states", str(MAX_STATES), *extra_args(path)]
    code, out, err = run_cli(base + ["--engine", "python", "--max-seconds", str(MAX_SECONDS)], MAX_SECONDS + 3)
    if code is None:
        return "skip", "the Python explorer did not stop in time"
    if code not in (0, 1, 3):
        why = (err.strip().splitlines() or ["?"])[0]
        return "skip", f"Python explorer: exit {code}: {why[:160]}"
    py = json.loads(out)
    if py.get("reason") or py["verdict"] == "incomplete":
        return "skip", f"Python explorer: {py.get('reason') or 'incomplete'}"
    code_n, out_n, err_n = run_cli(base + ["--engine", "native"], 4 * MAX_SECONDS + 30)
    if code_n is None:
        return "differs", "the native engine did not stop in time"
    if code_n == 2 and "the native explorer cannot run" in err_n:
        line = next(ln for ln in err_n.splitlines() if "the native explorer cannot run" in ln)
        return "refused", line.split(f"cannot run {path.name}: ", 1)[-1]
    if code_n != code:
        return "differs", f"exit code {code_n} (python {code}): {err_n.strip()[-300:]}"
    nat = json.loads(out_n)
    if _strip(nat) != _strip(py):
        keys = sorted(k for k in set(py) | set(nat) if k not in IGNORED_KEYS and py.get(k) != nat.get(k))
        return "differs", "different " + ", ".join(keys) + \
            f" (python {py['states']}/{py['transitions']}, native {nat['states']}/{nat['transitions']})"
    return "native", f"{py['states']} states"


def survey(paths=None, log=None) -> dict[str, tuple[str, str]]:
    results = {}
    for p in paths or corpus():
        try:
            rel = str(p.relative_to(ASMETA))
        except ValueError:
            rel = str(p.relative_to(ROOT))
        t0 = time.perf_counter()
        results[rel] = compare(p)
        if log is not None:
            print(f"{results[rel][0]:8} {time.perf_counter() - t0:5.1f}s {rel}: {results[rel][1]}", file=log,
                  flush=True)
    return results


def summary(results: dict) -> tuple[float, str]:
    compared = {k: v for k, v in results.items() if v[0] != "skip"}
    native = [k for k, v in compared.items() if v[0] == "native"]
    share = len(native) / len(compared) if compared else 1.0
    lines = [f"native engine: {len(native)} of {len(compared)} specs the Python explorer finishes "
             f"({100 * share:.1f} %); {len(results) - len(compared)} specs outside the bound"]
    reasons: dict = {}
    for k, (o, d) in sorted(compared.items()):
        if o != "native":
            reasons.setdefault(f"{o}: {d}", []).append(k)
    for why, specs in sorted(reasons.items(), key=lambda x: (-len(x[1]), x[0])):
        lines.append(f"  {len(specs):3}  {why}")
        for s in specs:
            lines.append(f"         {s}")
    return share, "\n".join(lines)


def test_native_engine_matches_the_python_engine():
    if not (ASMETA / "MANIFEST.tsv").exists():
        pytest.skip(f"the ASMETA corpus is not at {ASMETA} (set ASMCHECK_SHARED to the shared folder)")
    from asmcheck.explore.native_build import compiler
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    results = survey()
    share, text = summary(results)
    print(text)
    differs = {k: d for k, (o, d) in results.items() if o == "differs"}
    assert differs == {}
    assert share >= MIN_NATIVE_SHARE, text


if __name__ == "__main__":
    # python tests/test_native_diff.py [SPEC ...]: the survey with one line per spec
    sys.path.insert(0, str(Path(__file__).parent))
    res = survey([Path(a).resolve() for a in sys.argv[1:]] or None, log=sys.stdout)
    print(summary(res)[1])
