#!/usr/bin/env python3
"""Regenerate docs/rtpattern-audit.md: the audit of the authors' RTPatternLibrary.

    python scripts/rtpattern_audit.py [--shared ../shared] [--out docs/rtpattern-audit.md]
                                      [--jobs 2] [--only NAME ...] [--no-coverage]

Explores every application of the library (ASMETA's asm_examples/RTPatternLibrary, read in
place from the shared folder: nothing of it is copied or modified) and the
nondeterministic-scheduling specs of tests/rtpattern/ with the property files
properties/rtpattern*.prop, each with ``asmcheck explore`` in a subprocess (the command that the
report names for it), parses what asmcheck prints (states, transitions, depth, seconds, the
verdict of every property, the shortest trace of every violation) and writes the report, with the
judgement of every violation recorded below in JUDGEMENTS.

The specs in tests/rtpattern/ import the library as ``RTPatternLibrary/...``, found through the
folder given at run time with ``-I`` (the shared folder's asmeta/asm_examples), so --shared can point
anywhere and nothing is copied.
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
LIB_REL = Path("asmeta") / "asm_examples" / "RTPatternLibrary"
NONDET_DIR = ROOT / "tests" / "rtpattern"

PROPS_SB = ["properties/rtpattern.prop", "properties/rtpattern_semaphore.prop"]
PROPS_SEM = ["properties/rtpattern_semaphore.prop", "properties/rtpattern_semtest.prop"]
PROPS_NONDET = PROPS_SB + ["properties/rtpattern_nondet.prop"]
PROPS_COVERAGE = ["properties/rtpattern_coverage.prop"]

# Test_Sem_Async / Test_Sem_Sync count their steps in an unbounded Integer (indexCycle): their
# state spaces are infinite, so they are explored to this depth. Their behaviour depends on
# indexCycle only through indexCycle mod 3 (Async) and mod 5, 6, 7 (Sync, period 210), so 1000
# steps run every residue several times.
SEM_DEPTH = 1000


@dataclass
class Run:
    key: str                 # unique, e.g. "VisualServoing/free"
    spec: str                # asm name
    path: str                # library-relative path, or "nondet:NAME"
    props: list
    extra: list = field(default_factory=list)
    passed: str = "free"     # "free", "true" or "-" (no monitored passed)
    bound: str = ""          # human description of the bound, "" = to completion
    coverage: bool = False   # a coverage run (properties/rtpattern_coverage.prop)


def runs_list(coverage: bool = True) -> list[Run]:
    out = []
    for app in ("VisualServoing", "RobotController", "CompleteApplication", "Test_SB"):
        p = f"Application/{app}.asm"
        out.append(Run(f"{app}/free", app, p, PROPS_SB))
        out.append(Run(f"{app}/true", app, p, PROPS_SB, ["--monitored", "passed=true"], passed="true"))
    for t in ("Test_Sem_Async", "Test_Sem_Sync"):
        p = f"Test/{t}.asm"
        out.append(Run(f"{t}/free", t, p, PROPS_SEM, ["--max-depth", str(SEM_DEPTH)],
                       bound=f"--max-depth {SEM_DEPTH}"))
        out.append(Run(f"{t}/true", t, p, PROPS_SEM, ["--monitored", "passed=true", "--max-depth", str(SEM_DEPTH)],
                       passed="true", bound=f"--max-depth {SEM_DEPTH}"))
    for nd in ("RtNondetVS", "RtNondetPairs"):
        out.append(Run(f"{nd}/nondet", nd, f"nondet:{nd}", PROPS_NONDET, ["--deadlock"], passed="-"))
    if coverage:
        for app in ("VisualServoing", "RobotController", "CompleteApplication", "Test_SB"):
            out.append(Run(f"{app}/coverage", app, f"Application/{app}.asm", PROPS_COVERAGE,
                           ["--monitored", "passed=true"], passed="true", coverage=True))
        for nd in ("RtNondetVS", "RtNondetPairs"):
            out.append(Run(f"{nd}/coverage", nd, f"nondet:{nd}", PROPS_COVERAGE, passed="-", coverage=True))
    return out


# ------------------------------------------------------------------ judgements of the violations
# (spec, property) -> (classification, explanation). A violation without an entry is reported as a
# NEW finding that still needs a judgement.
JUDGEMENTS = {
    ("Test_Sem_Sync", "inv_single_sem_mutex"): (
        "defect of the test spec Test_Sem_Sync (not of Semaphore.asm as the applications use it)",
        "When indexCycle is a multiple of both 5 and 7 (35, 70, ...) the main rule's `par` runs "
        "`r_sem_trywait` twice in the same step: for a READY task (the `mod 5` branch) and for a WAITING one "
        "(the `mod 7` branch). Both read `semacount(sem) = 1` in the same state, both update it to 0 "
        "(a consistent update, legal in ASMETA too) and both tasks go to EXECUTION: two holders of a binary "
        "semaphore. `r_sem_trywait`/`r_sem_wait`/`r_sem_post` are correct only when at most one of them runs "
        "per semaphore per step (or in `seq`), which the applications respect (their schedulers run in "
        "`seq`), but Semaphore.asm does not say so and its own test breaks it. The same `par` composes a "
        "`r_sem_post` with a `r_sem_trywait` at multiples of 30 (mod 5 and mod 6): there the trywait reads "
        "the count before the post and its task goes WAITING although the semaphore is free after the step."),
    ("Test_Sem_Sync", "inv_single_sem_count"): (
        "defect of the test spec Test_Sem_Sync (consequence of the double grant)",
        "Same cause as inv_single_sem_mutex: after the double grant at indexCycle = 35 the count (0) no longer "
        "matches the holders (two), and the next `r_sem_post` (at a multiple of 6) sets the count back to 1 "
        "while the other task still holds the semaphore."),
    ("RtNondetVS", "stp_swap_publishes_latest"): (
        "defect of the library (swinging-buffer freshness), hidden in the applications by their timing",
        "The VS task (asynchronous MASTER reader of cam2Vs) swaps the arrays every time it reads, once "
        "`sb_firstWrite` is true, whether or not the camera has written since its previous swap: "
        "`r_SwingingBuffer_updateIndexes` has no \"new data\" flag (`indexUpdated` only records that this "
        "MANAGING_SB phase already swapped), and the library's `trigger` is constantly true for an "
        "ASYNCHRONOUS task, so the \"data-driven\" VS does not wait for new data either. In the trace the "
        "camera writes once (array 0), the VS swaps and reads it, runs a whole cycle while the camera does not "
        "move, and swaps again: the read array is now array 1, which was never written (the VS then reads "
        "undef although valid data exists); in the steady state the second swap hands the reader the *older* "
        "array, data older than what it has already read. This is not one of the paper's three properties, "
        "and the applications never show it because of their fixed timing (the camera's period, 10 ms, is "
        "shorter than the VS's cycle, 12.3 ms or more, so the camera always writes between two swaps); any "
        "schedule where the master reader runs faster than its slave writer shows it."),
}


# ------------------------------------------------------------------ running asmcheck
def lib_dir(shared: Path) -> Path:
    return shared / LIB_REL


def spec_file(run: Run, shared: Path) -> Path:
    if run.path.startswith("nondet:"):
        return NONDET_DIR / f"{run.path.split(':', 1)[1]}.asm"
    return lib_dir(shared) / run.path


def import_args(run: Run, shared: Path, relative: bool) -> list:
    """-I DIR for the specs of tests/rtpattern, which import RTPatternLibrary/... from there."""
    if not run.path.startswith("nondet:"):
        return []
    d = lib_dir(shared).parent
    return ["-I", os.path.relpath(d, ROOT) if relative else str(d)]


def shown_command(run: Run, shared: Path) -> str:
    """The command, relative to the project root, that reproduces the run."""
    if run.path.startswith("nondet:"):
        spec = f"tests/rtpattern/{run.path.split(':', 1)[1]}.asm"
    else:
        spec = os.path.relpath(lib_dir(shared) / run.path, ROOT)
    args = ["python", "-m", "asmcheck", "explore", spec, *import_args(run, shared, True), "--no-default-properties"]
    for p in run.props:
        args += ["--properties", p]
    args += run.extra
    return " ".join(args)


def explore(run: Run, shared: Path, timeout: float | None) -> dict:
    spec = spec_file(run, shared)
    cmd = [sys.executable, "-m", "asmcheck", "explore", str(spec), *import_args(run, shared, False),
           "--no-default-properties"]
    for p in run.props:
        cmd += ["--properties", str(ROOT / p)]
    cmd += run.extra
    env = dict(os.environ, NO_COLOR="1", PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    t0 = time.perf_counter()
    try:
        cp = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
        out, err, code = cp.stdout, cp.stderr, cp.returncode
    except subprocess.TimeoutExpired as e:
        out = e.stdout.decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
        err, code = f"timed out after {timeout} s", -1
    res = parse_output(out)
    res.update(run=run, exit=code, stderr=err.strip(), wall=time.perf_counter() - t0)
    return res


HEAD_RE = re.compile(r"^(\S+\.asm): ([\d,]+) states, ([\d,]+) transitions, depth (\d+), ([\d.]+) s(?:, (\w+) engine)?$")
ROW_RE = re.compile(r"^  (\S+)\s+(holds|violated|incomplete)$")
VIOL_RE = re.compile(r"^(\S+)(?: \(([^)]*)\))? is violated.*shortest trace, (\d+) steps?")


def parse_output(text: str) -> dict:
    lines = text.splitlines()
    res = {"states": None, "transitions": None, "depth": None, "seconds": None, "rows": {}, "traces": {},
           "trace_steps": {}, "incomplete": "", "verdict": None, "raw": text}
    i = 0
    cur = None
    buf: list = []

    def close():
        if cur is not None:
            while buf and not buf[-1].strip():
                buf.pop()
            res["traces"][cur] = "\n".join(buf)

    for ln in lines:
        m = HEAD_RE.match(ln)
        if m and res["states"] is None:
            res["states"] = int(m.group(2).replace(",", ""))
            res["transitions"] = int(m.group(3).replace(",", ""))
            res["depth"] = int(m.group(4))
            res["seconds"] = float(m.group(5))
            continue
        if cur is None:
            m = ROW_RE.match(ln)
            if m:
                res["rows"][m.group(1)] = m.group(2)
                continue
        m = VIOL_RE.match(ln)
        if m:
            close()
            cur = m.group(1)
            res["trace_steps"][cur] = int(m.group(3))
            buf = [ln]
            continue
        if ln.startswith("incomplete: "):
            close()
            cur = None
            res["incomplete"] = ln[len("incomplete: "):]
            continue
        if ln.startswith("verdict: "):
            close()
            cur = None
            res["verdict"] = ln[len("verdict: "):].strip()
            continue
        if cur is not None:
            buf.append(ln)
        i += 1
    close()
    return res


def bounded(res: dict) -> str:
    """Why the run did not cover the whole state space ('' if it did)."""
    run = res["run"]
    if res["incomplete"]:
        return res["incomplete"]
    ex = run.extra
    if "--max-depth" in ex and res["depth"] is not None and res["depth"] >= int(ex[ex.index("--max-depth") + 1]):
        return f"depth limit {ex[ex.index('--max-depth') + 1]} reached"
    if "--max-states" in ex and res["states"] is not None and res["states"] >= int(ex[ex.index("--max-states") + 1]):
        return f"state limit {ex[ex.index('--max-states') + 1]} reached"
    return ""


def verdict_of(res: dict, prop: str) -> str:
    v = res["rows"].get(prop)
    if v is None:
        return "?"
    if v in ("holds", "incomplete") and bounded(res):
        return "not violated within the bound"
    return v


# ------------------------------------------------------------------ the report
def fmt_int(n) -> str:
    return "?" if n is None else f"{n:,}"


def md_escape(s: str) -> str:
    return s.replace("|", "\\|")


PAPER_PROPS = {
    "(1) no concurrent write/read on one array": ("inv_no_concurrent_rw", "inv_no_concurrent_rw_data",
                                                  "stp_indexes_stable_during_access"),
    "(2) semaphore released on exit": ("stp_exit_releases_semaphore",),
    "(3) slave non-interference": ("stp_slave_never_moves_indexes", "stp_slave_never_moves_indexes_exact"),
}


def summary(main: list[dict], w) -> None:
    """The findings in a few lines: the paper's properties per spec, then every violation's judgement."""
    w("## Summary")
    w("")
    specs: list = []
    for r in main:
        if r["run"].spec not in specs:
            specs.append(r["run"].spec)
    w("| spec | runs | " + " | ".join(PAPER_PROPS) + " | other violations |")
    w("|---|---|" + "---|" * len(PAPER_PROPS) + "---|")
    for sp in specs:
        rs = [r for r in main if r["run"].spec == sp]
        runs = ", ".join(f"{r['run'].passed if r['run'].passed != '-' else 'nondet'}: {fmt_int(r['states'])} states"
                         + (" (bounded)" if bounded(r) else "") for r in rs)
        cells = []
        for props in PAPER_PROPS.values():
            vs = {verdict_of(r, p) for r in rs for p in props if p in r["rows"]}
            if not vs:
                cells.append("n/a")
            elif "violated" in vs:
                cells.append("**violated**")
            elif vs == {"holds"}:
                cells.append("holds")
            else:
                cells.append("holds (bounded)")
        paper = {p for props in PAPER_PROPS.values() for p in props}
        other = sorted({p for r in rs for p, v in r["rows"].items() if v == "violated" and p not in paper})
        w(f"| {sp} | {runs} | " + " | ".join(cells) + " | " + (", ".join(f"`{p}`" for p in other) or "none") + " |")
    w("")
    found = []
    for r in main:
        for p, v in r["rows"].items():
            if v == "violated" and (r["run"].spec, p) not in [(a, b) for a, b, _ in found]:
                cls = JUDGEMENTS.get((r["run"].spec, p), ("NEW FINDING: no judgement yet", ""))[0]
                found.append((r["run"].spec, p, cls))
    if found:
        w("Violations found, with the judgement given under \"Violations\" below:")
        w("")
        for sp, p, cls in found:
            w(f"- `{p}` in {sp}: {cls}.")
        w("")


def write_report(results: list[dict], shared: Path, out: Path, extra: dict) -> None:
    main = [r for r in results if not r["run"].coverage]
    cov = [r for r in results if r["run"].coverage]
    L: list[str] = []
    w = L.append
    w("# Audit of the authors' RTPatternLibrary against the paper's three properties")
    w("")
    w("Generated by `python scripts/rtpattern_audit.py`; do not edit by hand. Every number and "
      "verdict below comes from the `asmcheck explore` command printed next to it (run from the project root, "
      f"with the shared folder at `{os.path.relpath(shared, ROOT)}`); the seconds are asmcheck's own timing "
      "on the machine that generated the report and vary from run to run.")
    w("")
    w("The library (`asm_examples/RTPatternLibrary`: CommonBehaviour/Scheduler.asm, Task.asm, "
      "CommonDefinitions.asm, Pattern/SwingingBuffer.asm, Semaphore.asm, and the applications) is read in "
      "place and never modified. `passed` (the applications' monitored \"while\" flag) is a free Boolean "
      "input in the runs marked *free* and fixed to true in those marked *true*; fresh `DataStream` elements "
      "made by `extend` are canonicalised and dropped when unreferenced.")
    w("")
    summary(main, w)
    w("## Properties")
    w("")
    w("In the library's vocabulary (`sb_ctrlState`, `syncPriority`, `action`, `sharedMemory`, `indexRead`/"
      "`indexWrite`/`indexUpdated`, `semacount`/`semaq`, `task_currState`); the files explain each one.")
    w("")
    w("| property | file | what it says |")
    w("|---|---|---|")
    for name, f, what in PROPERTY_TABLE:
        w(f"| `{name}` | {f} | {what} |")
    w("")
    w("Tasks are not ASM agents in the library (every application's main rule runs the schedulers in a fixed "
      "`seq`, all with the one `self` of the main rule: `updatedBy(self, loc)` holds for every update and "
      "`updatedBy(task, loc)` for none), so `updatedBy` cannot say which task moved the indexes. "
      "`stp_slave_never_moves_indexes` attributes an index update by the state instead: after a swap some "
      "scheduler's current phase is a MASTER phase on that buffer in MANAGING_SB with its task in EXECUTION "
      "and `indexUpdated` set, and the indexes moved exactly one array on; a release is explained by such a "
      "master leaving MANAGING_SB. In the nondeterministic specs exactly one scheduler runs per step and "
      "`r_scheduler_execute` always updates its `scheduler_currentScheduleTime`, which gives the exact "
      "attribution of `stp_slave_never_moves_indexes_exact` (checked sound by `stp_one_scheduler_per_step`).")
    w("")
    w("## Results")
    w("")
    w("| spec | passed | states | transitions | depth | seconds | bound | violated |")
    w("|---|---|---|---|---|---|---|---|")
    for r in main:
        run = r["run"]
        bad = [p for p, v in r["rows"].items() if v == "violated"]
        w(f"| {run.spec} | {run.passed} | {fmt_int(r['states'])} | {fmt_int(r['transitions'])} | "
          f"{fmt_int(r['depth'])} | {r['seconds'] if r['seconds'] is not None else '?'} | "
          f"{md_escape(bounded(r)) or 'none (complete)'} | {', '.join(f'`{p}`' for p in bad) or 'none'} |")
    w("")
    w("Commands (from the project root):")
    w("")
    for r in main:
        w(f"- {r['run'].spec} ({r['run'].passed}): `{shown_command(r['run'], shared)}`"
          + (f" -- exit {r['exit']}" if r["exit"] not in (0, 1, 3) else ""))
        if r["stderr"] and r["exit"] not in (0, 1, 3):
            w(f"  - error: `{md_escape(r['stderr'].splitlines()[-1])}`")
    w("")
    w("The specs in tests/rtpattern/ import the library as `RTPatternLibrary/...`; `-I` names the folder "
      "that holds it, so the library is read in place, unmodified.")
    w("")
    w("### Verdict per property")
    w("")
    specs: list = []
    for r in main:
        if r["run"].spec not in specs:
            specs.append(r["run"].spec)
    order = [name for name, _, _ in PROPERTY_TABLE]
    props = [p for p in order if any(p in r["rows"] for r in main)]
    for r in main:
        for p in r["rows"]:
            if p not in props:
                props.append(p)
    abbrev = {"holds": "holds", "violated": "**violated**", "not violated within the bound": "holds (bounded)"}
    w("| property | " + " | ".join(specs) + " |")
    w("|---|" + "---|" * len(specs))
    for p in props:
        cells = []
        for sp in specs:
            rs = [r for r in main if r["run"].spec == sp and p in r["rows"]]
            vs = [abbrev.get(verdict_of(r, p), verdict_of(r, p)) for r in rs]
            if not vs:
                cells.append("")
            elif len(set(vs)) == 1:
                cells.append(vs[0])
            else:
                cells.append("; ".join(f"{r['run'].passed}: {v}" for r, v in zip(rs, vs)))
        w(f"| `{p}` | " + " | ".join(cells) + " |")
    w("")
    w("A cell holds the verdict of every run of that spec (passed free and true) when they agree; empty: the "
      "property does not apply to the spec.")
    w("")
    w("*holds (bounded)*: the run stopped at the bound given for it, and the property was not "
      "violated in the states explored up to there.")
    w("")
    if cov:
        w("### Coverage: do the properties hold for a reason?")
        w("")
        w("Each witness of properties/rtpattern_coverage.prop says a situation never happens; \"reached at d\" "
          "means asmcheck found it, at depth d (the shortest way), so the properties whose antecedent it is "
          "are not vacuous there. `passed` is true in these runs.")
        w("")
        cprops = []
        for r in cov:
            for p in r["rows"]:
                if p not in cprops:
                    cprops.append(p)
        w("| witness | " + " | ".join(r["run"].spec for r in cov) + " |")
        w("|---|" + "---|" * len(cov))
        for p in cprops:
            cells = []
            for r in cov:
                v = r["rows"].get(p)
                if v == "violated":
                    cells.append(f"reached at {r['trace_steps'].get(p, '?')}")
                elif v == "holds":
                    cells.append("never" + (" (bounded)" if bounded(r) else ""))
                else:
                    cells.append("n/a" if v is None else v)
            w(f"| `{p}` | " + " | ".join(cells) + " |")
        w("")
        for r in cov:
            w(f"- {r['run'].spec}: `{shown_command(r['run'], shared)}` ({fmt_int(r['states'])} states, "
              f"{r['seconds']} s)")
        w("")
    w("## `passed` fixed to true, and ASMETA's 15,708 states")
    w("")
    for line in extra.get("passed_notes", []):
        w(line)
    w("")
    w("## Violations")
    w("")
    any_v = False
    for r in main:
        for p, v in r["rows"].items():
            if v != "violated":
                continue
            any_v = True
            run = r["run"]
            cls, why = JUDGEMENTS.get((run.spec, p), ("NEW FINDING: no judgement recorded yet",
                                                     "scripts/rtpattern_audit.py has no judgement for this "
                                                     "violation; look at the trace."))
            w(f"### `{p}` in {run.spec} ({'passed ' + run.passed if run.passed != '-' else 'nondeterministic scheduling'})")
            w("")
            w(f"- Command: `{shown_command(run, shared)}`")
            w(f"- Judgement: **{cls}**.")
            w(f"- {why}")
            w("")
            tr = r["traces"].get(p, "")
            n = tr.count("\n") + 1
            w("Shortest trace, as asmcheck prints it:")
            w("")
            w("```")
            if n > TRACE_LINES_MAX:
                keep = tr.splitlines()
                w("\n".join(keep[:TRACE_LINES_MAX // 2]))
                w(f"  ... {n - TRACE_LINES_MAX} lines left out (run the command for the whole trace) ...")
                w("\n".join(keep[-TRACE_LINES_MAX // 2:]))
            else:
                w(tr)
            w("```")
            w("")
    if not any_v:
        w("None.")
        w("")
    for section in STATIC_SECTIONS:
        w(section)
        w("")
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(L).rstrip() + "\n", encoding="utf-8")


TRACE_LINES_MAX = 600

PROPERTY_TABLE = [
    ("inv_no_concurrent_rw", "rtpattern.prop", "(1) no task is WRITING the array (indexWrite) another task is READING (indexRead) of the same buffer"),
    ("inv_no_concurrent_rw_data", "rtpattern.prop", "(1) the same on the data: a READING task's copy is not the element being written and is still in the buffer"),
    ("stp_indexes_stable_during_access", "rtpattern.prop", "(1) the indexes of a buffer do not change under an ongoing READING/WRITING of it"),
    ("stp_exit_releases_semaphore", "rtpattern.prop", "(2) a pattern machine never exits with its task in EXECUTION, WAITING or queued on the buffer's semaphore"),
    ("stp_slave_never_moves_indexes", "rtpattern.prop", "(3) every update of indexRead/indexWrite/indexUpdated is explained by the buffer's MASTER (swap under the semaphore, or release)"),
    ("stp_slave_never_moves_indexes_exact", "rtpattern_nondet.prop", "(3) nondeterministic specs: the one scheduler that ran is in a MASTER phase of the buffer"),
    ("stp_one_scheduler_per_step", "rtpattern_nondet.prop", "nondeterministic specs: exactly one scheduler runs per step (soundness of the exact attribution)"),
    ("stp_swap_publishes_latest", "rtpattern.prop", "(4, beyond the paper) a master's swap makes the slave writer's latest element the read array's content"),
    ("inv_indexes_below_dimension", "rtpattern.prop", "indexRead, indexWrite < dimension"),
    ("inv_indexes_distinct", "rtpattern.prop", "indexRead != indexWrite"),
    ("inv_sem_mutex", "rtpattern.prop", "per buffer, at most one scheduler inside its pattern machine has its task in EXECUTION"),
    ("inv_sem_count_matches_holder", "rtpattern.prop", "semacount(sem(b)) < 1 exactly when a scheduler inside its pattern machine on b is in EXECUTION"),
    ("inv_semacount_range", "rtpattern_semaphore.prop", "0 <= semacount <= 1 (binary semaphores)"),
    ("inv_semaq_no_duplicates", "rtpattern_semaphore.prop", "no task twice in a semaphore's queue"),
    ("inv_semaq_waiting_async", "rtpattern_semaphore.prop", "queued tasks are WAITING and ASYNCHRONOUS"),
    ("inv_semaq_only_if_locked", "rtpattern_semaphore.prop", "a non-empty queue only while the semaphore is taken"),
    ("inv_single_sem_mutex", "rtpattern_semtest.prop", "Test_Sem_*: at most one task in EXECUTION (one semaphore)"),
    ("inv_single_sem_count", "rtpattern_semtest.prop", "Test_Sem_*: semacount < 1 exactly when some task is in EXECUTION"),
]

STATIC_SECTIONS = [
    """## Nondeterministic scheduling

The applications fix the order of the tasks (`seq r_scheduler_execute[c1] r_scheduler_execute[c2] ... endseq`
every step), so each is one deterministic schedule (plus the `passed` stutter). The specs in tests/rtpattern/
import the library unchanged and replace only the application's main rule by

```
choose $c in Scheduler with
        not (task_kind(scheduler_mainThread($c)) = ASYNCHRONOUS
             and task_currState(scheduler_mainThread($c)) = WAITING) do
    r_scheduler_execute [$c]
```

one scheduler per step, any of them, except a task blocked in `sem_wait` (an RTOS does not run it; in the
library it would spin and count its unbounded time counters, which makes the state space infinite without
fairness). `RtNondetVS` is VisualServoing's set-up (tasks, roles, buffers, phases, starting points) with small
times (phase times 0, periods 200); `RtNondetPairs` exercises the pattern machines no application uses
(synchronous MASTER writing and reading, asynchronous SLAVE reading and writing). Their import
line names `RTPatternLibrary/CommonBehaviour/Scheduler`, found through the folder given at run time with
`-I ../shared/asmeta/asm_examples` (or the `ASMCHECK_PATH` environment variable), so the library is read in
place and never copied.""",
    """## Do the properties catch defects?

The coverage table shows the situations the properties speak about are reached. In addition,
tests/test_rtpattern_mutants.py seeds three defects into a temporary copy of the library (the shared folder is
never touched) and explores RtNondetPairs (a master and a slave in both directions, every interleaving) with
the same property files:

| seeded defect | states | caught by (shortest trace, steps) |
|---|---:|---|
| `r_SwingingBuffer_releaseLock` does not post the semaphore | 192 | `stp_exit_releases_semaphore` (4), `inv_sem_count_matches_holder` (4) |
| a SLAVE also runs `r_SwingingBuffer_updateIndexes` after taking the lock | 21,782 | `stp_slave_never_moves_indexes` (2), `stp_slave_never_moves_indexes_exact` (2), `stp_indexes_stable_during_access` (3), `inv_no_concurrent_rw_data` (4), `stp_exit_releases_semaphore` (5) |
| the swap moves `indexRead` only | 2,134 | `stp_slave_never_moves_indexes` (3), `inv_indexes_distinct` (3), `inv_no_concurrent_rw` (12), `inv_no_concurrent_rw_data` (12) |

Each of the paper's three properties is thus shown to fail when the library breaks it.""",
    """## What the audit changed in asmcheck

The audit found five shortcomings of asmcheck itself; all are fixed, with tests:

1. **Step properties and extend-made elements.** Step properties were evaluated on the canonicalised
   successor, whose extend-made elements are renamed independently of the state before the step, so an
   element carried across the step by a `let` could denote another one after it (a first version of
   `stp_exit_releases_semaphore` was reported violated on VisualServoing for steps that do not break it).
   Step properties now see the successor as the step made it; tests/test_trace_names.py keeps the
   two-element reproducer (`test_step_property_keeps_extend_made_elements_across_the_step`).
2. **Trace names.** Traces printed each state under its own canonical names, so a step listed "changes" that
   were only renamings. Traces now name extend-made elements as a plain simulation of the same run does
   (an element keeps its name; a new one takes the next number of its domain), in every format.
3. **Bounded runs beside a violation.** With a limit (`--max-depth`, ...) and a violated property, the other
   properties were reported "holds"; they are now "incomplete", and the text output says which limit stopped
   the search.
4. **A library kept elsewhere.** The nondeterministic specs import the library through the new `-I DIR` /
   `ASMCHECK_PATH` search path instead of a relative path that only works in one folder layout.
5. `updatedBy(x, loc)` accepted any `x` (here a Task, which is not an Agent) and was then always false; it is
   now a located type error.

Still open: the library's specs run on the Python engine only (the native explorer does not take specs with
`extend`, sequences or step properties), so CompleteApplication's full exploration takes minutes.""",
]


def passed_notes(results: list[dict], loop: dict) -> list[str]:
    by = {r["run"].key: r for r in results}
    notes = []
    rows = []
    for app in ("VisualServoing", "RobotController", "CompleteApplication", "Test_SB"):
        f, t = by.get(f"{app}/free"), by.get(f"{app}/true")
        if not f or not t:
            continue
        lp = loop.get(app)
        rows.append(f"| {app} | {fmt_int(f['states'])} | {fmt_int(t['states'])} | {fmt_int(t['transitions'])} | "
                    + (f"{fmt_int(lp[0])} -> state at depth {fmt_int(lp[1])} (cycle of {fmt_int(lp[0] + 1 - lp[1])} steps)"
                       if lp else "n/a") + " |")
    if rows:
        notes.append("| application | states, passed free | states, passed true | transitions, passed true | "
                     "last state -> revisited state |")
        notes.append("|---|---|---|---|---|")
        notes += rows
        notes.append("")
    vs = by.get("VisualServoing/true")
    lp = loop.get("VisualServoing")
    if vs and lp:
        n = vs["states"]
        notes.append(
            f"With `passed` true every application is deterministic: its states form one chain that ends in a "
            f"cycle. For VisualServoing asmcheck counts {n:,} states: the initial state (`initialized = false`), "
            f"then the states after steps 1 to {lp[0]:,}; step {lp[0] + 1:,} leads back to the state after step "
            f"{lp[1]:,}. Without the initial state that is {n - 1:,} distinct states, which matches ASMETA's "
            f"simulator revisiting a state after about 15,708 distinct states (AsmetaS does not count the state "
            f"before its first step as one it can revisit, and the first step, which runs `r_init`, is never "
            f"repeated). So the run is a start-up of {lp[1]:,} steps followed by a cycle of "
            f"{lp[0] + 1 - lp[1]:,} steps ({(lp[0] + 1 - lp[1]) * 100 / 1e6:g} s of the application's time at "
            f"baseTime = 100 us per step), after which the three tasks' phase sequences, clocks and buffer contents "
            f"line up again. asmcheck finds this cycle only because fresh `DataStream` elements are identified: every "
            f"write `extend`s DataStream with a new element, so without canonical renaming (and dropping the "
            f"elements nothing refers to any more) no state "
            f"would ever repeat and the state space would be infinite.")
        notes.append("")
    f = by.get("VisualServoing/free")
    if vs and f:
        notes.append(
            f"With `passed` free the state space has {f['states'] - vs['states']:+,} state(s) with respect to "
            f"`passed` true: a step with `passed` false changes nothing except in the very first step, where "
            f"`r_init` runs regardless of `passed`, so the state right after `r_init` alone is the one extra state; "
            f"every other `passed = false` step is a self-loop, which is why the transitions double. The verdicts "
            f"are the same.")
    return notes


def loop_targets(shared: Path, apps: list[str]) -> dict:
    """For the deterministic passed=true chains: (depth of the last state, depth of the state its only
    successor is). Uses asmcheck's explorer in-process, with the state graph kept."""
    import asmcheck

    out = {}
    for app in apps:
        try:
            model = asmcheck.load(lib_dir(shared) / f"Application/{app}.asm", monitored={"passed": [True]},
                                  default_properties=False)
            g = model.explore(engine="python", graph=True).graph()
            last = max(g.nodes, key=lambda s: (g.nodes[s]["depth"], -s))
            back = sorted(g.successors(last))
            if back:
                out[app] = (int(g.nodes[last]["depth"]), int(g.nodes[back[0]]["depth"]))
        except (asmcheck.AsmError, asmcheck.UsageError) as e:
            print(f"loop analysis of {app} failed: {e}", file=sys.stderr)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--shared", default=os.environ.get("ASMCHECK_SHARED", str(ROOT.parent / "shared")),
                    help="the shared folder that holds asmeta/asm_examples/RTPatternLibrary (default ../shared)")
    ap.add_argument("--out", default=str(ROOT / "docs" / "rtpattern-audit.md"))
    ap.add_argument("--jobs", type=int, default=2, help="explorations run in parallel (default 2)")
    ap.add_argument("--only", action="append", default=[], metavar="NAME",
                    help="only the runs of this spec (repeatable); for a quick partial report")
    ap.add_argument("--no-coverage", action="store_true", help="skip the coverage runs")
    ap.add_argument("--loop", action="append", default=None, metavar="APP",
                    help="applications whose passed=true cycle is analysed (default VisualServoing; 'none' for none)")
    ap.add_argument("--timeout", type=float, default=None, help="seconds per exploration (default none)")
    args = ap.parse_args(argv)
    shared = Path(args.shared).resolve()
    if not (lib_dir(shared) / "CommonBehaviour" / "Scheduler.asm").exists():
        print(f"rtpattern_audit: the library is not at {lib_dir(shared)} (use --shared)", file=sys.stderr)
        return 2
    runs = runs_list(coverage=not args.no_coverage)
    if args.only:
        runs = [r for r in runs if r.spec in args.only]
    # longest first, so that the parallel runs finish together
    order = sorted(runs, key=lambda r: -EXPECTED_COST.get(r.spec, 1))
    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        futs = {r.key: pool.submit(explore, r, shared, args.timeout) for r in order}
        results = []
        for r in runs:
            res = futs[r.key].result()
            print(f"{r.key}: {fmt_int(res['states'])} states, {res['seconds']} s, verdict {res['verdict']}"
                  + (f" ({bounded(res)})" if bounded(res) else ""), file=sys.stderr)
            results.append(res)
    apps = [a for a in (args.loop or ["VisualServoing"]) if a != "none" and (not args.only or a in args.only)]
    loop = loop_targets(shared, apps)
    write_report(results, shared, Path(args.out), {"passed_notes": passed_notes(results, loop)})
    print(f"wrote {args.out}", file=sys.stderr)
    return 0


EXPECTED_COST = {"CompleteApplication": 100, "RtNondetVS": 80, "VisualServoing": 20, "RobotController": 15}

if __name__ == "__main__":
    sys.exit(main())
