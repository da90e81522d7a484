#!/usr/bin/env python3
"""The memory and time of the CTL check's successor lists (asmcheck.temporal.need): each spec is
explored on the native engine by a separate process, with the lists the check reads and with every
list (``ASMCHECK_EDGE_NEED=all``), the two runs paired (one right after the other, ``--repeat``
times); whole-process wall time, peak resident memory, and bytes per state (the peak above that of
the same command on a one-state spec, divided by the states).

    python benchmarks/bench_edge_need.py SPEC.asm [...] [--repeat 3]

A benchmark, not a test: nothing fails on a slow machine."""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_native import measure  # noqa: E402

ONE = """asm One
import StandardLibrary
import CTLLibrary
signature:
	controlled x: Boolean
definitions:
	CTLSPEC ag(not x)
	main rule r_main = skip
default init s0:
	function x = false
"""


def run(spec: Path, every: bool) -> dict:
    env = {"ASMCHECK_EDGE_NEED": "all" if every else ""}
    got = measure([sys.executable, "-m", "asmcheck", "explore", str(spec), "--engine", "native", "--format", "json"],
                  cwd=ROOT, env=env, timeout=600)
    try:
        d = json.loads(got["stdout"])
    except ValueError:
        d = {}
    got["states"] = d.get("states")
    got["verdicts"] = [r.get("verdict") for r in d.get("properties", d.get("rows", []))] if d else []
    return got


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("specs", nargs="+")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as d:
        one = Path(d) / "One.asm"
        one.write_text(ONE)
        base = {k: min(run(one, k)["rss"] for _ in range(2)) for k in (False, True)}
    print("| spec | states | peak MB (reduced / every list) | bytes/state | whole process s |")
    print("|---|---:|---|---|---|")
    for spec in map(Path, a.specs):
        rows = {False: [], True: []}
        for _ in range(a.repeat):
            for every in (True, False):
                rows[every].append(run(spec, every))
        n = rows[False][0]["states"] or 0
        peak = {k: statistics.median(r["rss"] for r in v) for k, v in rows.items()}
        wall = {k: statistics.median(r["wall"] for r in v) for k, v in rows.items()}
        bps = {k: (peak[k] - base[k]) / n if n else float("nan") for k in rows}
        print(f"| {spec.name} | {n:,} | {peak[False] / 2**20:.1f} / {peak[True] / 2**20:.1f} | "
              f"{bps[False]:,.0f} / {bps[True]:,.0f} | {wall[False]:.2f} / {wall[True]:.2f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
