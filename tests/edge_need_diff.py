"""The successor lists the CTL check reads (temporal/need.py), checked on the corpus: every spec with
CTL properties is explored with the reduced recording and with every list (ASMCHECK_EDGE_NEED=all),
on the native and the Python engine; the JSON reports must be identical.

    ASMCHECK_SHARED=../shared python tests/edge_need_diff.py [SPEC.asm ...]

prints, per spec, ``same LISTS`` (LISTS: none, some or all, what the native search kept; n/a: no
native search ran, the spec has an error or the Python engine ran it; ``+again``: searched again for
an ag(p) broken), ``differs`` or ``skip: REASON``; and the counts of none / some / all / n/a."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("ASMCHECK_SHARED", ROOT.parent / "shared"))

def specs_with_ctl() -> list[Path]:
    out = []
    for p in sorted((SHARED / "asmeta").rglob("*.asm")):
        try:
            text = p.read_text(errors="replace")
        except OSError:
            continue
        if "CTLSPEC" in text:
            out.append(p)
    return out


def run(spec: Path, engine: str, need: str, seconds: float) -> tuple[str, str, str]:
    """(json text or '', lists kept, searched again) of one run."""
    env = dict(os.environ, ASMCHECK_SHARED=str(SHARED))
    if need == "all":
        env["ASMCHECK_EDGE_NEED"] = "all"
    else:
        env.pop("ASMCHECK_EDGE_NEED", None)
    code = ("import sys, json\n"
            "from asmcheck.explore import native as N\n"
            "kept = []\n"
            "orig = N.NativeExplorer._qc_start\n"
            "def spy(self, ks):\n"
            "    orig(self, ks)\n"
            "    kept.append(self.lists_kept)\n"
            "N.NativeExplorer._qc_start = spy\n"
            "again = []\n"
            "orig2 = N.NativeExplorer.lists_again\n"
            "def spy2(self, *a):\n"
            "    again.append(1)\n"
            "    return orig2(self, *a)\n"
            "N.NativeExplorer.lists_again = spy2\n"
            "ran = []\n"
            "orig3 = N.NativeExplorer.run\n"
            "def spy3(self, *a):\n"
            "    ran.append(1)\n"
            "    return orig3(self, *a)\n"
            "N.NativeExplorer.run = spy3\n"
            "from asmcheck.cli import main\n"
            "try:\n"
            "    main(sys.argv[1:])\n"
            "except SystemExit:\n"
            "    pass\n"
            "sys.stdout.flush()\n"
            "print('\\n@@', kept[0] if kept else 'all' if ran else 'n/a', len(again), file=sys.stderr)\n")
    try:
        r = subprocess.run([sys.executable, "-c", code, "explore", str(spec), "--engine", engine, "--format", "json",
                            "--max-seconds", str(seconds)], cwd=ROOT, env=env, capture_output=True, text=True,
                           timeout=seconds * 3 + 60)
    except subprocess.TimeoutExpired:
        return "", "?", "0"
    tail = [ln for ln in r.stderr.splitlines() if ln.startswith("@@")]
    kept, again = (tail[-1].split()[1:3] if tail else ("?", "0"))
    return r.stdout, kept, again


def normal(text: str) -> str:
    """The report without its timings (and the compile's)."""
    try:
        d = json.loads(text)
    except ValueError:
        return text
    def strip(x):
        if isinstance(x, dict):
            return {k: strip(v) for k, v in x.items() if not any(w in k for w in ("second", "time", "memory", "rate",
                                                                                    "per_s", "cache", "compile", "bytes"))}
        if isinstance(x, list):
            return [strip(v) for v in x]
        return x
    return json.dumps(strip(d), sort_keys=True)


def compare(spec: Path, seconds: float = 20.0, engines=("native",)) -> tuple[str, str]:
    """(same / differs: ENGINE / skip: REASON, lists kept by the native search)."""
    kept = "all"
    for engine in engines:
        new, k, again = run(spec, engine, "", seconds)
        old, _, _ = run(spec, engine, "all", seconds)
        if engine == "native":
            kept = k + ("+again" if again != "0" else "")
        if not new or not old:
            return "skip: no report", kept
        a, b = normal(new), normal(old)
        if any(str(json.loads(x).get("incomplete", "")).startswith("time limit") for x in (new, old)):
            # (where a time limit stops the search depends on the machine's speed)
            return "skip: time limit", kept
        if a != b:
            return f"differs: {engine}", kept
        d = json.loads(new)
        if engine == "native" and d.get("engine") not in (None, "native"):
            engines = ()
    return "same", kept


def main(argv) -> int:
    specs = [Path(a) for a in argv] or specs_with_ctl()
    counts: dict = {}
    bad = 0
    for spec in specs:
        what, kept = compare(spec)
        counts[kept.split("+")[0]] = counts.get(kept.split("+")[0], 0) + 1
        bad += what.startswith("differs")
        print(f"{spec.relative_to(SHARED) if SHARED in spec.parents else spec}: {what} {kept}", flush=True)
    print("lists kept:", ", ".join(f"{k} {v}" for k, v in sorted(counts.items())), f"; {bad} differ")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
