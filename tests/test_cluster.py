"""The partitioned search on a local Ray instance (explore --cluster): one actor per partition,
the same result as the sequential search (engine: python).  Skipped without Ray."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from asmcheck.parallel import Recipe, WorkerLost, explore_partitioned

from conftest import need_bench
from test_parallel import SPECS, load, sequential, summary

pytestmark = pytest.mark.engines("python")

ROOT = Path(__file__).resolve().parent.parent


def on_ray(path, workers, **kw):
    m, sp, stp = load(path)
    ex, r = explore_partitioned(m, workers=workers, backend="ray", recipe=Recipe(str(Path(path).resolve())),
                                state_props=sp, step_props=stp, **kw)
    assert r.backend == "ray"
    return summary(ex, r, kw.get("keep_graph", False))


SPECS_ON_RAY = ["sb_async_master.asm", "producer_consumer.asm", "buggy/sb_async_master_no_release.asm",
                "buggy/sb_sync_slave_moves_indexes.asm", "buggy/sb_async_slave_no_recheck.asm"]


@pytest.mark.slow
@pytest.mark.parametrize("name", SPECS_ON_RAY)
def test_two_actors_give_the_sequential_result(ray_local, name):
    assert on_ray(SPECS / name, 2, keep_graph=True) == sequential(SPECS / name, keep_graph=True)


@pytest.mark.slow
def test_eight_actors_on_two_cores_partition_correctly(ray_local):
    for name in ("buggy/producer_consumer_reader_takes_writer_array.asm", "buggy/sb_sync_slave_clears_lock.asm"):
        got = on_ray(SPECS / name, 8)
        assert got == sequential(SPECS / name)
    # the last run's numbers (sb_sync_slave_clears_lock on 8 actors)
    assert (got["states"], got["transitions"], got["violations"][0][:3]) == (387, 1038,
                                                                          ("stp_failed_slave_no_interference", 39, 15))


@pytest.mark.slow
def test_twins_on_two_actors(ray_local, tmp_path):
    bench = need_bench()
    for bug in (False, True):
        subprocess.run([sys.executable, str(bench / "gen_swing.py"), "7", "16"] + (["--bug"] if bug else [])
                       + [str(tmp_path)], capture_output=True, text=True, check=True)
        path = tmp_path / ("swing_T7_K16_bug.asm" if bug else "swing_T7_K16.asm")
        assert on_ray(path, 2) == sequential(path)


@pytest.mark.slow
def test_a_killed_actor_ends_the_run_with_a_clear_error(ray_local):
    m, sp, stp = load(SPECS / "sb_sync_master.asm")

    def kill_second(search, depth):
        if depth == 3:
            ray_local.kill(search.b.actors[1])

    with pytest.raises(WorkerLost) as e:
        explore_partitioned(m, workers=2, backend="ray", recipe=Recipe(str(SPECS / "sb_sync_master.asm")),
                            state_props=sp, step_props=stp, on_level=kill_second)
    assert "a partition actor failed during the search" in str(e.value)
    assert str(e.value).endswith("the search has no verdict")


def test_without_ray_cluster_says_how_to_get_it(tmp_path):
    fake = tmp_path / "ray"
    fake.mkdir()
    (fake / "__init__.py").write_text("raise ImportError('no module named ray')\n")
    r = subprocess.run([sys.executable, "-m", "asmcheck", "explore", "specs/sb_async_master.asm", "--cluster", "local"],
                       cwd=ROOT, capture_output=True, text=True,
                       env={**os.environ, "PYTHONPATH": os.pathsep.join([str(tmp_path), str(ROOT)])})
    assert r.returncode == 2
    assert r.stderr.strip() == ("asmcheck: error: --cluster needs Ray, an optional extra: pip install "
                                "'asmcheck[cluster]' (or pip install 'ray[default]>=2')")


@pytest.mark.slow
def test_swarm_walks_as_ray_tasks_equal_the_local_walks(ray_local):
    from asmcheck.parallel.swarm import swarm
    path = SPECS / "buggy/sb_async_master_no_release.asm"
    spec, m = load_spec(path)
    sp, stp, temporal = props(spec, m, path)
    local = swarm(m, sp, stp, 8, 25, seed=2, workers=1, temporal=temporal)
    remote = swarm(m, sp, stp, 8, 25, seed=2, workers=2, temporal=temporal, cluster="local",
                   recipe=Recipe(str(path.resolve())))
    assert (remote.states_met, remote.steps_taken, remote.covered, remote.found) == \
        (local.states_met, local.steps_taken, local.covered, local.found)
    assert remote.steps_taken == 8 * 25


def load_spec(path):
    from asmcheck.props.load import load_machine
    return load_machine(str(path), {})


def props(spec, m, path):
    from asmcheck.props import spec_properties
    from asmcheck.props.files import properties_for
    sp, stp = spec_properties(m)
    es, est, temporal = properties_for(spec, m, str(path), None, use_default=True)
    return sp + es, stp + est, temporal


@pytest.mark.slow
def test_a_local_cluster_run_keeps_stderr_clean():
    """`explore --cluster local` in a child process: the report on stdout, nothing on stderr (Ray's
    native code announced its token authentication there)."""
    pytest.importorskip("ray", reason="Ray is not installed (pip install 'asmcheck[cluster]')")
    r = subprocess.run([sys.executable, "-m", "asmcheck", "explore", "specs/sb_async_master.asm", "--cluster", "local",
                        "--workers", "2"], cwd=ROOT, capture_output=True, text=True, timeout=600,
                       env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode == 0, r.stderr
    assert r.stderr == ""
    assert "219 states, 512 transitions" in r.stdout
