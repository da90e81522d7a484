"""The partitioned search on the native expander: one worker of the native engine, and the
partitioned search on a local Ray instance with 2 and 8 actors and in 2 forked worker processes,
with the time to start the actors (each compiles or loads the spec's C code) apart from the search.

    python benchmarks/bench_cluster.py [--twin T K] [--rt] [--repeat N]

Every run's states, transitions and verdict are checked against one worker.  A benchmark, not a
test: nothing fails on a slow machine.  Prints one Markdown table.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))


def models(args, work: Path):
    out = []
    if args.twin:
        t, k = args.twin
        subprocess.run([sys.executable, str(SHARED / "bench" / "gen_swing.py"), str(t), str(k), str(work)],
                       check=True, capture_output=True)
        out.append((f"twin T{t} K{k}", work / f"swing_T{t}_K{k}.asm", {}))
    if args.rt:
        props = ROOT / "properties"
        out.append(("tests/rtpattern/RtNondetVS.asm", ROOT / "tests" / "rtpattern" / "RtNondetVS.asm",
                    {"import_path": [str(SHARED / "asmeta" / "asm_examples")], "default_properties": False,
                     "properties": [str(props / "rtpattern.prop"), str(props / "rtpattern_semaphore.prop"),
                                    str(props / "rtpattern_nondet.prop")], "deadlock": True}))
    return out


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--twin", nargs=2, type=int, metavar=("T", "K"))
    ap.add_argument("--rt", action="store_true", help="tests/rtpattern/RtNondetVS.asm as bench_native measures it")
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    import ray

    import asmcheck
    from asmcheck.explore.native import NativeExplorer
    from asmcheck.parallel import Recipe, explore_partitioned
    from asmcheck.semantics.resolve import import_path
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False,
             runtime_env={"env_vars": {"PYTHONPATH": str(ROOT)}})
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, path, opts in models(args, Path(tmp)):
            deadlock = opts.pop("deadlock", False)
            model = asmcheck.load(path, **opts)
            m, sp, stp = model.machine, list(model.state_props), list(model.step_props)
            recipe = Recipe(str(Path(path).resolve()), dict(model.options), model.prop_files, model.default_properties,
                            list(import_path()), deadlock, [p.name for p in sp], [p.name for p in stp])
            for _ in range(args.repeat):
                t0 = time.perf_counter()
                nx = NativeExplorer(m, state_props=sp, step_props=stp, deadlock=deadlock)
                r1 = nx.run()
                one = (r1.states, r1.transitions, r1.verdict)
                rows.append((name, "1 worker, native engine", time.perf_counter() - t0, r1.seconds, one, one))
                for backend, n in (("ray", 2), ("ray", 8), ("processes", 2)):
                    t0 = time.perf_counter()
                    ex, r = explore_partitioned(m, workers=n, backend=backend, state_props=sp, step_props=stp,
                                                deadlock=deadlock, recipe=recipe, expander="native")
                    wall = time.perf_counter() - t0
                    label = f"{n} Ray actors" if backend == "ray" else f"{n} worker processes"
                    rows.append((name, label + f" ({r.engine} expander)", wall, r.seconds,
                                 (r.states, r.transitions, r.verdict), one))
    ray.shutdown()
    print("| model | run | wall | search | states | transitions | verdict | as 1 worker |")
    print("|---|---|---:|---:|---:|---:|---|---|")
    for name, label, wall, search, got, one in rows:
        print(f"| {name} | {label} | {wall:.2f} s | {search:.2f} s | {got[0]:,} | {got[1]:,} | {got[2]} | "
              f"{'yes' if got == one else 'NO'} |")
    print(f"\nload average after the runs: {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
