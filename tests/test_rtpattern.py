"""The authors' RTPatternLibrary (ASMETA's asm_examples/RTPatternLibrary, read in place)
against the swinging-buffer properties of properties/rtpattern*.prop -- the fast runs: Test_SB, the
semaphore tests (depth-bounded: their step counter makes them infinite), RtNondetPairs
(nondeterministic scheduling), coverage witnesses, the audit script, and the asmcheck bug the
property files work around. The long runs are in test_rtpattern_apps.py and test_rtpattern_vs.py.
Everything is skipped when ../shared/asmeta is absent."""
import subprocess
import sys

import pytest

from rtpattern.rtlib import (PROPS_COVERAGE, PROPS_NONDET, PROPS_SB, PROPS_SEM, ROOT, app, explore_json,
                             need_library, nondet_spec, trace_steps, verdicts, violated)

pytestmark = pytest.mark.engines("both")

SB_PROPS = {"inv_no_concurrent_rw", "inv_no_concurrent_rw_data", "stp_indexes_stable_during_access",
            "stp_exit_releases_semaphore", "stp_slave_never_moves_indexes", "stp_swap_publishes_latest",
            "inv_indexes_below_dimension", "inv_indexes_distinct", "inv_sem_mutex", "inv_sem_count_matches_holder",
            "inv_semacount_range", "inv_semaq_no_duplicates", "inv_semaq_waiting_async", "inv_semaq_only_if_locked"}
SEM_PROPS = {"inv_semacount_range", "inv_semaq_no_duplicates", "inv_semaq_waiting_async", "inv_semaq_only_if_locked",
             "inv_single_sem_mutex", "inv_single_sem_count"}


@pytest.mark.parametrize("passed, states, transitions", [("free", 103, 206), ("true", 102, 102)])
def test_test_sb_holds(capsys, passed, states, transitions):
    extra = ["--monitored", "passed=true"] if passed == "true" else []
    code, out = explore_json(capsys, app("Test_SB"), PROPS_SB, *extra)
    assert (code, out["verdict"], out["states"], out["transitions"]) == (0, "holds", states, transitions)
    assert verdicts(out) == {p: "holds" for p in SB_PROPS}


def test_test_sem_sync_grants_the_semaphore_twice(capsys):
    # indexCycle = 35 is a multiple of 5 and 7: the harness's par runs two r_sem_trywait in one step
    code, out = explore_json(capsys, app("Test_Sem_Sync"), PROPS_SEM, "--max-depth", "1000")
    assert code == 1
    assert (out["states"], out["transitions"], out["depth"]) == (2165, 4674, 1000)
    assert out["incomplete"] == "depth limit 1000 reached"
    assert set(verdicts(out)) == SEM_PROPS
    assert violated(out) == {"inv_single_sem_mutex", "inv_single_sem_count"}
    assert trace_steps(out) == {"inv_single_sem_mutex": 36, "inv_single_sem_count": 37}
    last = out["violations"][0]["trace"][-1]["state"]
    assert last["indexCycle"] == 36
    assert (last["task_currState(p1)"], last["task_currState(p2)"]) == ("EXECUTION", "EXECUTION")
    assert last["semacount(sem)"] == 0


def test_test_sem_async_within_depth_1000(capsys):
    code, out = explore_json(capsys, app("Test_Sem_Async"), PROPS_SEM, "--max-depth", "1000")
    assert (code, out["verdict"], out["states"], out["transitions"]) == (3, "incomplete", 5991, 11978)
    assert violated(out) == set()
    assert set(verdicts(out)) == SEM_PROPS


def test_nondet_pairs_holds_everywhere(capsys):
    """Synchronous MASTER writing/reading and asynchronous SLAVE reading/writing (used by no application),
    every interleaving of the two tasks."""
    path, imp = nondet_spec("RtNondetPairs")
    code, out = explore_json(capsys, path, PROPS_NONDET, "--deadlock", *imp)
    assert (code, out["verdict"], out["states"], out["transitions"]) == (0, "holds", 3699, 7310)
    assert verdicts(out) == {p: "holds" for p in SB_PROPS | {"stp_one_scheduler_per_step",
                                                              "stp_slave_never_moves_indexes_exact", "deadlock"}}


def test_nondet_spec_needs_the_library_folder_at_run_time(capsys):
    """The spec names RTPatternLibrary/... and finds it only through -I (or ASMCHECK_PATH)."""
    from asmcheck.cli import main

    path, imp = nondet_spec("RtNondetVS")
    assert "import RTPatternLibrary/CommonBehaviour/Scheduler\n" in open(path, encoding="utf-8").read()
    assert main(["parse", path]) == 2
    out = capsys.readouterr().out
    assert "RtNondetVS.asm:37:1: import not found: " in out and "RTPatternLibrary/CommonBehaviour/Scheduler.asm" in out
    assert main(["parse", path, *imp]) == 0
    assert capsys.readouterr().out == f"{path}: OK\n"


@pytest.mark.parametrize("spec, never", [("Test_SB", {"cov_rw_same_buffer", "cov_master_reads_old_data"}),
                                         ("RtNondetPairs", set())])
def test_coverage_witnesses(capsys, spec, never):
    """The properties do not hold vacuously: the situations they are about are reachable."""
    path, extra = nondet_spec(spec) if spec.startswith("RtNondet") else (app(spec), ["--monitored", "passed=true"])
    code, out = explore_json(capsys, path, PROPS_COVERAGE, *extra)
    v = verdicts(out)
    assert len(v) == 8
    assert {p for p, x in v.items() if x == "holds"} == never


def test_audit_script_partial_report(tmp_path):
    need_library()
    out = tmp_path / "audit.md"
    cp = subprocess.run([sys.executable, str(ROOT / "scripts" / "rtpattern_audit.py"), "--only", "Test_SB",
                         "--only", "Test_Sem_Sync", "--no-coverage", "--loop", "none", "--out", str(out)],
                        capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert cp.returncode == 0, cp.stderr
    text = out.read_text(encoding="utf-8")
    assert "| Test_SB | free | 103 | 206 | 101 |" in text
    assert "| Test_Sem_Sync | free | 2,165 | 4,674 | 1,000 |" in text
    assert "### `inv_single_sem_mutex` in Test_Sem_Sync (passed free)" in text
    assert "defect of the test spec Test_Sem_Sync" in text
    assert "NEW FINDING" not in text
