"""Helpers for tests/test_rtpattern*.py: where the authors' RTPatternLibrary is, the -I option
through which the specs of tests/rtpattern/ import it, and running
``asmcheck explore --format json`` in-process."""
from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE.parent))
from conftest import need_asmeta  # noqa: E402

PROPS_SB = [str(ROOT / "properties" / "rtpattern.prop"), str(ROOT / "properties" / "rtpattern_semaphore.prop")]
PROPS_SEM = [str(ROOT / "properties" / "rtpattern_semaphore.prop"), str(ROOT / "properties" / "rtpattern_semtest.prop")]
PROPS_NONDET = PROPS_SB + [str(ROOT / "properties" / "rtpattern_nondet.prop")]
PROPS_COVERAGE = [str(ROOT / "properties" / "rtpattern_coverage.prop")]


def need_library() -> Path:
    """The RTPatternLibrary folder of the shared ASMETA corpus (skip when it is absent)."""
    lib = need_asmeta() / "asm_examples" / "RTPatternLibrary"
    if not (lib / "CommonBehaviour" / "Scheduler.asm").exists():
        pytest.skip(f"the authors' RTPatternLibrary is not at {lib}")
    return lib


def app(name: str) -> str:
    lib = need_library()
    for sub in ("Application", "Test"):
        p = lib / sub / f"{name}.asm"
        if p.exists():
            return str(p)
    raise FileNotFoundError(name)


def nondet_spec(name: str) -> tuple[str, list[str]]:
    """tests/rtpattern/NAME.asm and the -I option that lets it import the library in place."""
    lib = need_library()
    return str(HERE / f"{name}.asm"), ["-I", str(lib.parent)]


def explore_json(capsys, path: str, props: list, *extra: str) -> tuple[int, dict]:
    from asmcheck.cli import main

    args = ["explore", path, "--no-default-properties", "--format", "json"]
    for p in props:
        args += ["--properties", p]
    args += list(extra)
    code = main(args)
    out = json.loads(capsys.readouterr().out)
    return code, out


def verdicts(out: dict) -> dict:
    return {p["property"]: p["verdict"] for p in out["properties"]}


def violated(out: dict) -> set:
    return {p for p, v in verdicts(out).items() if v == "violated"}


def trace_steps(out: dict) -> dict:
    """property -> number of steps of its shortest trace."""
    return {v["property"]: len(v["trace"]) - 1 for v in out["violations"]}
