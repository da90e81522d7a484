"""The explore report names the engine that ran the search, and why the native one did not."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from asmcheck.cli import main
from asmcheck.explore import native_build

pytestmark = pytest.mark.engines("native")

SPEC = str(Path(__file__).resolve().parents[1] / "specs" / "sb_async_master.asm")
needs_cc = pytest.mark.skipif(native_build.compiler() is None, reason="no C compiler for the native engine")


def explore(capsys, *argv):
    code = main(["explore", SPEC, *argv])
    return code, capsys.readouterr().out


@needs_cc
def test_text_header_names_the_native_engine(capsys):
    code, out = explore(capsys)
    assert code == 0
    head = out.splitlines()[0]
    assert head.startswith("sb_async_master.asm: 219 states, 512 transitions, depth 12, ")
    assert head.endswith(" s, native engine")
    assert "native engine not used" not in out


def test_python_engine_on_request_says_nothing_of_native(capsys):
    code, out = explore(capsys, "--engine", "python")
    assert code == 0
    assert out.splitlines()[0].endswith(" s, python engine")
    assert "native engine not used" not in out


@needs_cc
def test_fallback_gives_its_reason_in_text_and_json(capsys, tmp_path):
    # the native engine writes --graph after a complete search only
    code, out = explore(capsys, "--max-states", "5", "--graph", str(tmp_path / "g.dot"))
    assert code == 3
    lines = out.splitlines()
    assert lines[0].endswith(" s, python engine")
    assert lines[1] == "  (native engine not used: --graph on a search that stopped before its end)"
    code, out = explore(capsys, "--max-states", "5", "--graph", str(tmp_path / "h.dot"), "--format", "json")
    doc = json.loads(out)
    assert doc["engine"] == "python"
    assert doc["engine_note"] == "native engine not used: --graph on a search that stopped before its end"
    assert doc["compile_seconds"] == 0.0


@needs_cc
def test_json_reports_compile_time_apart(capsys):
    explore(capsys, "--format", "json")           # compiled (or taken from the cache) once
    code, out = explore(capsys, "--format", "json")
    doc = json.loads(out)
    assert code == 0 and doc["engine"] == "native" and "engine_note" not in doc
    assert doc["compile_seconds"] == 0.0          # the second run takes the engine from the cache
    assert doc["states"] == 219 and doc["transitions"] == 512
