"""The differential check of the LTL/CTL verdicts decided on a partial state space: for every
corpus spec with CTLSPEC / LTLSPEC declarations that explores to the end, each verdict decided
with a state or depth bound must equal the verdict of the whole state space.  Used by
tests/test_partial_verdicts.py; run it as a script for the figures:
``python tests/partial_diff.py [SPEC.asm ...]``."""
from __future__ import annotations

import re
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

_DECL = re.compile(r"^\s*(CTLSPEC|LTLSPEC)", re.M)


def corpus_specs(asmeta: Path) -> list:
    """The corpus specs (MANIFEST.tsv, accepted by the ASMETA parser) that declare LTL/CTL properties."""
    out = []
    for line in (asmeta / "MANIFEST.tsv").read_text(encoding="utf-8").splitlines()[1:]:
        parts = line.split("\t")
        if len(parts) < 2 or parts[1] != "accepts":
            continue
        p = asmeta / parts[0]
        try:
            if _DECL.search(p.read_text(encoding="utf-8", errors="replace")):
                out.append(p)
        except OSError:
            continue
    return sorted(out)


def bounds(states: int, depth: int, few: bool = False) -> list:
    """(max_states, max_depth) pairs below the full run's (``few``: six state bounds and three
    depth bounds, else ten and five)."""
    ms = (1, 3, 10, states // 10, states // 2, states - 1) if few else \
        (1, 2, 3, 5, 10, 30, states // 10, states // 3, states // 2, states - 1)
    md = (1, 2, depth // 2) if few else (1, 2, 3, depth // 2, depth - 1)
    return [(b, None) for b in sorted({b for b in ms if 1 <= b < states})] + \
        [(None, d) for d in sorted({d for d in md if 1 <= d < depth})]


def check_spec(path: Path, engines=("auto", "python"), python_states: int = 3000, seconds: float = 10.0,
               few: bool = False):
    """{"full": rows, "runs": n, "decided": n, "wrong": [..], "skipped": reason}."""
    from asmcheck import api
    from asmcheck.errors import AsmError
    out = {"spec": str(path), "runs": 0, "decided": 0, "wrong": [], "skipped": "", "by_engine": {}}
    try:
        model = api.load(str(path))
        full = model.explore(max_seconds=seconds)
    except (AsmError, api.UsageError) as e:
        out["skipped"] = f"does not load or explore: {str(e).splitlines()[0][:80]}"
        return out
    if full.result.stopped_early:
        out["skipped"] = f"does not finish: {full.result.reason[:60]}"
        return out
    want = {r["property"]: r["verdict"] for r in full.rows if r["kind"] in ("ltl", "ctl")}
    if not want:
        out["skipped"] = "no LTL/CTL row"
        return out
    out["full"] = want
    out["states"] = full.states
    for ms, md in bounds(full.states, full.depth, few):
        for engine in engines:
            if engine == "python" and (ms or full.states) > python_states:
                continue
            try:
                run = model.explore(engine=engine, max_states=ms, max_depth=md, max_seconds=seconds)
            except (AsmError, api.UsageError):
                continue
            out["runs"] += 1
            eng = out["by_engine"].setdefault(run.engine, [0, 0])
            eng[0] += 1
            for r in run.rows:
                if r["kind"] not in ("ltl", "ctl"):
                    continue
                if r.get("decided_on") is None:
                    if run.result.stopped_early and r["verdict"] not in ("incomplete", "cannot be checked"):
                        out["wrong"].append((r["property"], ms, md, run.engine, r["verdict"], "undecided but not incomplete"))
                    continue
                out["decided"] += 1
                eng[1] += 1
                if r["verdict"] != want.get(r["property"]):
                    out["wrong"].append((r["property"], ms, md, run.engine, r["verdict"], want.get(r["property"])))
                # a decided verdict's trace replays (the witness or counterexample)
                t = next(t for t in run.temporal if t.name == r["property"])
                if t.nodes:
                    t.trace()
    return out


def main(argv):
    import os
    asmeta = Path(os.environ.get("ASMCHECK_SHARED", HERE.parent.parent / "shared")) / "asmeta"
    specs = [Path(a) for a in argv] or corpus_specs(asmeta)
    t0 = time.perf_counter()
    tot = {"specs": 0, "runs": 0, "decided": 0, "wrong": 0, "props": 0}
    for p in specs:
        r = check_spec(p)
        name = str(p.relative_to(asmeta)) if p.is_relative_to(asmeta) else str(p)
        if r["skipped"]:
            print(f"{name}: skipped ({r['skipped']})", flush=True)
            continue
        tot["specs"] += 1
        tot["runs"] += r["runs"]
        tot["decided"] += r["decided"]
        tot["wrong"] += len(r["wrong"])
        tot["props"] += len(r["full"])
        print(f"{name}: {r['states']} states, {len(r['full'])} LTL/CTL, {r['runs']} bounded runs, "
              f"{r['decided']} decided, engines {r['by_engine']}, wrong {r['wrong']}", flush=True)
    print(f"total: {tot}, {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
