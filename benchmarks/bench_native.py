#!/usr/bin/env python3
"""Native-engine benchmark: whole-process time, states/s, transitions/s, peak memory, bytes per
state, compile time and the engine used, on the specs users run.

    python benchmarks/bench_native.py [--quick] [--engine auto|native|python] [--shared ../shared]
                                      [--max-seconds S] [--only TEXT] [--out benchmarks/results]

Each model is explored by a separate process (``python -m asmcheck explore ... --format json``);
its wall time and peak resident memory (``os.wait4``'s rusage of that child) are measured.
Rates are per second of search (the JSON's ``seconds``); each row is also given as a ratio of
the transitions/s of the benchmark twin T=63 K=250 measured in the same run (T=31 K=128 with
``--quick``).  Bytes/state is the peak memory above that of the same command on a one-state spec,
divided by the states.  The models:

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


def measure(cmd: list[str], cwd=None, timeout: float | None = None, env: dict | None = None) -> dict:
    """Run ``cmd``; its wall time, peak RSS (bytes, from ``os.wait4``'s rusage of that very
    child), exit code (None when killed at ``timeout``) and stdout/stderr."""
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen(cmd, cwd=cwd, stdout=out, stderr=err, env={**os.environ, "PYTHONPATH": str(ROOT), **(env or {})})
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
    return [asmeta / rel for _, rel in scored[:n]]


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
    return out


def run_model(name, path, extra, engine, max_seconds, cache: Path | None = None) -> dict:
    """One model.  With ``cache`` (a fresh folder) the first run compiles (cold); when it ran native
    it is run again on the filled cache, and that warm run is the row, with the compile time
    (the JSON's ``compile_seconds`` when the report gives it, else cold wall - warm wall)."""
    cmd = [sys.executable, "-m", "asmcheck", "explore", str(path), "--format", "json", "--engine", engine,
           "--max-seconds", str(max_seconds), *extra]
    env = {"ASMCHECK_CACHE": str(cache)} if cache is not None else {}
    r = measure(cmd, timeout=max_seconds * 3 + 60, env=env)
    row = _row(name, path, extra, r)
    if cache is not None and row.get("engine") == "native":
        warm = _row(name, path, extra, measure(cmd, timeout=max_seconds * 3 + 60, env=env))
        if warm.get("compile_seconds") is None and row.get("compile_seconds") is None:
            warm["compile_seconds"] = round(max(row["wall"] - warm["wall"], 0.0), 3)
        elif warm.get("compile_seconds") is not None and row.get("compile_seconds") is not None:
            warm["compile_seconds_warm"] = warm["compile_seconds"]
            warm["compile_seconds"] = row["compile_seconds"]
        warm["cold_wall"] = row["wall"]
        row = warm
    return row


def _row(name, path, extra, r) -> dict:
    row = {"model": name, "path": str(path), "args": extra, "exit": r["code"], "wall": round(r["wall"], 3),
           "peak_mb": round(r["rss"] / 2 ** 20, 1), "rss": r["rss"]}
    try:
        res = json.loads(r["stdout"])
    except ValueError:
        lines = (r["stderr"].strip() or "no output").splitlines()
        row.update(engine="-", error=lines[0][:200] if lines else "")
        return row
    search = max(float(res.get("seconds") or 0.0), 1e-6)
    row.update(engine=res.get("engine", "?"), verdict=res.get("verdict"), states=res.get("states", 0),
               transitions=res.get("transitions", 0), search=res.get("seconds"),
               states_per_s=round(res.get("states", 0) / search), transitions_per_s=round(res.get("transitions", 0) / search),
               compile_seconds=res.get("compile_seconds"), reason=res.get("incomplete", ""),
               engine_reason=res.get("engine_reason", ""))
    return row


def markdown(rows, meta) -> str:
    lines = [f"# bench_native {meta['date']} ({meta['mode']}, --engine {meta['engine']})", "",
             f"Machine: {meta['machine']}; twin transitions/s: {meta['twin_tps']:,.0f}; baseline peak "
             f"{meta['baseline_mb']:.1f} MB.", "",
             "| model | engine | verdict | states | transitions | wall s | search s | compile s (cold wall) | states/s | "
             "transitions/s | × twin | peak MB | bytes/state |",
             "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if "states" not in r:
            lines.append(f"| {r['model']} | - | error: {r.get('error', '')} | | | {r['wall']:.2f} | | | | | | "
                         f"{r['peak_mb']:.0f} | |")
            continue
        comp = "-" if r.get("compile_seconds") is None else f"{r['compile_seconds']:.2f} ({r.get('cold_wall', float('nan')):.2f})"
        verdict = r["verdict"] + (f" ({r['reason']})" if r.get("reason") else "")
        lines.append(f"| {r['model']} | {r['engine']} | {verdict} | {r['states']:,} | {r['transitions']:,} | "
                     f"{r['wall']:.2f} | {r['search']:.2f} | {comp} | {r['states_per_s']:,} | "
                     f"{r['transitions_per_s']:,} | {r['ratio']:.3f} | {r['peak_mb']:.0f} | "
                     f"{r['bytes_per_state']:,} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shared", default=os.environ.get("ASMCHECK_SHARED") or str(ROOT.parent / "shared"))
    ap.add_argument("--engine", default="auto")
    ap.add_argument("--quick", action="store_true", help="the small twin and fewer corpus specs")
    ap.add_argument("--max-seconds", type=float, default=None, help="search time limit per model "
                    "(default 300, 20 with --quick)")
    ap.add_argument("--only", help="run only models whose name contains this text")
    ap.add_argument("--out", default=str(ROOT / "benchmarks" / "results"))
    args = ap.parse_args(argv)
    shared = Path(args.shared)
    max_seconds = args.max_seconds or (20 if args.quick else 300)
    work = Path(tempfile.mkdtemp(prefix="asmcheck-bench-"))
    todo = models(shared, work, args.quick)
    # baseline: the same command on a spec with one state
    one = work / "One.asm"
    one.write_text("asm One\nimport StandardLibrary\nsignature:\n\tcontrolled x: Boolean\ndefinitions:\n"
                   "\tmain rule r_main = x := true\ndefault init s0:\n\tfunction x = true\n")
    base = run_model("baseline", one, [], args.engine, max_seconds)
    rows = []
    for name, path, extra, role in todo:
        if args.only and args.only not in name and role != "twin":
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
    for r in rows:
        r["ratio"] = (r.get("transitions_per_s", 0) / twin_tps) if twin_tps else float("nan")
    meta = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "mode": "quick" if args.quick else "full", "engine": args.engine,
            "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}",
            "twin_tps": twin_tps, "baseline_mb": base["rss"] / 2 ** 20, "max_seconds": max_seconds}
    md = markdown(rows, meta)
    print(md)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = f"bench_native-{time.strftime('%Y%m%d-%H%M', time.gmtime())}{'-quick' if args.quick else ''}"
    for r in rows:
        r.pop("rss", None)
    (out / f"{stem}.json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1) + "\n")
    (out / f"{stem}.md").write_text(md)
    print(f"wrote {out / stem}.json and .md", file=sys.stderr)
    import shutil
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
