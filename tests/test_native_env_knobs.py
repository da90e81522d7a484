"""The native engine's tuning variables of the environment (ASMCHECK_THREAD_MIN_CHUNK and
ASMCHECK_THREAD_MAX_CHUNK): a value that is not a count is a one-line usage error, never a
traceback.

Engines: native."""
from __future__ import annotations

import pytest

from asmcheck.cli import main
from asmcheck.explore.native_build import compiler

from conftest import ROOT

pytestmark = pytest.mark.engines("native")


@pytest.mark.parametrize("name", ["ASMCHECK_THREAD_MIN_CHUNK", "ASMCHECK_THREAD_MAX_CHUNK"])
@pytest.mark.parametrize("value", ["abc", "0", "-3"])
def test_a_bad_chunk_size_is_a_usage_error(monkeypatch, capsys, name, value):
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    monkeypatch.setenv(name, value)
    code = main(["explore", str(ROOT / "specs" / "sb_async_master.asm"), "--engine", "native", "--workers", "2"])
    err = capsys.readouterr().err
    assert code == 2
    assert err == f"asmcheck: error: {name}={value!r}: give a whole number of states, 1 or more\n"


def test_a_good_chunk_size_is_used(monkeypatch, capsys):
    if compiler() is None:
        pytest.skip("no C compiler: the native explorer cannot run here")
    monkeypatch.setenv("ASMCHECK_THREAD_MAX_CHUNK", "16")
    code = main(["explore", str(ROOT / "specs" / "sb_async_master.asm"), "--engine", "native", "--workers", "2"])
    assert code == 0
    assert capsys.readouterr().out.startswith("sb_async_master.asm: 219 states, 512 transitions")
