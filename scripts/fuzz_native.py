"""The native engine against the Python engine on random small specs (tests/fuzzgen.py).

    python scripts/fuzz_native.py [FIRST [COUNT]] [--deadlock] [--keep DIR]

For each seed: the spec is written, explored by the Python engine (the reference) and by the
native engine with ``--format json``, and the two reports are compared whole (but the timings and
the engine's name).  A spec the Python engine does not finish within the bound is skipped; one
the native engine refuses is counted with its reason.  Specs that differ are kept in DIR (default:
a temporary folder) and listed; the exit code is 1 when one differs.
"""
from __future__ import annotations

import argparse
import collections
import contextlib
import io
import json
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT))

import fuzzgen  # noqa: E402

from asmcheck.cli import main  # noqa: E402

IGNORED = ("seconds", "engine", "compile_seconds", "engine_note", "workers")
MAX_STATES = 3000


def run(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(args)
    return code, out.getvalue(), err.getvalue()


def compare(path: Path, more: list[str], native_more: list[str] = ()) -> tuple[str, str]:
    """('same' | 'skip' | 'refused' | 'differs' | 'bad', detail)."""
    base = ["explore", str(path), "--format", "json", "--max-states", str(MAX_STATES), *more]
    code, out, err = run(base + ["--engine", "python", "--max-seconds", "5"])
    if code not in (0, 1, 3):
        return "bad", (err.strip().splitlines() or ["?"])[0][:300]
    py = json.loads(out)
    # a search the time limit stopped (with or without a verdict) is not compared; one a state or
    # depth limit stopped is
    if "time limit" in py.get("incomplete", "") or (code == 3 and not py.get("incomplete")):
        return "skip", py.get("incomplete", "incomplete")[:120]
    code_n, out_n, err_n = run(base + ["--engine", "native", *native_more])
    if code_n == 2 and "the native explorer cannot run" in err_n:
        line = next(ln for ln in err_n.splitlines() if "the native explorer cannot run" in ln)
        return "refused", line.split(": ", 1)[-1][:160]
    if code_n != code:
        return "differs", f"exit {code_n} (python {code}): {(err_n.strip().splitlines() or [''])[0][:200]}"
    nat = json.loads(out_n)
    a = {k: v for k, v in py.items() if k not in IGNORED}
    b = {k: v for k, v in nat.items() if k not in IGNORED}
    if nat.get("engine") != "native":
        return "refused", f"ran on {nat.get('engine')}: {nat.get('engine_note', '')[:140]}"
    if a != b:
        keys = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
        return "differs", "keys " + ", ".join(keys) + ": " + "; ".join(
            f"{k}: python {json.dumps(a.get(k))[:200]} native {json.dumps(b.get(k))[:200]}" for k in keys[:2])
    return "same", ""


def main_(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("first", type=int, nargs="?", default=0)
    ap.add_argument("count", type=int, nargs="?", default=100)
    ap.add_argument("--deadlock", action="store_true", help="explore with --deadlock too")
    ap.add_argument("--step", action="store_true", help="with a property file of step properties (fuzzgen's)")
    ap.add_argument("--keep", help="the folder the specs are written to (kept)")
    ap.add_argument("--with", dest="extra", default="", metavar="'FLAGS'",
                    help="more explore options for both engines, e.g. --with '--symmetry' or '--max-depth 3'")
    ap.add_argument("--native-with", dest="native_extra", default="", metavar="'FLAGS'",
                    help="more explore options for the native engine alone, e.g. '--workers 2'")
    args = ap.parse_args(argv)
    folder = Path(args.keep or tempfile.mkdtemp(prefix="fuzz-native-"))
    folder.mkdir(parents=True, exist_ok=True)
    tally = collections.Counter()
    reasons = collections.Counter()
    bad = []
    for seed in range(args.first, args.first + args.count):
        path = folder / f"fz{seed}.asm"
        text, props = fuzzgen.spec_and_props(seed)
        path.write_text(text, encoding="utf-8")
        prop_path = folder / f"fz{seed}.prop"
        prop_path.write_text(props, encoding="utf-8")
        for more in ([], ["--deadlock"]) if args.deadlock else ([],):
            more = more + args.extra.split() + (["--properties", str(prop_path)] if args.step else [])
            outcome, detail = compare(path, more, args.native_extra.split())
            tally[outcome] += 1
            if outcome in ("refused", "bad", "skip"):
                reasons[f"{outcome}: {detail[:100]}"] += 1
            if outcome in ("differs", "bad"):
                bad.append((seed, more, outcome, detail))
                print(f"seed {seed} {' '.join(more)}: {outcome}: {detail}", flush=True)
    print(f"{dict(tally)} (specs in {folder})")
    for r, n in reasons.most_common(12):
        print(f"  {n:4d}  {r}")
    return 1 if any(o == "differs" for _, _, o, _ in bad) else 0


if __name__ == "__main__":
    sys.exit(main_())
