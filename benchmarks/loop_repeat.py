#!/usr/bin/env python3
"""The native search loop of one exploration, run again and again in one process (for profilers:
``perf record``, ``perf stat``), with the seconds of each run.

    python benchmarks/loop_repeat.py SPEC [--repeat N] [--seconds S] [--engine native] [-- EXPLORE ARGS]

The exploration is the one ``asmcheck explore SPEC EXPLORE ARGS`` makes (same properties, same
generated engine); its ``NativeExplorer.run`` (the search loop the bench's "loop s" column times)
is called N times (or until S seconds have passed), each time a whole search from the initial
states.  Prints the fastest and the median run, the states and transitions, and (``--source
FILE``) writes the generated C.  ``$ASMCHECK_CFLAGS`` (e.g. ``-O1 ... -g``) gives a library with
symbols for a profiler; it is part of the cache key.
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("spec")
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--seconds", type=float, default=None, help="repeat until this long (overrides --repeat)")
    ap.add_argument("--engine", default="native")
    ap.add_argument("--source", help="write the generated C here")
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    args = ap.parse_args(argv[:argv.index("--")] if "--" in argv else argv)
    args.extra = extra
    import asmcheck.cli as cli
    from asmcheck.explore import native
    orig = native.NativeExplorer.run
    times: list = []

    def repeated(self):
        if args.source:
            Path(args.source).write_text(self._src or "")
        res = None
        t_end = time.perf_counter() + args.seconds if args.seconds else None
        n = 0
        while True:
            s = time.perf_counter()
            res = orig(self)
            times.append(time.perf_counter() - s)
            n += 1
            if (t_end is not None and time.perf_counter() >= t_end) or (t_end is None and n >= args.repeat):
                break
        return res
    native.NativeExplorer.run = repeated
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        cli.main(["explore", args.spec, "--format", "json", "--engine", args.engine, *args.extra])
    res = json.loads(out.getvalue())
    print(json.dumps({"spec": args.spec, "engine": res.get("engine"), "states": res.get("states"),
                      "transitions": res.get("transitions"), "runs": len(times),
                      "fastest": round(min(times), 5) if times else None,
                      "median": round(statistics.median(times), 5) if times else None,
                      "transitions_per_s_fastest": round(res.get("transitions", 0) / min(times)) if times else None},
                     indent=1))


if __name__ == "__main__":
    main()
