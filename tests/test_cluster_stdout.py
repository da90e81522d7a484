"""With --cluster, stdout carries the report alone: what Ray writes while it starts and stops (on
Python's stdout or on file descriptor 1: a banner, a usage-stats notice) goes to stderr, and the
workers' output stays with Ray (``log_to_driver=False``), so ``--format json`` parses.  Ray's
start and stop are wrapped here to write such lines, as some of its versions and set-ups do.
Skipped without Ray."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.engines("native")

ROOT = Path(__file__).resolve().parent.parent

# the command line, in a process whose ray.init and ray.shutdown first write to stdout (both ways)
# and say on stderr whether the workers' output would come to the driver
CHATTY = """
import os, sys
import ray
real_init, real_shutdown = ray.init, ray.shutdown

def init(*args, **kw):
    print("(raylet) started: a line on sys.stdout")
    os.write(1, b"(raylet) started: a line on descriptor 1\\n")
    if kw.get("log_to_driver") is not False:
        os.write(2, b"log_to_driver is not False\\n")
    return real_init(*args, **kw)

def shutdown(*args, **kw):
    print("(raylet) stopping: a line on sys.stdout")
    os.write(1, b"(raylet) stopping: a line on descriptor 1\\n")
    return real_shutdown(*args, **kw)

ray.init, ray.shutdown = init, shutdown
from asmcheck.cli import main
sys.exit(main(sys.argv[1:]))
"""

CHATTER = ["(raylet) started: a line on sys.stdout", "(raylet) started: a line on descriptor 1",
           "(raylet) stopping: a line on sys.stdout", "(raylet) stopping: a line on descriptor 1"]


def chatty(tmp_path, *args):
    pytest.importorskip("ray", reason="Ray is not installed (pip install 'asmcheck[cluster]')")
    script = tmp_path / "chatty.py"
    script.write_text(CHATTY)
    return subprocess.run([sys.executable, str(script), *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=600, env={**os.environ, "PYTHONPATH": str(ROOT), "NO_COLOR": "1"})


@pytest.mark.slow
def test_explore_on_a_local_cluster_prints_only_its_json_report(tmp_path):
    r = chatty(tmp_path, "explore", "specs/sb_async_master.asm", "--cluster", "local", "--workers", "2",
               "--format", "json")
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert (doc["spec"], doc["verdict"], doc["states"], doc["transitions"], doc["workers"]) == \
        ("sb_async_master", "holds", 219, 512, 2)
    assert r.stderr.splitlines() == CHATTER


@pytest.mark.slow
def test_a_swarm_on_a_local_cluster_prints_only_its_json_report(tmp_path):
    r = chatty(tmp_path, "simulate", "specs/sb_async_master.asm", "--swarm", "4", "--depth", "10",
               "--swarm-workers", "2", "--cluster", "local", "--format", "json")
    assert r.returncode == 0, r.stderr
    doc = json.loads(r.stdout)
    assert doc["walks"] == 4
    assert r.stderr.splitlines() == CHATTER
