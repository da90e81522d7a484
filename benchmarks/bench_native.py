#!/usr/bin/env python3
"""Native-engine benchmark: whole-process time, states/s, transitions/s, peak memory, bytes per
state, compile time and the engine used, on the specs users run.

    python benchmarks/bench_native.py [--quick] [--engine auto|native|python] [--shared ../shared]
                                      [--max-seconds S] [--only TEXT] [--out benchmarks/results]
    python benchmarks/bench_native.py --phases SPEC [-- EXPLORE ARGS]

Each model is explored by a separate process (``python -m asmcheck explore ... --format json``);
its wall time and peak resident memory (``os.wait4``'s rusage of that child) are measured.
Rates are per second of the exploration (the JSON's ``seconds``: search, code generation and
compilation, LTL/CTL); each row is also given as a ratio of
the transitions/s of the benchmark twin T=63 K=250 measured in the same run (T=31 K=128 with
``--quick``).  Bytes/state is the peak memory above that of the same command on a one-state spec,
divided by the states: at small sizes mostly the fixed cost of the spec (its syntax tree, the compiled
engine, the modules the command imports).  Search bytes/state is the peak above the resident size at
the start of the search (``--growth``: measured in process, Linux), divided by the states: what the
search, the state graph, the checks and the report hold.  Engine bytes/state is the native engine's
own count of what its tables hold at the end of the search (asm_memory_bytes), per state: the
marginal cost of a state, without the fixed costs.  The measured processes keep their Python bytecode in a folder of the run
(PYTHONDONTWRITEBYTECODE is dropped), as an installed asmcheck does.  The models:

* specs/*.asm with their property files (the ones beside them, as ``explore`` finds them);
* RTPatternLibrary VisualServoing and CompleteApplication, tests/rtpattern/RtNondetVS.asm, with the
  flags of tests/test_rtpattern*.py;
* the twin;
* the corpus specs that declare the most monitored functions;
* examples/parking.asm and every spec with NuSMV verdicts (../shared/asmeta/verdicts).

Writes ``bench_native-<date>.json`` and ``.md`` into the output folder.  A benchmark, not a test:
nothing fails on a slow machine.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


MEMORY_LIMIT = 3 * 2 ** 30      # a model whose search needs more is stopped (out of memory), not the machine


def _limit_memory():
    import resource
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def measure(cmd: list[str], cwd=None, timeout: float | None = None, env: dict | None = None) -> dict:
    """Run ``cmd``; its wall time, peak RSS (bytes, from ``os.wait4``'s rusage of that very
    child), exit code (None when killed at ``timeout``) and stdout/stderr."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, cwd=cwd, stdout=out, stderr=err, preexec_fn=_limit_memory,
                                env={**os.environ, "PYTHONPATH": str(ROOT), **(env or {})})
        killed = False
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if timeout is not None and time.perf_counter() - t0 > timeout and not killed:
                proc.kill()
                killed = True
            time.sleep(0.002)
        wall = time.perf_counter() - t0
        code = os.waitstatus_to_exitcode(status)
        proc.returncode = code
        out.seek(0)
        err.seek(0)
        rss = usage.ru_maxrss * (1 if sys.platform == "darwin" else 1024)
        return {"wall": wall, "rss": rss, "code": None if killed else code, "stdout": out.read(),
                "stderr": err.read()}


def monitored_rich(asmeta: Path, n: int) -> list[Path]:
    """The ``n`` corpus specs (accepted by ASMETA's parser, with a main rule) that declare the
    most monitored functions in their own file."""
    manifest = asmeta / "MANIFEST.tsv"
    if not manifest.exists():
        return []
    scored = []
    for line in manifest.read_text().splitlines()[1:]:
        rel, verdict = line.split("\t")[:2]
        if verdict != "accepts":
            continue
        text = (asmeta / rel).read_text(errors="replace")
        if not re.search(r"\bmain\s+rule\b", text):
            continue
        text = re.sub(r"//[^\n]*|/\*.*?\*/", "", text, flags=re.S)
        k = len(re.findall(r"\bmonitored\s+\w+\s*:", text))
        scored.append((-k, rel))
    scored.sort()
    out, folders = [], set()
    for _, rel in scored:        # one spec per folder: variants of one model tell nothing new
        folder = str(Path(rel).parent)
        if folder not in folders:
            folders.add(folder)
            out.append(asmeta / rel)
        if len(out) == n:
            break
    return out


def models(shared: Path, work: Path, quick: bool):
    """(name, spec path, extra arguments, role) of every model to measure."""
    out = []
    gen = shared / "bench" / "gen_swing.py"
    t, k = (31, 128) if quick else (63, 250)
    if gen.exists():
        subprocess.run([sys.executable, str(gen), str(t), str(k), str(work)], check=True, capture_output=True)
        out.append((f"twin T={t} K={k}", work / f"swing_T{t}_K{k}.asm", [], "twin"))
    for p in sorted((ROOT / "specs").glob("*.asm")):
        out.append((f"specs/{p.name}", p, [], "spec"))
    asmeta = shared / "asmeta"
    lib = asmeta / "asm_examples" / "RTPatternLibrary"
    props = ROOT / "properties"
    sb = ["--no-default-properties", "--properties", str(props / "rtpattern.prop"),
          "--properties", str(props / "rtpattern_semaphore.prop")]
    if (lib / "Application" / "VisualServoing.asm").exists():
        out.append(("RTPatternLibrary VisualServoing", lib / "Application" / "VisualServoing.asm", sb, "rtpattern"))
        if not quick:
            out.append(("RTPatternLibrary CompleteApplication", lib / "Application" / "CompleteApplication.asm", sb,
                        "rtpattern"))
        out.append(("tests/rtpattern/RtNondetVS.asm", ROOT / "tests" / "rtpattern" / "RtNondetVS.asm",
                    sb + ["--properties", str(props / "rtpattern_nondet.prop"), "--deadlock",
                          "-I", str(asmeta / "asm_examples")], "rtpattern"))
    for p in monitored_rich(asmeta, 2 if quick else 4):
        out.append((str(p.relative_to(asmeta)), p, [], "monitored"))
    parking = asmeta / "asm_examples" / "examples" / "parking.asm"
    if parking.exists():
        out.append(("examples/parking.asm", parking, [], "verdicts"))
    vdir = asmeta / "verdicts"
    if vdir.exists():
        vs = sorted(vdir.rglob("*.verdicts"))
        if quick:
            vs = vs[:5]
        for v in vs:
            rel = v.relative_to(vdir).with_suffix(".asm")
            p = asmeta / rel
            if p.exists() and p != parking:
                out.append((str(rel), p, [], "verdicts"))
    tombola = asmeta / "asm_examples" / "examples" / "tombola.asm"
    if tombola.exists() and not quick:
        # too many states to finish without flags (about 10^9): finished by the symmetry reduction
        out.append(("examples/tombola.asm --symmetry", tombola, ["--symmetry"], "verdicts"))
    return out


def run_model(name, path, extra, engine, max_seconds, cache: Path | None = None) -> dict:
    """One model.  With ``cache`` (a fresh folder) the first run compiles (cold); it is run again on
    the filled cache (a Python-engine run too, when the first ended within the limit: the cold run
    built the parser's grammar table), and that warm run is the row, with the compile time of a
    native run (the JSON's ``compile_seconds`` when the report gives it, else cold wall - warm wall)."""
    cmd = [sys.executable, "-m", "asmcheck", "explore", str(path), "--format", "json", "--engine", engine,
           "--max-seconds", str(max_seconds), *extra]
    env = {"ASMCHECK_CACHE": str(cache)} if cache is not None else {}
    r = measure(cmd, timeout=max_seconds + 30, env=env)
    row = _row(name, path, extra, r)
    if cache is not None and row.get("engine") == "python" and row.get("wall", 0) < max_seconds:
        # the cold run also built the parser's grammar table in the fresh cache folder
        warm = _row(name, path, extra, measure(cmd, timeout=max_seconds + 30, env=env))
        warm["cold_wall"] = row["wall"]
        row = warm
    elif cache is not None and row.get("engine") == "native":
        warm = _row(name, path, extra, measure(cmd, timeout=max_seconds + 30, env=env))
        if warm.get("compile_seconds") is None and row.get("compile_seconds") is None:
            warm["compile_seconds"] = round(max(row["wall"] - warm["wall"], 0.0), 3)
        elif warm.get("compile_seconds") is not None and row.get("compile_seconds") is not None:
            warm["compile_seconds_warm"] = warm["compile_seconds"]
            warm["compile_seconds"] = row["compile_seconds"]
        warm["cold_wall"] = row["wall"]
        row = warm
    if row.get("states"):
        row.update(search_loop(path, extra, engine, max_seconds, env))
        row.update(search_growth(path, extra, engine, max_seconds, env, row["states"]))
    return row


def search_growth(path, extra, engine, max_seconds, env, states: int) -> dict:
    """The memory the command needs from the start of its search on (``--growth``, in a process
    of its own): ``growth_bytes`` and ``growth_bytes_per_state`` (over ``states``)."""
    res = _in_process(["--growth", str(path), "--engine", engine], path, extra, max_seconds, env)
    if res.get("states") != states or res.get("growth_bytes") is None:
        return {}
    out = {"growth_bytes": res["growth_bytes"], "growth_bytes_per_state": round(res["growth_bytes"] / max(states, 1))}
    if res.get("engine_bytes") is not None:
        out["engine_bytes_per_state"] = round(res["engine_bytes"] / max(states, 1))
    return out


def _proc_kb(field: str) -> int:
    m = re.search(rf"^{field}:\s+(\d+) kB", Path("/proc/self/status").read_text(), re.M)
    return int(m.group(1)) if m else 0


def growth(spec: str, extra: list[str], engine: str) -> dict:
    """``explore SPEC`` in this process, measuring the resident memory it needs from the start of
    its search on: at the first call of the search (``NativeExplorer.run`` or ``Explorer.run``)
    the garbage is collected, freed heap memory is handed back (``malloc_trim``), the peak
    resident size is reset (Linux: ``/proc/self/clear_refs``) and the resident size read; at the
    end, the peak.  ``engine_bytes``: the native engine's own count of the bytes its
    tables hold at the end of the search (``asm_memory_bytes``: states, hash table, value table,
    canonical forms, recorded lists and edges; the most of its runs).  ``growth_bytes`` = peak -
    resident size at the start: what the search, the
    state graph, the LTL/CTL checks, the traces and the report hold above the parsed spec, the
    compiled engine and the interpreter (the fixed cost, which dominates small models' whole-process
    peak).  Only on Linux (None elsewhere)."""
    import ctypes
    import gc
    import asmcheck.cli as cli
    import asmcheck.explore.bfs as bfs
    from asmcheck.explore import native
    mark: dict = {}

    def at_start():
        if mark:
            return
        gc.collect()
        try:
            ctypes.CDLL("libc.so.6").malloc_trim(0)
            Path("/proc/self/clear_refs").write_text("5")
        except OSError:
            mark["start_kb"] = None
            return
        mark["start_kb"] = _proc_kb("VmRSS")

    for cls in (native.NativeExplorer, bfs.Explorer):
        orig = cls.run

        def run(self, *a, _orig=orig, **k):
            at_start()
            res = _orig(self, *a, **k)
            held = getattr(getattr(self, "dll", None), "asm_memory_bytes", None)
            if held is not None:
                held.restype = ctypes.c_int64
                mark["engine_bytes"] = max(mark.get("engine_bytes", 0), int(held()))
            return res
        cls.run = run
    import io
    import contextlib
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = cli.main(["explore", spec, "--format", "json", "--engine", engine, *extra])
    res = json.loads(out.getvalue())
    start = mark.get("start_kb")
    grown = None if not start else max(_proc_kb("VmHWM") - start, 0) * 1024
    return {"spec": spec, "exit": code, "engine": res.get("engine"), "states": res.get("states"),
            "start_bytes": start * 1024 if start else None, "growth_bytes": grown,
            "engine_bytes": mark.get("engine_bytes")}


LOOP_RUNS = 3          # the native search loop is timed as the fastest of at least this many runs
LOOP_SECONDS = 2.0     # and of more (up to 4 * LOOP_RUNS) while they took less than this in all


def _in_process(mode: list, path, extra, max_seconds, env) -> dict:
    """This script run with ``mode`` (--phases or --growth) on one model, in a process of its own:
    its JSON ({} when it printed none)."""
    cmd = [sys.executable, str(Path(__file__).resolve()), *mode, "--", "--max-seconds", str(max_seconds), *extra]
    r = measure(cmd, timeout=max_seconds + 30, env=env)
    try:
        return json.loads(r["stdout"])
    except ValueError:
        return {}


def search_loop(path, extra, engine, max_seconds, env) -> dict:
    """The seconds of the search loop alone (``NativeExplorer.run`` or ``Explorer.run``, measured
    in process by ``--phases``) and the rates over it: what the explore phase costs beyond it
    (code generation or the cache lookup, INVAR and property set-up, LTL/CTL, traces) is a fixed
    cost that dominates small models.  The native search is the fastest of several runs
    (LOOP_RUNS, LOOP_SECONDS): one run of a few milliseconds on a shared machine is mostly noise."""
    res = _in_process(["--phases", str(path), "--engine", engine, "--loop-runs", str(LOOP_RUNS),
                       "--loop-seconds", str(LOOP_SECONDS)], path, extra, max_seconds, env)
    ph = res.get("phases", {})
    loop = ph.get("search (native)") if res.get("engine") == "native" else ph.get("search (python)")
    if not loop or res.get("transitions") is None:
        return {}
    batch = ph.get("search batch", 1)
    out = {"loop_seconds": round(loop, 4 if batch == 1 else 7),
           "loop_transitions_per_s": round(res["transitions"] / max(loop, 1e-9)), "loop_batch": batch}
    inside = ph.get("search (native), in the engine") if res.get("engine") == "native" else None
    if inside:
        out["engine_loop_seconds"] = round(inside, 5)
        out["engine_loop_transitions_per_s"] = round(res["transitions"] / max(inside, 1e-9))
    return out


def _row(name, path, extra, r) -> dict:
    row = {"model": name, "path": str(path), "args": extra, "exit": r["code"], "wall": round(r["wall"], 3),
           "peak_mb": round(r["rss"] / 2 ** 20, 1), "rss": r["rss"]}
    try:
        res = json.loads(r["stdout"])
    except ValueError:
        lines = (r["stderr"].strip() or "no output").splitlines()
        why = "killed at the time limit" if r["code"] is None else lines[-1][:200] if lines else ""
        row.update(engine="-", error=why)
        return row
    if isinstance(res.get("error"), dict):
        # the spec is refused (the report's error: a usage or input error, with its place)
        e = res["error"]
        row.update(engine="-", error=f"exit {r['code']}: line {e.get('line')}: {str(e.get('message', ''))[:160]}")
        return row
    search = max(float(res.get("seconds") or 0.0), 1e-6)
    row.update(engine=res.get("engine", "?"), verdict=res.get("verdict"), states=res.get("states", 0),
               transitions=res.get("transitions", 0), search=res.get("seconds"),
               states_per_s=round(res.get("states", 0) / search), transitions_per_s=round(res.get("transitions", 0) / search),
               compile_seconds=res.get("compile_seconds"), reason=res.get("incomplete", ""),
               engine_note=res.get("engine_note", ""))
    return row


MIN_TIMED = 0.01             # rates of searches shorter than this (s) are not shown: the clock says little
MIN_LOOP_TIMED = 0.002      # the same for the search loop alone (timed in process) ...
BATCH_SECONDS = 0.002       # ... where a shorter search is timed as the mean run of a batch of this long
MIN_STATES_MEMORY = 1000     # bytes/state of smaller models is mostly the interpreter: not shown


def markdown(rows, meta) -> str:
    lines = [f"# bench_native {meta['date']} ({meta['mode']}, --engine {meta['engine']})", "",
             f"Machine: {meta['machine']}; twin transitions/s: {meta['twin_tps']:,.0f}; baseline peak "
             f"{meta['baseline_mb']:.1f} MB; search time limit {meta.get('max_seconds')} s.",
             "Rates are per second of the explore phase (the JSON's seconds; shown from 0.01 s); bytes/state is peak memory above "
             "the baseline per state (shown from 1,000 states); search bytes/state is the peak above the resident memory at the "
             "start of the search (the parsed spec, the compiled engine and the interpreter: --growth) per state; engine bytes/state is what the native "
             "engine's tables hold at the end of the search by its own count, per state; compile s is the cold run's compile time, "
             "the row itself the warm run (cache filled).  The loop columns time the search loop alone "
             f"(measured in process, the native search's fastest of {meta.get('loop_runs', 1)} or more runs, and for a "
             f"search under {BATCH_SECONDS * 1000:.0f} ms the mean run of the fastest of 3 batches of runs back to back, each "
             f"{BATCH_SECONDS * 1000:.0f} ms or more; "
             f"the twin's loop: {meta.get('twin_loop_tps', 0):,.0f} transitions/s): the rest of "
             "the explore phase is the fixed cost of code generation or the cache lookup, property set-up and LTL/CTL.  "
             "Engine loop × twin: the same run's time inside the engine's search calls (asm_run) alone, against the "
             "twin's: the loop's Python set-up of a search (the initial states, the temporal plan) left out, which is most "
             "of a small model's loop.", "",
             "| model | engine | verdict | states | transitions | wall s | explore s | compile s (cold wall) | states/s | "
             "transitions/s | × twin | loop s | loop transitions/s | × twin's loop | engine loop × twin | peak MB | "
             "bytes/state | search bytes/state | engine bytes/state |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if "states" not in r:
            lines.append(f"| {r['model']} | - | error: {r.get('error', '')} | | | {r['wall']:.2f} | | | | | | | | | | "
                         f"{r['peak_mb']:.0f} | | | |")
            continue
        timed = (r.get("search") or 0) >= MIN_TIMED
        rate = (lambda x: f"{x:,}") if timed else (lambda x: "-")
        ratio = f"{r['ratio']:.3f}" if timed else "-"
        # (a batch of runs is timed over BATCH_SECONDS or more)
        loop_timed = r.get("loop_batch", 1) > 1 or (r.get("loop_seconds") or 0) >= MIN_LOOP_TIMED
        ls = r.get("loop_seconds") or 0
        lsx = f"{ls:.3f}" if ls >= 0.001 or not ls else f"{ls:.6f}"
        loop = (f"{lsx} | {r['loop_transitions_per_s']:,} | {r.get('loop_ratio', float('nan')):.3f}"
                if loop_timed else f"{r.get('loop_seconds') or 0:.3f} | - | -" if r.get("loop_seconds") else "- | - | -")
        eng = f"{r['engine_loop_ratio']:.3f}" if loop_timed and r.get("engine_loop_ratio") else "-"
        bps = f"{r['bytes_per_state']:,}" if r["states"] >= MIN_STATES_MEMORY else "-"
        gps, eps = ((f"{r[k]:,}" if r["states"] >= MIN_STATES_MEMORY and r.get(k) is not None else "-")
                    for k in ("growth_bytes_per_state", "engine_bytes_per_state"))
        comp = "-" if r.get("compile_seconds") is None or r.get("engine") != "native" else f"{r['compile_seconds']:.2f} ({r.get('cold_wall', float('nan')):.2f})"
        verdict = (r.get("verdict") or "-") + (f" ({r['reason']})" if r.get("reason") else "")
        lines.append(f"| {r['model']} | {r['engine']} | {verdict} | {r['states'] or 0:,} | {r['transitions'] or 0:,} | "
                     f"{r['wall']:.2f} | {r['search'] or 0:.2f} | {comp} | {rate(r['states_per_s'])} | "
                     f"{rate(r['transitions_per_s'])} | {ratio} | {loop} | {eng} | {r['peak_mb']:.0f} | {bps} | {gps} | {eps} |")
    return "\n".join(lines) + "\n"


def phases(spec: str, extra: list[str], engine: str, loop_runs: int = 1, loop_seconds: float = 0.0) -> dict:
    """Where the time of ``explore SPEC`` goes, in this process: import, parse and load,
    properties, search, Kripke structure, each LTL/CTL check, traces, report.  The native search
    (``NativeExplorer.run``) is run ``loop_runs`` times, and more while the runs took less than
    ``loop_seconds`` in all (up to ``4 * loop_runs``), each a whole search from the initial states;
    "search (native)" is the fastest run ("search runs": how many), so that a busy machine's
    pauses do not count (a profiler can watch the runs: ``perf record``)."""
    t0 = time.perf_counter()
    import asmcheck.api as api
    import asmcheck.cli as cli
    import asmcheck.explore.bfs as bfs
    import asmcheck.temporal as temporal
    import asmcheck.temporal.ctl as ctl
    import asmcheck.temporal.ltl as ltl
    from asmcheck.explore import native, native_build
    times: dict = {"import": time.perf_counter() - t0}

    active: dict = {}

    def timed_fn(owner, name, key):
        orig = getattr(owner, name)

        def wrapper(*a, **k):
            # a call inside a call of the same phase (the native search run again with more
            # element slots) is counted once, by the outer call
            if active.get(key):
                return orig(*a, **k)
            active[key] = True
            s = time.perf_counter()
            try:
                return orig(*a, **k)
            finally:
                active[key] = False
                times[key] = times.get(key, 0.0) + time.perf_counter() - s
        setattr(owner, name, wrapper)
    timed_fn(api, "load_machine", "parse and load")
    timed_fn(api, "properties_for", "property files")
    timed_fn(bfs.Explorer, "run", "search (python)")
    timed_fn(native.NativeExplorer, "__init__", "generate and compile (native)")
    if loop_runs > 1 or loop_seconds > 0:
        repeat_native_search(native.NativeExplorer, times, max(loop_runs, 1), loop_seconds)
    else:
        timed_fn(native.NativeExplorer, "run", "search (native)")
    timed_fn(temporal, "build_kripke", "Kripke structure")
    timed_fn(temporal, "check_temporal", "temporal, all")
    timed_fn(ltl, "check_ltl", "LTL checks")
    timed_fn(ctl.CTL, "check", "CTL checks")
    import io
    import contextlib
    out = io.StringIO()
    s = time.perf_counter()
    with contextlib.redirect_stdout(out):
        code = cli.main(["explore", spec, "--format", "json", "--engine", engine, *extra])
    times["explore command, all"] = time.perf_counter() - s
    res = json.loads(out.getvalue())
    times["total in process"] = time.perf_counter() - t0
    if "generate and compile (native)" in times:
        times["of which compile"] = native_build.last_compile_seconds
    if "search runs" in times:
        times["search runs"] = int(times["search runs"])
    return {"spec": spec, "exit": code, "engine": res.get("engine"), "states": res.get("states"),
            "transitions": res.get("transitions"), "phases": {k: round(v, 5 if k.startswith("search") else 3) for k, v in times.items()}}


def repeat_native_search(cls, times: dict, runs: int, seconds: float) -> None:
    """``cls.run`` (the native search) run again and again at its first call: the fastest run's
    seconds as "search (native)", the number of runs as "search runs"."""
    orig = cls.run
    state = {"done": False}

    def run(self):
        if state["done"]:        # (a search run again with more element slots: counted in its call)
            return orig(self)
        state["done"] = True
        best, best_engine, total, n, res = None, None, 0.0, 0, None
        while n < runs or (total < seconds and n < 4 * runs):
            inside = _EngineClock(self.dll)
            s = time.perf_counter()
            try:
                res = orig(self)
            finally:
                inside.restore()
            dt = time.perf_counter() - s
            if best is None or dt < best:
                best, best_engine = dt, inside.seconds
            total += dt
            n += 1
        batch = 1
        if best < BATCH_SECONDS:
            # a search shorter than the clock can time well: batches of k runs back to back, each
            # at least BATCH_SECONDS, the mean run of the fastest of 3 batches
            batch = min(int(2 * BATCH_SECONDS / max(best, 1e-6)) + 1, 100_000)
            best_b = None
            for _ in range(3):
                inside = _EngineClock(self.dll)
                s = time.perf_counter()
                try:
                    for _ in range(batch):
                        res = orig(self)
                finally:
                    inside.restore()
                dt = (time.perf_counter() - s) / batch
                if best_b is None or dt < best_b:
                    best_b, best_engine = dt, inside.seconds / batch
                n += batch
            best = best_b
        times["search (native)"] = best
        # the part of that run spent in the engine's search calls (asm_run, asm_run_par): the rest
        # is the Python set-up of a search (packing the initial states, the temporal plan, ...)
        times["search (native), in the engine"] = best_engine
        times["search runs"] = n
        times["search batch"] = batch
        return res
    cls.run = run


class _EngineClock:
    """Times the calls of the native search functions of ``dll`` (asm_run, asm_run_par) until
    ``restore``."""

    NAMES = ("asm_run", "asm_run_par")

    def __init__(self, dll):
        self.dll, self.seconds, self.saved = dll, 0.0, {}
        for name in self.NAMES:
            fn = getattr(dll, name, None)
            if fn is None:
                continue
            self.saved[name] = fn

            def timed(*a, _fn=fn):
                t = time.perf_counter()
                try:
                    return _fn(*a)
                finally:
                    self.seconds += time.perf_counter() - t
            setattr(dll, name, timed)

    def restore(self):
        for name, fn in self.saved.items():
            setattr(self.dll, name, fn)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shared", default=os.environ.get("ASMCHECK_SHARED") or str(ROOT.parent / "shared"))
    ap.add_argument("--engine", default="auto")
    ap.add_argument("--quick", action="store_true", help="the small twin and fewer corpus specs")
    ap.add_argument("--max-seconds", type=float, default=None, help="search time limit per model "
                    "(default 300, 20 with --quick)")
    ap.add_argument("--only", help="run only models whose name contains this text (or one of these, comma-separated)")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results"))
    ap.add_argument("--phases", metavar="SPEC", help="only: where the time of one exploration goes (in process)")
    ap.add_argument("--loop-runs", type=int, default=1, help="with --phases: run the native search this many times "
                    "(the fastest is reported; for profilers: perf record ... --phases SPEC --loop-runs 50)")
    ap.add_argument("--loop-seconds", type=float, default=0.0, help="with --phases: and more runs while they took "
                    "less than this in all")
    ap.add_argument("--growth", metavar="SPEC", help="only: the memory explore SPEC needs from the start of its "
                    "search on (in process, Linux)")
    ap.add_argument("extra", nargs="*", help="with --phases or --growth: more arguments for explore")
    ap.add_argument("--render", metavar="JSON", help="only: print the markdown table of a results file")
    args = ap.parse_args(argv)
    if args.render:
        data = json.loads(Path(args.render).read_text())
        print(markdown(data["rows"], data["meta"]), end="")
        return
    if args.growth:
        print(json.dumps(growth(args.growth, args.extra, args.engine), indent=1))
        return
    if args.phases:
        print(json.dumps(phases(args.phases, args.extra, args.engine, args.loop_runs, args.loop_seconds), indent=1))
        return
    shared = Path(args.shared)
    max_seconds = args.max_seconds or (20 if args.quick else 300)
    work = Path(tempfile.mkdtemp(prefix="asmcheck-bench-"))
    # the measured processes keep their Python bytecode (in a folder of this run, none in the
    # checkout), as an installed asmcheck does: without it every run compiles the modules it
    # imports again (some 0.05 s of the explore phase: asmcheck.explore.native alone takes 0.04 s)
    os.environ.pop("PYTHONDONTWRITEBYTECODE", None)
    os.environ["PYTHONPYCACHEPREFIX"] = str(work / "pycache")
    todo = models(shared, work, args.quick)
    # baseline: the same command on a spec with one state
    one = work / "One.asm"
    one.write_text("asm One\nimport StandardLibrary\nsignature:\n\tcontrolled x: Boolean\ndefinitions:\n"
                   "\tmain rule r_main = x := true\ndefault init s0:\n\tfunction x = true\n")
    # (run warm, as the rows are: a cold run's peak also holds the bytecode compilation and the
    # parser's grammar table)
    base = run_model("baseline", one, [], args.engine, max_seconds, Path(tempfile.mkdtemp(prefix="cache-", dir=work)))
    rows = []
    for name, path, extra, role in todo:
        if args.only and not any(o in name for o in args.only.split(",")) and role != "twin":
            continue
        cache = Path(tempfile.mkdtemp(prefix="cache-", dir=work))
        row = run_model(name, path, extra, args.engine, max_seconds, cache)
        row["role"] = role
        row["bytes_per_state"] = round(max(row["rss"] - base["rss"], 0) / max(row.get("states") or 1, 1))
        rows.append(row)
        print(f"{name}: {row.get('engine')} {row.get('states', '-')} states {row.get('transitions', '-')} "
              f"transitions, {row['wall']:.2f} s, {row['peak_mb']:.0f} MB {row.get('error', '')}",
              file=sys.stderr, flush=True)
    twin = next((r for r in rows if r["role"] == "twin" and r.get("transitions_per_s")), None)
    twin_tps = twin["transitions_per_s"] if twin else 0
    twin_loop = twin.get("loop_transitions_per_s", 0) if twin else 0
    for r in rows:
        r["ratio"] = (r.get("transitions_per_s", 0) / twin_tps) if twin_tps else float("nan")
        r["loop_ratio"] = (r.get("loop_transitions_per_s", 0) / twin_loop) if twin_loop else float("nan")
        twin_engine = twin.get("engine_loop_transitions_per_s", 0) if twin else 0
        if r.get("engine_loop_transitions_per_s") and twin_engine:
            r["engine_loop_ratio"] = r["engine_loop_transitions_per_s"] / twin_engine
    meta = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "mode": "quick" if args.quick else "full", "engine": args.engine,
            "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}",
            "twin_tps": twin_tps, "twin_loop_tps": twin_loop, "baseline_mb": base["rss"] / 2 ** 20, "max_seconds": max_seconds,
            "loop_runs": LOOP_RUNS}
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = f"bench_native-{time.strftime('%Y%m%d-%H%M', time.gmtime())}{'-quick' if args.quick else ''}"
    for r in rows:
        r.pop("rss", None)
    # the measurements first: a rendering problem must not lose them
    (out / f"{stem}.json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1) + "\n")
    md = markdown(rows, meta)
    print(md)
    (out / f"{stem}.md").write_text(md)
    print(f"wrote {out / stem}.json and .md", file=sys.stderr)
    import shutil
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
