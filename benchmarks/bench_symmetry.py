#!/usr/bin/env python3
"""Symmetry reduction (``explore --symmetry``) on the native engine and on the Python engine, each
run a separate process, the two paired (one right after the other, ``--repeat`` times): whole-process
wall time, peak resident memory, classes, transitions, and the search's rate (classes and
transitions per second of the time the report gives).  The native engine's first run compiles in a
fresh cache folder (cold), the later ones find it there (warm).  The load average before and after
is recorded: the machine may be shared.

    python benchmarks/bench_symmetry.py [SPEC.asm ...] [--repeat 3] [--out benchmarks/results]

Without specs: ../shared/asmeta/asm_examples/examples/tombola.asm, battleship.asm and parking.asm.
The Python engine's runs stop at --python-seconds (120 s; the report then says 'incomplete').
A benchmark, not a test: nothing fails on a slow machine."""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_native import measure  # noqa: E402

SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))
DEFAULT = ["asm_examples/examples/tombola.asm", "asm_examples/examples/battleship.asm",
           "asm_examples/examples/parking.asm"]


def run(spec: Path, engine: str, cache: str, seconds: float | None = None) -> dict:
    more = ["--max-seconds", str(seconds)] if seconds else []
    got = measure([sys.executable, "-m", "asmcheck", "explore", str(spec), "--symmetry", "--engine", engine,
                   "--format", "json", *more], cwd=ROOT, env={"ASMCHECK_CACHE": cache}, timeout=900)
    try:
        d = json.loads(got["stdout"])
    except ValueError:
        d = {}
    out = {"wall": round(got["wall"], 3), "rss_mb": round(got["rss"] / 2**20, 1), "code": got["code"],
           "engine": d.get("engine"), "classes": d.get("states"), "transitions": d.get("transitions"),
           "search_seconds": d.get("seconds"), "compile_seconds": d.get("compile_seconds"),
           "verdicts": [r.get("verdict") for r in d.get("properties", [])], "incomplete": d.get("incomplete", "")}
    secs = d.get("seconds") or 0
    if secs:
        out["classes_per_s"] = round(d["states"] / secs)
        out["transitions_per_s"] = round(d["transitions"] / secs)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("specs", nargs="*")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--out", default=None, help="a folder for the JSON and Markdown results")
    ap.add_argument("--python-seconds", type=float, default=120.0,
                    help="the Python engine's time limit (parking.asm takes far longer)")
    a = ap.parse_args(argv)
    specs = [Path(s) for s in a.specs] or [SHARED / "asmeta" / rel for rel in DEFAULT]
    report = {"load_before": os.getloadavg(), "runs": {}}
    with tempfile.TemporaryDirectory() as cache:
        for spec in specs:
            rows = {"native_cold": run(spec, "native", cache), "native": [], "python": []}
            for _ in range(a.repeat):
                rows["native"].append(run(spec, "native", cache))
                rows["python"].append(run(spec, "python", cache, a.python_seconds))
            report["runs"][spec.name] = rows
            print(spec.name, json.dumps(rows["native_cold"]), flush=True)
            for k in ("native", "python"):
                walls = [r["wall"] for r in rows[k]]
                print(f"  {k}: median {statistics.median(walls):.2f} s whole process, "
                      f"{max(r['rss_mb'] for r in rows[k]):.0f} MB; {json.dumps(rows[k][-1])}", flush=True)
    report["load_after"] = os.getloadavg()
    print("load", report["load_before"], "->", report["load_after"])
    if a.out:
        stamp = time.strftime("%Y%m%d-%H%M")
        Path(a.out).mkdir(parents=True, exist_ok=True)
        (Path(a.out) / f"bench_symmetry-{stamp}.json").write_text(json.dumps(report, indent=1) + "\n")
        lines = ["# --symmetry, native and Python engines (paired runs)", "",
                 f"load average before {report['load_before'][0]:.2f}, after {report['load_after'][0]:.2f}; "
                 "the rates are over the time the report gives (the search, the LTL/CTL check and the traces)", "",
                 "| spec | engine | whole process (median) | cold compile run | peak MB | classes | transitions | "
                 "classes/s | transitions/s |", "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
        for name, rows in report["runs"].items():
            for k in ("native", "python"):
                last = rows[k][-1]
                lines.append(f"| {name} | {k} | {statistics.median(r['wall'] for r in rows[k]):.2f} s | "
                             + (f"{rows['native_cold']['wall']:.2f} s" if k == "native" else "–")
                             + f" | {max(r['rss_mb'] for r in rows[k]):.0f} | {last['classes']} | "
                               f"{last['transitions']} | {last.get('classes_per_s', '–')} | "
                               f"{last.get('transitions_per_s', '–')} |")
        (Path(a.out) / f"bench_symmetry-{stamp}.md").write_text("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
