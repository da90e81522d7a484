#!/usr/bin/env python3
"""Front-end benchmark: parse and type-check every corpus file ASMETA's parser accepts.

    python benchmarks/bench_parse.py [--shared ../shared]

Reads ../shared/asmeta/MANIFEST.tsv and checks each accepted file (with its imports)
in one process, as `asmcheck parse` would; prints the total and the slowest files.
A benchmark, not a test.
"""
import argparse
import sys
import tempfile
import time
from pathlib import Path

import asmcheck


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shared", default=str(Path(__file__).resolve().parents[2] / "shared"))
    args = ap.parse_args(argv)
    root = Path(args.shared) / "asmeta"
    manifest = root / "MANIFEST.tsv"
    if not manifest.exists():
        sys.exit(f"no corpus at {root}")
    # the first parse builds (or reads from the cache) the grammar's tables
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        first = Path(tmp) / "First.asm"
        first.write_text("asm First\nimport StandardLibrary\nsignature:\ndefinitions:\nmain rule r_main = skip\n")
        asmcheck.parse(first)
    t_grammar = time.perf_counter() - t0
    rows = [line.split("\t") for line in manifest.read_text().splitlines()[1:]]
    times = []
    failed = 0
    t0 = time.perf_counter()
    for path, verdict in rows:
        if verdict != "accepts":
            continue
        t1 = time.perf_counter()
        try:
            asmcheck.parse(root / path)
        except asmcheck.AsmError:
            failed += 1
        times.append((time.perf_counter() - t1, path))
    total = time.perf_counter() - t0
    print(f"grammar ready (and StandardLibrary read) in {t_grammar:.2f} s")
    print(f"{len(times)} accepted files parsed and checked in {total:.2f} s ({failed} rejected)")
    for secs, path in sorted(times, reverse=True)[:5]:
        print(f"  {secs:6.3f} s  {path}")


if __name__ == "__main__":
    main()
