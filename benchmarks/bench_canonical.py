#!/usr/bin/env python3
"""Canonicaliser benchmark: explorations of specs that `extend` abstract domains.

    python benchmarks/bench_canonical.py [--shared ../shared] [--repeat N] [--only TEXT]

Explores the RTPatternLibrary applications (../shared/asmeta/asm_examples/RTPatternLibrary)
and tests/rtpattern/RtNondetVS.asm, each in a separate process with the Python engine,
and prints a Markdown table: states, transitions, depth, search seconds, states/s, and
the seconds spent canonicalising extend-made elements (asmcheck/explore/canonical.py).
A benchmark, not a test: nothing fails on a slow machine. Without the shared corpus it
says so and stops.
"""
import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# runs asmcheck's CLI with the canonicaliser's time added up; prints it on stderr
_CHILD = r"""
import sys, time
from asmcheck.explore import canonical
spent = [0.0, 0]
call = canonical.Canonicalizer.__call__
def timed(self, state):
    t = time.perf_counter()
    try:
        return call(self, state)
    finally:
        spent[0] += time.perf_counter() - t
        spent[1] += 1
canonical.Canonicalizer.__call__ = timed
from asmcheck.cli import main
try:
    rc = main(sys.argv[1:])
finally:
    sys.stderr.write("\ncanonical-seconds %.6f %d\n" % (spent[0], spent[1]))
sys.exit(rc)
"""


def runs(shared: Path):
    app = shared / "asmeta/asm_examples/RTPatternLibrary/Application"
    props = ROOT / "properties"
    return [
        ("Test_SB", [app / "Test_SB.asm", "--properties", props / "rtpattern.prop",
                     "--properties", props / "rtpattern_semaphore.prop"]),
        ("RobotController", [app / "RobotController.asm"]),
        ("VisualServoing", [app / "VisualServoing.asm"]),
        ("CompleteApplication (3,000 states)", [app / "CompleteApplication.asm", "--max-states", "3000"]),
        ("RtNondetVS (depth 20)", [ROOT / "tests/rtpattern/RtNondetVS.asm", "-I", shared / "asmeta/asm_examples",
                                   "--max-depth", "20"]),
    ]


def explore(args):
    cmd = [sys.executable, "-c", _CHILD, "explore", "--no-default-properties", "--engine", "python",
           "--format", "json"] + [str(a) for a in args]
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    try:
        res = json.loads(proc.stdout)
    except ValueError:
        sys.exit(f"asmcheck failed: {' '.join(cmd[3:])}\n{proc.stdout}\n{proc.stderr}")
    canon, calls = 0.0, 0
    for line in proc.stderr.splitlines():
        if line.startswith("canonical-seconds "):
            _, s, n = line.split()
            canon, calls = float(s), int(n)
    return wall, res, canon, calls


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shared", default=str(ROOT.parent / "shared"))
    ap.add_argument("--repeat", type=int, default=1, help="runs per spec (the fastest is reported)")
    ap.add_argument("--only", help="run only specs whose name contains this text")
    args = ap.parse_args(argv)
    shared = Path(args.shared)
    if not (shared / "asmeta/asm_examples/RTPatternLibrary").is_dir():
        print(f"skipped: no RTPatternLibrary under {shared} (pass --shared DIR)")
        return 0
    print("| spec | states | transitions | depth | search s | states/s | canonicaliser s | share | wall s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, extra in runs(shared):
        if args.only and args.only not in name:
            continue
        best = None
        for _ in range(max(1, args.repeat)):
            got = explore(extra)
            if best is None or got[1]["seconds"] < best[1]["seconds"]:
                best = got
        wall, res, canon, _calls = best
        secs = res["seconds"]
        print(f"| {name} | {res['states']:,} | {res['transitions']:,} | {res['depth']:,} | {secs:.2f} | "
              f"{res['states'] / max(secs, 1e-9):,.0f} | {canon:.2f} | {canon / max(secs, 1e-9):.0%} | {wall:.2f} |",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
