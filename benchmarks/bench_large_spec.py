#!/usr/bin/env python3
"""Front-end benchmark on generated large specs: many rules, deep nesting.

    python benchmarks/bench_large_spec.py [--rules 10000 50000] [--depth 800 2900]

For each size, writes a spec of N macro rules (``rule r_i = if x = i then x := i + 1 endif``)
and a spec of D nested ifs into a temporary folder, then measures ``asmcheck.parse`` (parsing
and name resolution together; wall-clock and CPU seconds).  Both are linear in the number of rules.
A benchmark, not a test.
"""
import argparse
import tempfile
import time
from pathlib import Path

import asmcheck


def _rules_spec(n: int) -> str:
    lines = ["asm Rules", "import StandardLibrary", "signature:", "\tcontrolled x: Integer", "definitions:"]
    lines += [f"\trule r_{i} = if x = {i} then x := {i + 1} endif" for i in range(n)]
    calls = "\n".join(f"\t\tr_{i}[]" for i in range(0, n, max(1, n // 50)))
    lines += ["\tmain rule r_main =\n\tpar\n" + calls + "\n\tendpar", "default init s0:", "\tfunction x = 0", ""]
    return "\n".join(lines)


def _deep_spec(d: int) -> str:
    body = "x := 0"
    for i in range(d):
        body = f"if x = {i % 7} then {body} endif"
    return ("asm Deep\nimport StandardLibrary\nsignature:\n\tcontrolled x: Integer\ndefinitions:\n"
            f"\tmain rule r_main = {body}\ndefault init s0:\n\tfunction x = 0\n")


def _measure(path: Path) -> tuple[float, float]:
    w0, c0 = time.perf_counter(), time.process_time()
    asmcheck.parse(path)
    return time.perf_counter() - w0, time.process_time() - c0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rules", type=int, nargs="*", default=[1000, 10000, 50000])
    ap.add_argument("--depth", type=int, nargs="*", default=[800, 2900])
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:      # the grammar table is built once, before timing
        p = Path(tmp) / "Rules.asm"
        p.write_text(_rules_spec(50))
        asmcheck.parse(p)
    with tempfile.TemporaryDirectory() as tmp:
        print(f"{'spec':>18}  {'parse+resolve s (cpu)':>22}")
        for n in args.rules:
            p = Path(tmp) / "Rules.asm"
            p.write_text(_rules_spec(n))
            w, c = _measure(p)
            print(f"{n:>12} rules  {w:13.2f} ({c:5.2f})")
        for d in args.depth:
            p = Path(tmp) / "Deep.asm"
            p.write_text(_deep_spec(d))
            w, c = _measure(p)
            print(f"{d:>9} nested ifs  {w:13.2f} ({c:5.2f})")


if __name__ == "__main__":
    main()
