#!/usr/bin/env python3
"""The memory and time of the CTL check's successor lists (asmcheck.temporal.need): each spec is
explored on the native engine by a separate process, with the lists the check reads and with every
list (``ASMCHECK_EDGE_NEED=all``), the two runs paired (one right after the other, ``--repeat``
times); whole-process wall time, peak resident memory, and bytes per state (the peak above that of
the same command on a one-state spec, divided by the states).

    python benchmarks/bench_edge_need.py SPEC.asm [...] [--repeat 3] [--flip]

``--flip`` adds four models written here: 16 bits, a step flips one or two of them (65,536 states,
136 successors each), with CTL properties that read no list, half the lists (eg), half the lists
(ag(ef ..)), and an ag broken (a second search, with three quarters of the lists).

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


FLIP = """asm {name}
import StandardLibrary
import CTLLibrary
signature:
	domain Bit subsetof Integer
	controlled b: Bit -> Boolean
	monitored fi: Bit
	monitored fj: Bit
definitions:
	domain Bit = {{0 : 15}}
{props}
	main rule r_main =
		par
			b(fi) := not b(fi)
			if fj != fi then b(fj) := not b(fj) endif
		endpar
default init s0:
	function b($x in Bit) = false
"""
FLIPS = {
    "FlipNone": ["not(ef(b(0) and not b(0)))", "ef(not b(0))", "ag(b(1) or not b(1))"],
    "FlipEg": ["eg(not b(15))"],
    "FlipAgEf": ["ag(ef(b(0)))"],
    # broken at the second level: the search again, with the lists of the states where it holds
    "FlipAgBroken": ["ag(not(b(0) and b(1)))"],
}


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
    ap.add_argument("specs", nargs="*")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--flip", action="store_true")
    a = ap.parse_args(argv)
    tmp = tempfile.TemporaryDirectory()
    d = Path(tmp.name)
    one = d / "One.asm"
    one.write_text(ONE)
    run(one, False)
    base = {k: min(run(one, k)["rss"] for _ in range(2)) for k in (False, True)}
    specs = list(a.specs)
    if a.flip:
        for name, props in FLIPS.items():
            (d / f"{name}.asm").write_text(FLIP.format(name=name, props="\n".join(f"\tCTLSPEC {p}" for p in props)))
            specs.append(str(d / f"{name}.asm"))
    print("| spec | states | peak MB (reduced / every list) | bytes/state | whole process s |")
    print("|---|---:|---|---|---|")
    for spec in map(Path, specs):
        rows = {False: [], True: []}
        run(spec, False)        # (the engine compiled and cached: the measured runs compile nothing)
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
