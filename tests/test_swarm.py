"""Swarm simulation (simulate --swarm) and bitstate search (explore --bitstate), engine: python."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from asmcheck.props.load import load_machine as _load
from asmcheck.explore.bfs import Explorer
from asmcheck.parallel.bitstate import BitstateExplorer
from asmcheck.parallel.swarm import swarm, swarm_traces
from asmcheck.props import spec_properties
from asmcheck.props.files import properties_for
from asmcheck.report.trace import build_trace

from conftest import need_bench

pytestmark = pytest.mark.engines("python")

ROOT = Path(__file__).resolve().parent.parent
BUGGY = sorted((ROOT / "specs" / "buggy").glob("*.asm"))

# per seeded bug, with the default budget (32 walks of 100 steps, seed 0): the property the spec
# is built to break, what the report says of it, and the states of the replayed trace
FOUND = {
    "producer_consumer_reader_takes_writer_array": ("inv_no_concurrent_rw", "shortest found: 5 steps, walk 27", 6),
    "sb_async_master_no_release": ("stp_lock_release_on_exit", "shortest found: 4 steps, walk 4", 5),
    "sb_async_slave_no_recheck": ("ltlSpec_slave_leaves", "shortest lasso found: 8 states, walk 11", 9),
    "sb_sync_master_no_watchdog": ("ltlSpec_master_leaves", "shortest lasso found: 9 states, walk 23", 10),
    "sb_sync_slave_clears_lock": ("stp_failed_slave_no_interference", "shortest found: 5 steps, walk 6", 6),
    "sb_sync_slave_moves_indexes": ("stp_slave_never_moves_indexes", "shortest found: 4 steps, walk 11", 5),
    "visual_servoing_swap_without_lock": ("stp_indexes_moved_under_lock", "shortest found: 14 steps, walk 0", 15),
}


def cli(*args):
    return subprocess.run([sys.executable, "-m", "asmcheck", *args], cwd=ROOT, capture_output=True, text=True,
                          env={**os.environ, "NO_COLOR": "1"})


def test_every_seeded_bug_has_an_entry():
    assert sorted(FOUND) == [p.stem for p in BUGGY]


@pytest.mark.slow
@pytest.mark.parametrize("path", BUGGY, ids=[p.stem for p in BUGGY])
def test_swarm_finds_each_seeded_bug_with_its_default_budget(path):
    expect = re.search(r"// asmcheck: expect violated (\w+)", path.read_text()).group(1)
    name, row, trace_states = FOUND[path.stem]
    assert name == expect
    r = cli("simulate", str(path.relative_to(ROOT)), "--swarm", "--format", "json")
    assert r.returncode == 1, r.stderr
    doc = json.loads(r.stdout)
    assert (doc["walks"], doc["depth"], doc["seed"], doc["verdict"]) == (32, 100, 0, "violated")
    rows = {p["property"]: p["verdict"] for p in doc["properties"]}
    assert rows[name] == f"violated ({row})"
    assert [k for k, v in rows.items() if v.startswith("violated")] == [name]
    (v,) = doc["violations"]
    assert len(v["trace"]) == trace_states


def load(path):
    spec, m = _load(str(path), {})
    sp, stp = spec_properties(m)
    es, est, temporal = properties_for(spec, m, str(path), None, use_default=True)
    return m, sp + es, stp + est, temporal


def test_swarm_is_the_same_on_one_or_two_workers_and_its_traces_replay():
    path = ROOT / "specs/buggy/sb_async_master_no_release.asm"
    m, sp, stp, temporal = load(path)
    a = swarm(m, sp, stp, 12, 30, seed=5, workers=1, temporal=temporal)
    b = swarm(m, sp, stp, 12, 30, seed=5, workers=2, temporal=temporal)
    assert (a.states_met, a.steps_taken, a.covered, a.found) == (b.states_met, b.steps_taken, b.covered, b.found)
    assert a.steps_taken == 12 * 30
    ((v, tr),) = swarm_traces(m, sp, stp, a)
    f = a.found["stp_lock_release_on_exit"]
    assert (v.prop.name, tr.kind, len(tr.steps) - 1) == ("stp_lock_release_on_exit", "step", f.length)
    # a different seed walks differently
    c = swarm(m, sp, stp, 12, 30, seed=6, workers=1, temporal=temporal)
    assert c.states_met != a.states_met


def test_swarm_text_report_names_coverage_and_what_it_cannot_check():
    r = cli("simulate", "specs/sb_async_master.asm", "--swarm", "4", "--depth", "20", "--seed", "3")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert re.fullmatch(r"sb_async_master\.asm: swarm of 4 walks of up to 20 steps \(seed 3\): [\d,]+ states met, "
                        r"80 steps taken, [\d.]+ s", lines[0])
    assert lines[1].startswith("  rule coverage: ") and " rules made an update" in lines[1]
    assert "  ltlSpec_master_leaves                    no violation found (on each walk's own graph)" in lines
    assert lines[-1] == "verdict: no violation found (random walks prove nothing: explore does)"


def test_swarm_usage_error():
    r = cli("simulate", "specs/sb_async_master.asm", "--swarm", "0")
    assert r.returncode == 2 and "--swarm and --depth expect positive numbers" in r.stderr


# ------------------------------------------------------------------ bitstate
def twin(tmp_path, bug=False):
    bench = need_bench()
    subprocess.run([sys.executable, str(bench / "gen_swing.py"), "7", "16"] + (["--bug"] if bug else [])
                   + [str(tmp_path)], capture_output=True, text=True, check=True)
    return tmp_path / ("swing_T7_K16_bug.asm" if bug else "swing_T7_K16.asm")


def test_bitstate_with_a_large_table_finds_every_state(tmp_path):
    path = twin(tmp_path)
    r = cli("explore", str(path), "--bitstate", "20")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("swing_T7_K16.asm: 5,571 states, 14,404 transitions, depth 218, ")
    assert lines[-2] == ("bitstate search: 2^20 bits (128 KB), 3 hashes, 1.58% set; probability that a reachable "
                         "state was missed <= 5.5e-03 (expected states missed directly 5.5e-03)")
    assert lines[-1] == "verdict: holds"


def test_bitstate_with_a_small_table_misses_states_and_says_so(tmp_path):
    path = twin(tmp_path)
    doc = json.loads(cli("explore", str(path), "--bitstate", "12", "--format", "json").stdout)
    assert (doc["states"], doc["transitions"]) == (1661, 4352)
    bs = doc["bitstate"]
    assert (bs["bits"], bs["hashes"], bs["table_bytes"], bs["p_missed"]) == (12, 3, 512, 1.0)
    assert round(bs["fill"], 4) == 0.7664 and bs["expected_missed"] > 200


def test_bitstate_violation_trace_is_replayed(tmp_path):
    path = twin(tmp_path, bug=True)
    m, sp, stp, _ = load(path)
    ex = BitstateExplorer(m, 20, state_props=sp, step_props=stp)
    r = ex.run()
    ref = Explorer(m, state_props=sp, step_props=stp)
    rr = ref.run()
    assert (r.verdict, r.states, r.transitions) == (rr.verdict, rr.states, rr.transitions) == ("violated", 205, 457)
    tr = build_trace(ex, r.violations[0])
    assert [s.state for s in tr.steps] == [s.state for s in build_trace(ref, rr.violations[0]).steps]
    assert len(tr.steps) == 14


def test_bitstate_refuses_what_it_cannot_check():
    r = cli("explore", "specs/sb_async_master.asm", "--bitstate", "20")
    assert r.returncode == 2
    assert "--bitstate keeps no state graph, so it cannot check LTL/CTL properties" in r.stderr
    r = cli("explore", "specs/sb_async_master.asm", "--bitstate", "20", "--workers", "2")
    assert r.returncode == 2 and "--bitstate runs on one worker" in r.stderr
