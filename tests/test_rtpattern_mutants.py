"""The RTPattern properties are not vacuous: three seeded defects of the library, each made in a
temporary copy (the shared folder stays untouched), are caught on RtNondetPairs, every
interleaving of a master and a slave in both directions."""
import shutil

import pytest

from rtpattern.rtlib import PROPS_NONDET, explore_json, need_library, nondet_spec, trace_steps, violated

pytestmark = [pytest.mark.slow, pytest.mark.engines("both")]

MUTANTS = {
    # the lock is never released: r_SwingingBuffer_releaseLock does not post the semaphore
    "no_post": ("Pattern/SwingingBuffer.asm", "\t\tr_sem_post [sem($sb) , $p ]", "\t\tskip"),
    # a SLAVE also swaps the arrays after taking the lock
    "slave_swaps": ("CommonBehaviour/Scheduler.asm",
                    "\t\t\t\t\tif ( syncPriority($phase) = SLAVE ) then\n"
                    "\t\t\t\t\t\tr_SwingingBuffer_getLock [ sharedMemory( $phase ) , scheduler_mainThread( $c ) ]\n"
                    "\t\t\t\t\tendif",
                    "\t\t\t\t\tif ( syncPriority($phase) = SLAVE ) then\n"
                    "\t\t\t\t\t\tseq\n"
                    "\t\t\t\t\t\t\tr_SwingingBuffer_getLock [ sharedMemory( $phase ) , scheduler_mainThread( $c ) ]\n"
                    "\t\t\t\t\t\t\tr_SwingingBuffer_updateIndexes [ sharedMemory( $phase ) , scheduler_mainThread( $c ) ]\n"
                    "\t\t\t\t\t\tendseq\n"
                    "\t\t\t\t\tendif"),
    # the swap moves the read index only: reader and writer end up on one array
    "half_swap": ("Pattern/SwingingBuffer.asm",
                  "\t\t\t\t\t\tindexWrite($sb) := mod(indexWrite($sb) + 1n , dimension($sb) )\n", ""),
}


def mutant_library(tmp_path, name):
    """A copy of the library (and of the StandardLibrary folder it imports) with one defect."""
    lib = need_library()
    root = tmp_path / name
    shutil.copytree(lib / "CommonBehaviour", root / "RTPatternLibrary" / "CommonBehaviour")
    shutil.copytree(lib / "Pattern", root / "RTPatternLibrary" / "Pattern")
    if (lib.parent / "STDL").is_dir():
        shutil.copytree(lib.parent / "STDL", root / "STDL")
    rel, old, new = MUTANTS[name]
    f = root / "RTPatternLibrary" / rel
    text = f.read_text(encoding="latin-1")
    assert text.count(old) == 1, f"the library changed: cannot seed {name}"
    f.write_text(text.replace(old, new), encoding="latin-1")
    return root


@pytest.mark.parametrize("name, states, steps", [
    ("no_post", 192, {"stp_exit_releases_semaphore": 4, "inv_sem_count_matches_holder": 4}),
    ("slave_swaps", 21782, {"stp_slave_never_moves_indexes": 2, "stp_slave_never_moves_indexes_exact": 2,
                            "stp_indexes_stable_during_access": 3, "inv_no_concurrent_rw_data": 4,
                            "stp_exit_releases_semaphore": 5}),
    ("half_swap", 2134, {"stp_slave_never_moves_indexes": 3, "inv_indexes_distinct": 3, "inv_no_concurrent_rw": 12,
                         "inv_no_concurrent_rw_data": 12}),
])
def test_seeded_library_defect_is_caught(tmp_path, capsys, name, states, steps):
    path, _ = nondet_spec("RtNondetPairs")
    root = mutant_library(tmp_path, name)
    code, out = explore_json(capsys, path, PROPS_NONDET, "--deadlock", "-I", str(root))
    assert (code, out["verdict"], out["states"]) == (1, "violated", states)
    assert violated(out) == set(steps)
    assert trace_steps(out) == steps
