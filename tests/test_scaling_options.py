"""Scaling options that do not go together are usage errors before the search: a worker's memory
share (--worker-memory) without workers to share it was ignored (a 5 MB share, less than any
process, and the search ran to the end in one process with the default bound), and a share that is
not a finite number of megabytes (nan, inf) was an internal error."""
from __future__ import annotations

from pathlib import Path

import pytest

import asmcheck
from asmcheck.cli import main

pytestmark = pytest.mark.engines("native")

ROOT = Path(__file__).resolve().parent.parent
SPEC = "specs/sb_async_master.asm"
ALONE = ("--worker-memory bounds each worker of --workers N or --cluster; a search in one process is bounded "
         "by --max-memory")
POSITIVE = "--worker-memory expects a positive number of megabytes"


@pytest.mark.parametrize("args, message", [
    (["--worker-memory", "5"], ALONE),
    (["--worker-memory", "5", "--workers", "1"], ALONE),
    (["--worker-memory", "5", "--engine", "python"], ALONE),
    (["--worker-memory", "5", "--bitstate", "20", "--no-default-properties"], ALONE),
    (["--worker-memory", "-5"], POSITIVE),
    (["--worker-memory", "nan", "--workers", "2"], POSITIVE),
    (["--worker-memory", "inf", "--workers", "2"], POSITIVE),
    (["--worker-memory", "0", "--workers", "2", "--engine", "python"], POSITIVE),
])
def test_a_worker_memory_share_that_cannot_apply_is_a_usage_error(capsys, monkeypatch, args, message):
    monkeypatch.chdir(ROOT)
    assert main(["explore", SPEC, *args]) == 2
    assert capsys.readouterr() == ("", f"asmcheck: error: {message}\n")


def test_the_api_refuses_it_alike(monkeypatch):
    monkeypatch.chdir(ROOT)
    with pytest.raises(asmcheck.UsageError) as e:
        asmcheck.load(SPEC).explore(worker_memory=5)
    assert str(e.value) == ALONE


@pytest.mark.parametrize("workers", ["2", "auto"])
def test_a_share_with_workers_still_runs(capsys, monkeypatch, workers):
    monkeypatch.chdir(ROOT)
    assert main(["explore", SPEC, "--worker-memory", "500", "--workers", workers]) == 0
    assert capsys.readouterr().out.startswith("sb_async_master.asm: 219 states, 512 transitions, depth 12, ")


LTL_OWN = """asm LtlOwn
import StandardLibrary
import LTLLibrary
signature:
	controlled x: Integer
definitions:
	invariant inv_x over x: x >= 0
	LTLSPEC ltlSpec_grows: g(x >= 0)
	main rule r_main = x := (x + 1) mod 5
default init s0:
	function x = 0
"""


def test_bitstate_names_the_ltl_properties_of_the_spec_itself(write_spec, capsys):
    # (the hint was to drop them with --no-default-properties or --properties FILE, which leave the
    # spec's own)
    path = write_spec(LTL_OWN)
    for extra in ([], ["--no-default-properties"]):
        assert main(["explore", path, "--bitstate", "20", "--engine", "python", *extra]) == 2
        assert capsys.readouterr() == ("", "asmcheck: error: --bitstate keeps no state graph, so it cannot check "
                                           "LTL/CTL properties, and the spec declares its own (ltlSpec_grows): "
                                           "drop --bitstate\n")
